#pragma once
// The robots behind the robot channel (docs/PROTOCOL.md): the interface,
// and the perfect robot, whose TCP is where it is commanded, at once. Its
// motion is a list of segments in time; within one the position moves in a
// straight line at constant speed and the orientation by slerp, so the
// sensor's linear interpolation between two segment ends
// (tracker::SensorUnit::advance) is exact. It is also the commanded path of
// the arm (robot/arm_robot.h).
#include <deque>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "robot/arm.h"

namespace vts::robot {

// The pose a fraction f of the way from a to b: position linear, rotation by
// slerp (the twin of tracker::interpolate; robot/ depends on none of our libraries).
Pose3 interpolate(const Pose3& a, const Pose3& b, double f);

// What a controller offers a master: the TCP, motion commands, a path
// correction, and time advanced from outside (the cell's clock).
class Robot {
 public:
  virtual ~Robot() = default;
  virtual Pose3 tcp() const = 0;  // where the TCP is now (world)
  // Where the controller believes it is: what it reports (to the master, to
  // a sensor stamping its data). The same as tcp() for a perfect robot.
  virtual Pose3 reported_tcp() const { return tcp(); }
  virtual double time_s() const = 0;
  virtual bool moving() const = 0;
  virtual int queued() const = 0;
  virtual const Eigen::Vector3d& correction_mm() const = 0;
  virtual void servo(const Pose3& target) = 0;
  virtual bool move(const Pose3& target, double speed_mm_s, bool queue) = 0;
  virtual void stop() = 0;
  virtual void set_correction(const Eigen::Vector3d& offset_mm) = 0;
  // The times in (time_s(), t) at which the TCP's motion changes segment;
  // a caller advancing the sensor steps through them.
  virtual std::vector<double> breaks_before(double t) const = 0;
  // Moves the clock to t; true if the last queued move ended in (time_s(), t].
  virtual bool advance(double t) = 0;
  // Not empty once the robot has stopped on a fault (out of reach, a joint
  // limit, a singularity): why. It then ignores motion commands.
  virtual std::string fault() const { return {}; }
  // The joint angles (radians), for an arm.
  virtual std::optional<Joints> joints() const { return std::nullopt; }
};

class PerfectRobot final : public Robot {
 public:
  static constexpr int kMaxQueued = 64;
  static constexpr double kMaxTurnDegS = 90.0;  // orientation-only moves turn at this rate

  explicit PerfectRobot(const Pose3& tcp = Pose3::Identity()) : commanded_(tcp) {}

  // The TCP as it is at the current time (commanded path plus correction).
  Pose3 tcp() const override;
  // The commanded path's pose at the current time (no correction).
  const Pose3& commanded() const { return commanded_; }
  // A servo target not yet reached, and that target.
  bool servo_pending() const { return servo_; }
  const Pose3& servo_target() const { return servo_target_; }
  double time_s() const override { return time_s_; }
  bool moving() const override { return !segments_.empty() || servo_; }
  int queued() const override { return static_cast<int>(segments_.size()); }
  const Eigen::Vector3d& correction_mm() const override { return correction_; }

  // Position streaming: the TCP goes to `target` in a straight line over
  // the next advance (a controller's sensor interface takes one pose per
  // cycle). Cancels queued moves.
  void servo(const Pose3& target) override;
  // A linear move at speed_mm_s (orientation turned over the same time, at
  // most kMaxTurnDegS) from where the last queued move ends (queue), or from
  // the commanded pose now, replacing every move not yet done. Either way a
  // servo target not yet reached is dropped. False when kMaxQueued moves are
  // queued already.
  bool move(const Pose3& target, double speed_mm_s, bool queue) override;
  void stop() override;
  void set_correction(const Eigen::Vector3d& offset_mm) override { correction_ = offset_mm; }

  // The times in (time_s(), t) at which the motion changes segment: the
  // sensor is advanced to each in turn so that its interpolation follows the path.
  std::vector<double> breaks_before(double t) const override;
  // Moves the clock to t (>= time_s()). Returns true if the last queued
  // move ended in (time_s(), t] (a `move-done` event).
  bool advance(double t) override;

 private:
  struct Segment {
    Pose3 from, to;
    double t0 = 0.0, t1 = 0.0;
  };
  Pose3 at(const Segment& s, double t) const;

  double time_s_ = 0.0;
  Pose3 commanded_;               // the commanded path's pose at time_s_
  std::deque<Segment> segments_;  // queued moves, in time order, from time_s_ on
  bool servo_ = false;            // a servo target pending for the next advance
  Pose3 servo_target_;
  Eigen::Vector3d correction_ = Eigen::Vector3d::Zero();
};

}  // namespace vts::robot
