#include "robot/perfect_robot.h"

#include <algorithm>
#include <cmath>

namespace vts::robot {

Pose3 interpolate(const Pose3& a, const Pose3& b, double f) {
  const Eigen::Quaterniond qa(a.linear()), qb(b.linear());
  Pose3 p = Pose3::Identity();
  p.linear() = qa.slerp(f, qb).toRotationMatrix();
  p.translation() = (1.0 - f) * a.translation() + f * b.translation();
  return p;
}

Pose3 PerfectRobot::tcp() const {
  Pose3 p = commanded_;
  p.translation() += correction_;
  return p;
}

Pose3 PerfectRobot::at(const Segment& s, double t) const {
  if (t >= s.t1) return s.to;
  if (t <= s.t0) return s.from;
  return interpolate(s.from, s.to, (t - s.t0) / (s.t1 - s.t0));
}

void PerfectRobot::servo(const Pose3& target) {
  segments_.clear();
  servo_ = true;
  servo_target_ = target;
}

bool PerfectRobot::move(const Pose3& target, double speed_mm_s, bool queue) {
  servo_ = false;  // a pending servo target is dropped by any move
  if (!queue) segments_.clear();
  if (static_cast<int>(segments_.size()) >= kMaxQueued) return false;
  Segment s;
  s.from = segments_.empty() ? commanded_ : segments_.back().to;
  s.to = target;
  s.t0 = segments_.empty() ? time_s_ : segments_.back().t1;
  const double dist = (s.to.translation() - s.from.translation()).norm();
  const double turn = Eigen::AngleAxisd(s.from.linear().transpose() * s.to.linear()).angle();
  const double duration = std::max(dist / speed_mm_s, turn / (kMaxTurnDegS * M_PI / 180.0));
  s.t1 = s.t0 + duration;
  segments_.push_back(s);
  return true;
}

void PerfectRobot::stop() {
  segments_.clear();
  servo_ = false;
}

std::vector<double> PerfectRobot::breaks_before(double t) const {
  std::vector<double> out;
  for (const Segment& s : segments_)
    if (s.t1 > time_s_ && s.t1 < t) out.push_back(s.t1);
  return out;
}

bool PerfectRobot::advance(double t) {
  if (t <= time_s_) return false;
  if (servo_) {
    commanded_ = servo_target_;
    servo_ = false;
    time_s_ = t;
    return false;
  }
  const bool had = !segments_.empty();
  while (!segments_.empty() && segments_.front().t1 <= t) {
    commanded_ = segments_.front().to;
    segments_.pop_front();
  }
  if (!segments_.empty()) commanded_ = at(segments_.front(), t);
  time_s_ = t;
  return had && segments_.empty();
}

}  // namespace vts::robot
