#pragma once
// The controller's joint servo (issue 19, docs/ROBOT.md): each axis follows
// its commanded angle u(t) as a critically damped second-order system with
// velocity feed-forward,
//     q'' = omega^2 (u - q) + 2 omega (u' - q'),
// so the error e = q - u obeys e'' + 2 omega e' + omega^2 e = 0 while u moves
// at constant speed, and a step of size h is followed as
//     q(t) = u - h (1 + omega t) exp(-omega t).
// Sampled at the controller cycle: within a cycle the command is a ramp (the
// next command less this one over the cycle), and the update is the exact
// solution over the cycle unless the axis's acceleration or velocity limit
// would be passed; then the acceleration is clipped and the velocity held at
// its limit (trapezoidal integration).
#include "robot/arm.h"

namespace vts::robot {

struct ServoParams {
  double cycle_s = 0.004;     // controller cycle (4 ms)
  double omega_rad_s = 60.0;  // natural frequency of each axis (about 9.5 Hz)
};

class JointServo {
 public:
  JointServo(const ArmModel& model, const ServoParams& params, const Joints& q0);
  // One cycle: the command moves from the previous one to `u` over the
  // cycle (the first call: a step to `u`).
  void step(const Joints& u);
  const Joints& q() const { return q_; }
  const Joints& velocity() const { return v_; }
  const Joints& command() const { return u_; }
  // Axes whose limit clipped the last cycle (bit i: axis i + 1).
  unsigned clipped() const { return clipped_; }
  const ServoParams& params() const { return p_; }

 private:
  const ArmModel& m_;
  ServoParams p_;
  Joints q_, v_, u_;
  bool first_ = true;
  unsigned clipped_ = 0;
};

}  // namespace vts::robot
