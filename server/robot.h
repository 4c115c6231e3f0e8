#pragma once
// The served cell's robot (docs/PROTOCOL.md, "Robot channel"): for now a
// perfect one, whose TCP is where it is commanded (issue 19 puts servo
// dynamics, latency and absolute accuracy behind the same commands).
// Motion is a list of segments in time; within one the position moves in a
// straight line at constant speed and the orientation by slerp, so the
// sensor's linear interpolation between two segment ends
// (tracker::SensorUnit::advance) is exact.
#include <deque>
#include <vector>

#include <Eigen/Geometry>

namespace vts::server {

using Pose3 = Eigen::Isometry3d;

class PerfectRobot {
 public:
  static constexpr int kMaxQueued = 64;
  static constexpr double kMaxTurnDegS = 90.0;  // orientation-only moves turn at this rate

  explicit PerfectRobot(const Pose3& tcp = Pose3::Identity()) : commanded_(tcp) {}

  // The TCP as it is at the current time (commanded path plus correction).
  Pose3 tcp() const;
  double time_s() const { return time_s_; }
  bool moving() const { return !segments_.empty() || servo_; }
  int queued() const { return static_cast<int>(segments_.size()); }
  const Eigen::Vector3d& correction_mm() const { return correction_; }

  // Position streaming: the TCP goes to `target` in a straight line over
  // the next advance (a controller's sensor interface takes one pose per
  // cycle). Cancels queued moves.
  void servo(const Pose3& target);
  // A linear move at speed_mm_s (orientation turned over the same time, at
  // most kMaxTurnDegS) from where the last queued move ends (queue), or from
  // the commanded pose now, replacing every move not yet done. Either way a
  // servo target not yet reached is dropped. False when kMaxQueued moves are
  // queued already.
  bool move(const Pose3& target, double speed_mm_s, bool queue);
  void stop();
  void set_correction(const Eigen::Vector3d& offset_mm) { correction_ = offset_mm; }

  // The times in (time_s(), t) at which the motion changes segment: the
  // sensor is advanced to each in turn so that its interpolation follows the path.
  std::vector<double> breaks_before(double t) const;
  // Moves the clock to t (>= time_s()). Returns true if the last queued
  // move ended in (time_s(), t] (a `move-done` event).
  bool advance(double t);

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

}  // namespace vts::server
