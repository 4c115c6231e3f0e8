#include "tracker/sensor_interface.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace vts::tracker {
namespace {

// A break point further than this from every measured point is extrapolated
// (the joint is not fully in the laser plane yet, e.g. at a seam's start).
constexpr double kMaxSupportMm = 1.0;

}  // namespace

Pose3 interpolate(const Pose3& a, const Pose3& b, double t) {
  const Eigen::Quaterniond qa(a.linear()), qb(b.linear());
  Pose3 p = Pose3::Identity();
  p.linear() = qa.slerp(t, qb).toRotationMatrix();
  p.translation() = (1.0 - t) * a.translation() + t * b.translation();
  return p;
}

double support_distance_mm(const ProfileView& p, const Vec2& point) {
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < p.y_mm.size(); ++i) {
    if (!p.valid.empty() && !p.valid[i]) continue;
    const double dy = p.y_mm[i] - point.x(), dz = p.z_mm[i] - point.y();
    best = std::min(best, dy * dy + dz * dz);
  }
  return std::sqrt(best);
}

SensorUnit::SensorUnit(std::unique_ptr<ProfileStream> stream, const TrackerParams& tracker_params,
                       const SequenceParams& sequence_params, const FollowParams& follow_params)
    : stream_(std::move(stream)), follower_(tracker_params, follow_params), sequence_(sequence_params) {}

bool SensorUnit::laser_on() {
  error_.clear();
  follower_.reset();
  laser_ = true;
  latest_.reset();
  have_tool_ = false;
  sequence_.laser_on();
  return true;
}

void SensorUnit::laser_off() {
  laser_ = false;
  sequence_.laser_off();
}

void SensorUnit::search_start() {
  latest_.reset();
  follower_.reset();
  sequence_.search_start();
}
void SensorUnit::start_tracking() { sequence_.start_tracking(); }
void SensorUnit::look_for_end() { sequence_.look_for_end(); }
void SensorUnit::idle() { sequence_.idle(); }

bool SensorUnit::take(std::int64_t index, double time_s, const Pose3& world_from_tool,
                      std::vector<Event>& events) {
  if (!stream_->acquire(index, time_s, world_from_tool, profile_)) {
    error_ = stream_->error();
    laser_ = false;
    sequence_.laser_off();
    events.push_back(Event::StreamEnded);
    return false;
  }
  // The profiles are read as a sequence (tracker/follower.h): a reading
  // that jumps away from the followed joint is rejected. While the follower
  // confirms a joint, its readings already count for the sequence's start
  // search, which confirms the start itself.
  result_ = follower_.track(profile_.view(), &profile_.world_from_sensor);
  if (follower_.read() && result_.status == TrackStatus::Rejected) {
    result_.status = TrackStatus::Ok;
    result_.reason.clear();
  }
  Observation obs;
  obs.index = profile_.index;
  obs.time_s = profile_.time_s;
  obs.world_from_sensor = profile_.world_from_sensor;
  if (result_.status == TrackStatus::Ok && result_.track_point &&
      support_distance_mm(profile_.view(), *result_.track_point) <= kMaxSupportMm) {
    const Vec2& tp = *result_.track_point;
    obs.joint = true;
    obs.track_point_world = profile_.world_from_sensor * Eigen::Vector3d(0.0, tp.x(), tp.y());
    obs.gap_mm = result_.gap_mm;
    JointData j;
    j.profile_index = profile_.index;
    j.time_s = profile_.time_s;
    j.world_from_sensor = profile_.world_from_sensor;
    j.break_points = result_.break_points;
    j.track_point_sensor = tp;
    j.track_point_world = obs.track_point_world;
    j.gap_mm = result_.gap_mm;
    j.angle_deg = result_.angle_deg;
    j.confidence = result_.confidence;
    latest_ = j;
  }
  const std::optional<Event> e = sequence_.update(obs);
  if (e) events.push_back(*e);
  if (on_profile) on_profile(profile_, result_, obs.joint ? &*latest_ : nullptr, e);
  return true;
}

std::vector<Event> SensorUnit::advance(double time_s, const Pose3& world_from_tool) {
  std::vector<Event> events;
  const double rate = stream_->rate_hz();
  // Profile ticks k (time k / rate) in (clock_s_, time_s]; the tool pose is
  // interpolated between the previous call's and this one's.
  const auto tick_after = [&](double t) {
    return static_cast<std::int64_t>(std::floor(t * rate + 1e-9)) + 1;
  };
  const std::int64_t first = tick_after(clock_s_);
  const std::int64_t last = tick_after(time_s) - 1;
  const double t0 = clock_s_;
  if (!have_tool_) last_tool_ = world_from_tool;
  for (std::int64_t k = first; laser_ && k <= last; ++k) {
    const double t = static_cast<double>(k) / rate;
    const double f = time_s > t0 ? std::clamp((t - t0) / (time_s - t0), 0.0, 1.0) : 1.0;
    const Pose3 tool = f >= 1.0 ? world_from_tool : interpolate(last_tool_, world_from_tool, f);
    if (!take(next_index_, t, tool, events)) break;
    ++next_index_;
  }
  clock_s_ = std::max(clock_s_, time_s);
  last_tool_ = world_from_tool;
  have_tool_ = true;
  return events;
}

std::optional<JointData> SensorUnit::latest_joint(double now_s) const {
  if (!latest_) return std::nullopt;
  JointData j = *latest_;
  j.age_s = now_s - j.time_s;
  return j;
}

}  // namespace vts::tracker
