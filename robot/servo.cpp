#include "robot/servo.h"

#include <algorithm>
#include <cmath>

namespace vts::robot {

JointServo::JointServo(const ArmModel& model, const ServoParams& params, const Joints& q0)
    : m_(model), p_(params), q_(q0), v_(Joints::Zero()), u_(q0) {}

void JointServo::step(const Joints& u) {
  const double dt = p_.cycle_s, w = p_.omega_rad_s;
  const double k = std::exp(-w * dt);
  // The command's speed over this cycle (a step on the first call: none).
  const Joints ud = first_ ? Joints::Zero() : Joints((u - u_) / dt);
  const Joints u0 = first_ ? u : u_;
  first_ = false;
  clipped_ = 0;
  for (int i = 0; i < 6; ++i) {
    const Axis& a = m_.axes[static_cast<std::size_t>(i)];
    // Exact over the cycle for the error against the ramp from u0 at speed ud.
    const double e0 = q_[i] - u0[i], de0 = v_[i] - ud[i];
    const double c = de0 + w * e0;
    const double e1 = (e0 + c * dt) * k;
    const double de1 = (de0 - w * c * dt) * k;
    double v1 = ud[i] + de1;
    double q1 = u[i] + e1;
    const double acc = (v1 - v_[i]) / dt;
    if (std::abs(acc) > a.max_acc_rad_s2 || std::abs(v1) > a.max_vel_rad_s) {
      v1 = std::clamp(v_[i] + std::clamp(acc, -a.max_acc_rad_s2, a.max_acc_rad_s2) * dt, -a.max_vel_rad_s,
                      a.max_vel_rad_s);
      q1 = q_[i] + 0.5 * (v_[i] + v1) * dt;
      clipped_ |= 1u << i;
    }
    q_[i] = q1;
    v_[i] = v1;
  }
  u_ = u;
}

}  // namespace vts::robot
