#include "robot/arm_robot.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>

namespace vts::robot {
namespace {

Pose3 flange_target(const ArmSetup& s, const Pose3& world_from_tool) {
  return s.world_from_base.inverse() * world_from_tool * s.flange_from_tool.inverse();
}

// The joints reaching the pose cleanly with the most room to move: of every
// configuration, and of the turns of axes 4 and 6 (each may take an angle
// or that angle +- a full turn when its range allows), the one whose axis
// nearest a limit, as a share of its range, is farthest from it (the first
// such in inverse_all's order). A programmer starts a weld that turns the torch (a saddle) with
// the wrist in the middle of its range, not at the end it would wind into.
Joints start_joints(const ArmSetup& s, const Pose3& tcp, Config& config) {
  const Pose3 f = flange_target(s, tcp);
  std::string why = "no configuration reaches it";
  std::optional<Joints> best;
  double best_room = -1.0;
  for (const Solution& sol : inverse_all(s.nominal, f)) {
    for (int turn4 = -1; turn4 <= 1; ++turn4)
      for (int turn6 = -1; turn6 <= 1; ++turn6) {
        Joints near = sol.q;
        near[3] += 2.0 * M_PI * turn4;
        near[5] += 2.0 * M_PI * turn6;
        const IkResult r = inverse(s.nominal, f, sol.config, near, s.limits);
        if (r.status != IkStatus::Ok) {
          why = r.message;
          continue;
        }
        double room = std::numeric_limits<double>::infinity();
        for (int i = 0; i < 6; ++i) {
          const Axis& a = s.nominal.axes[static_cast<std::size_t>(i)];
          const double v = limited_value(s.nominal, r.q, i);
          room = std::min(room, std::min(v - a.min_rad, a.max_rad - v) / (a.max_rad - a.min_rad));
        }
        if (room > best_room + 1e-6) {
          best_room = room;
          best = r.q;
          config = sol.config;
        }
      }
  }
  if (best) return *best;
  const Eigen::Vector3d p = tcp.translation();
  throw std::invalid_argument("robot " + s.nominal.name + ": the start pose (" + std::to_string(p.x()) + ", " +
                              std::to_string(p.y()) + ", " + std::to_string(p.z()) + ") mm cannot be reached: " + why);
}

}  // namespace

ArmRobot::ArmRobot(const ArmSetup& setup, const Pose3& tcp_start)
    : s_(setup),
      built_(setup.accuracy_seed ? perturbed(setup.nominal, setup.accuracy_seed) : setup.nominal),
      path_(tcp_start),
      servo_(built_, setup.servo, start_joints(setup, tcp_start, config_)) {
  q_cmd_ = servo_.q();
  ramp_pose_ = tcp_start;
}

Pose3 ArmRobot::tcp() const { return s_.world_from_base * forward(built_, servo_.q()) * s_.flange_from_tool; }

Pose3 ArmRobot::reported_tcp() const {
  return s_.world_from_base * forward(s_.nominal, servo_.q()) * s_.flange_from_tool;
}

void ArmRobot::servo(const Pose3& target) {
  if (!fault_.empty()) return;
  const double since = last_servo_call_ >= 0.0 ? time_s_ - last_servo_call_ : 0.0;
  ramp_span_ = since > 0.0 ? since : s_.servo.cycle_s;
  last_servo_call_ = time_s_;
  ramp_t0_ = time_s_;
  ramp_from_ = path_.servo_pending() ? ramp_pose_ : path_.commanded();
  path_.servo(target);
}

bool ArmRobot::move(const Pose3& target, double speed_mm_s, bool queue) {
  return fault_.empty() ? path_.move(target, speed_mm_s, queue) : true;
}

std::vector<double> ArmRobot::breaks_before(double t) const {
  std::vector<double> out;
  const double dt = s_.servo.cycle_s;
  for (std::int64_t k = cycle_ + 1; static_cast<double>(k) * dt < t; ++k) out.push_back(static_cast<double>(k) * dt);
  return out;
}

bool ArmRobot::advance(double t) {
  if (t <= time_s_) return false;
  const double dt = s_.servo.cycle_s;
  bool done = false;
  while (static_cast<double>(cycle_ + 1) * dt <= t + 1e-12) {
    ++cycle_;
    const double tc = static_cast<double>(cycle_) * dt;
    Pose3 cmd;
    if (path_.servo_pending()) {
      // Each cycle samples the straight line to the target (servo()).
      const double f = std::clamp((tc - ramp_t0_) / ramp_span_, 0.0, 1.0);
      cmd = interpolate(ramp_from_, path_.servo_target(), f);
      if (f >= 1.0 - 1e-12) path_.advance(tc);  // reached: the path's pose
    } else {
      done = path_.advance(tc) || done;
      cmd = path_.commanded();
    }
    ramp_pose_ = cmd;
    corrections_.push_back(path_.correction_mm());
    while (static_cast<int>(corrections_.size()) > s_.correction_delay_cycles + 1) corrections_.pop_front();
    cmd.translation() += corrections_.front();
    if (fault_.empty()) {
      const IkResult r = inverse(s_.nominal, flange_target(s_, cmd), config_, q_cmd_, s_.limits, true);
      if (r.status == IkStatus::Ok) {
        q_cmd_ = r.q;
      } else {
        fault_ = std::string(to_string(r.status)) + " at t = " + std::to_string(tc) + " s: " + r.message;
        path_.stop();
      }
    }
    servo_.step(q_cmd_);  // after a fault: hold the last command, the arm settles there
  }
  time_s_ = t;
  return done;
}

}  // namespace vts::robot
