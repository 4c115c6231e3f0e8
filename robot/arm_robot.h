#pragma once
// The arm behind the robot channel (issue 19, docs/ROBOT.md): the commanded
// TCP path (a PerfectRobot: moves, servo targets) sampled at the controller
// cycle, the path correction applied after a latency, each cycle's pose
// through the inverse kinematics of the nominal model (keeping the start's
// configuration), the joint servo, and the TCP where the arm as built
// (robot/arm.h `perturbed`) puts it. An unreachable pose, a joint limit or a
// singularity stops the arm where it is, with the reason (fault()).
#include <cstdint>
#include <deque>
#include <string>

#include "robot/arm.h"
#include "robot/perfect_robot.h"
#include "robot/servo.h"

namespace vts::robot {

struct ArmSetup {
  ArmModel nominal;                  // what the controller computes with
  std::uint64_t accuracy_seed = 0;   // the arm as built: perturbed(nominal, seed); 0: exactly nominal
  Pose3 world_from_base = Pose3::Identity();
  Pose3 flange_from_tool = Pose3::Identity();  // the torch: TCP on the flange
  ServoParams servo;
  int correction_delay_cycles = 3;   // a path correction takes effect this many cycles later
  Limits limits;
};

class ArmRobot final : public Robot {
 public:
  // The arm with its TCP at tcp_start, in the configuration and turn of
  // axes 4 and 6 that leaves every axis the most room (its axis nearest a
  // limit, as a share of its range, farthest from it); throws
  // std::invalid_argument with the reason if none reaches it. Servo
  // commands then follow on continuously: an axis whose next angle lies
  // outside its range faults (JointLimit), it never turns a full turn back.
  ArmRobot(const ArmSetup& setup, const Pose3& tcp_start);
  ArmRobot(const ArmRobot&) = delete;  // the servo refers to built_
  ArmRobot& operator=(const ArmRobot&) = delete;

  Pose3 tcp() const override;
  double time_s() const override { return time_s_; }
  bool moving() const override { return path_.moving(); }
  int queued() const override { return path_.queued(); }
  const Eigen::Vector3d& correction_mm() const override { return path_.correction_mm(); }
  void servo(const Pose3& target) override;
  bool move(const Pose3& target, double speed_mm_s, bool queue) override;
  void stop() override { path_.stop(); }
  void set_correction(const Eigen::Vector3d& offset_mm) override { path_.set_correction(offset_mm); }
  std::vector<double> breaks_before(double t) const override;
  bool advance(double t) override;
  std::string fault() const override { return fault_; }
  std::optional<Joints> joints() const override { return servo_.q(); }

  const Config& config() const { return config_; }
  const ArmSetup& setup() const { return s_; }
  const ArmModel& as_built() const { return built_; }
  // Where the controller believes the TCP is (nominal model, the servo's joints).
  Pose3 reported_tcp() const override;

 private:
  ArmSetup s_;
  ArmModel built_;
  Config config_;
  PerfectRobot path_;  // the commanded path, without the correction
  JointServo servo_;
  // A servo target is reached in a straight line over the interval between
  // the last two servo() calls (a controller's external-guidance
  // interpolator: a target streamed every 50 ms is a ramp of 50 ms, not a
  // step), however the caller slices its advance() calls.
  Pose3 ramp_from_ = Pose3::Identity();  // the commanded pose when the target came
  Pose3 ramp_pose_ = Pose3::Identity();  // the commanded pose at the last cycle
  double ramp_t0_ = 0.0, ramp_span_ = 0.0;
  double last_servo_call_ = -1.0;
  std::deque<Eigen::Vector3d> corrections_;  // the delay line, one per cycle
  Joints q_cmd_;
  double time_s_ = 0.0;
  std::int64_t cycle_ = 0;  // cycles run
  bool done_pending_ = false;
  std::string fault_;
};

}  // namespace vts::robot
