#include "tracker/sequence.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace vts::tracker {
namespace {

Eigen::Vector3d origin_of(const Observation& o) { return o.world_from_sensor.translation(); }
// The laser plane's normal: the sensor's x axis (travel direction), world.
Eigen::Vector3d plane_normal(const Observation& o) { return o.world_from_sensor.linear().col(0); }

double travel(const Observation& a, const Observation& b) { return (origin_of(b) - origin_of(a)).norm(); }

// Distance along d from p to the laser plane of `o` (signed, in units of d).
double along_to_plane(const Eigen::Vector3d& p, const Eigen::Vector3d& d, const Observation& o) {
  const Eigen::Vector3d n = plane_normal(o);
  const double nd = n.dot(d);
  if (std::abs(nd) < 1e-6) return 0.0;
  return n.dot(origin_of(o) - p) / nd;
}

}  // namespace

std::string_view to_string(SensorState s) {
  switch (s) {
    case SensorState::Idle: return "idle";
    case SensorState::LaserOn: return "laser-on";
    case SensorState::Searching: return "searching";
    case SensorState::StartFound: return "start-found";
    case SensorState::Tracking: return "tracking";
    case SensorState::LookingForEnd: return "looking-for-end";
    case SensorState::EndFound: return "end-found";
    case SensorState::SeamLost: return "seam-lost";
  }
  return "?";
}

std::string_view to_string(Event e) {
  switch (e) {
    case Event::StartFound: return "start-found";
    case Event::StartBehind: return "start-behind";
    case Event::EndFound: return "end-found";
    case Event::SeamLost: return "seam-lost";
    case Event::StreamEnded: return "stream-ended";
  }
  return "?";
}

void Sequence::reset_runs() {
  run_.clear();
  run_misses_ = 0;
  last_without_.reset();
  last_joint_.reset();
  miss_first_.reset();
  miss_count_ = 0;
}

void Sequence::laser_on() {
  if (state_ == SensorState::Idle) state_ = SensorState::LaserOn;
}

void Sequence::laser_off() {
  state_ = SensorState::Idle;
  reset_runs();
}

void Sequence::idle() {
  if (state_ != SensorState::Idle) state_ = SensorState::LaserOn;
  reset_runs();
}

void Sequence::search_start() {
  if (state_ == SensorState::Idle) return;
  reset_runs();
  start_.reset();
  end_.reset();
  state_ = SensorState::Searching;
}

void Sequence::start_tracking() {
  if (state_ == SensorState::Idle || state_ == SensorState::Searching) return;
  if (state_ != SensorState::StartFound) start_.reset();
  end_.reset();
  // Keep the start run's last joint observation: tracking continues from it.
  run_.clear();
  run_misses_ = 0;
  last_without_.reset();
  miss_first_.reset();
  miss_count_ = 0;
  state_ = SensorState::Tracking;
}

void Sequence::look_for_end() {
  if (state_ == SensorState::Tracking) state_ = SensorState::LookingForEnd;
}

Eigen::Vector3d Sequence::seam_direction(const Observation& at) const {
  // From the start point when it lies far enough behind; else the travel.
  if (start_ && last_joint_) {
    const Eigen::Vector3d d = last_joint_->track_point_world - *start_;
    if (d.norm() > 5.0) return d.normalized();
  }
  return plane_normal(at);
}

std::optional<Event> Sequence::update(const Observation& obs) {
  switch (state_) {
    case SensorState::Idle:
    case SensorState::LaserOn:
    case SensorState::EndFound:
    case SensorState::SeamLost:
      return std::nullopt;
    default: break;
  }
  ++counters_.profiles;
  obs.joint ? ++counters_.joint_profiles : ++counters_.invalid_profiles;

  if (state_ == SensorState::Searching) {
    if (!obs.joint) {
      if (!run_.empty() && ++run_misses_ <= params_.start_bridge_profiles) {
        run_.push_back(obs);  // bridged: kept, so the planes stay in order
        return std::nullopt;
      }
      run_.clear();
      run_misses_ = 0;
      last_without_ = obs;
      return std::nullopt;
    }
    run_misses_ = 0;
    run_.push_back(obs);
    last_joint_ = obs;
    const auto with_joint = std::count_if(run_.begin(), run_.end(), [](const Observation& o) { return o.joint; });
    if (with_joint < params_.confirm_profiles || travel(run_.front(), obs) < params_.confirm_mm)
      return std::nullopt;
    if (!last_without_) {
      // Seen from the first profile on: the start lies behind the search's beginning.
      state_ = SensorState::LaserOn;
      reset_runs();
      return Event::StartBehind;
    }
    // The joint begins at the first profile whose gap matches the gap now
    // (median of the last three); before it, the joint was absent or only
    // partly in the laser plane.
    std::vector<double> recent;
    for (auto it = run_.rbegin(); it != run_.rend() && recent.size() < 3; ++it)
      if (it->joint && std::isfinite(it->gap_mm)) recent.push_back(it->gap_mm);
    const double g_ref = recent.empty() ? std::numeric_limits<double>::quiet_NaN() : [&] {
      std::sort(recent.begin(), recent.end());
      return recent[recent.size() / 2];
    }();
    auto whole = [&](const Observation& o) {
      return o.joint && (!std::isfinite(g_ref) || !std::isfinite(o.gap_mm) ||
                         std::abs(o.gap_mm - g_ref) <= params_.partial_gap_tol_mm);
    };
    std::size_t k = 0;
    while (k + 1 < run_.size() && !whole(run_[k])) ++k;
    const Observation& before = k == 0 ? *last_without_ : run_[k - 1];
    // The start lies between the plane before and the first plane with the
    // whole joint: take the middle, along the run's direction.
    const Eigen::Vector3d p1 = run_[k].track_point_world;
    Eigen::Vector3d d = obs.track_point_world - run_.front().track_point_world;
    d = d.norm() > 0.5 ? d.normalized() : plane_normal(run_[k]);
    const double t = along_to_plane(p1, d, before);  // negative: behind p1
    start_ = p1 + 0.5 * t * d;
    state_ = SensorState::StartFound;
    return Event::StartFound;
  }

  if (state_ == SensorState::StartFound) {
    if (obs.joint) last_joint_ = obs;
    return std::nullopt;
  }

  // Tracking or LookingForEnd.
  bool full = obs.joint;
  if (full && state_ == SensorState::LookingForEnd && last_joint_ && std::isfinite(obs.gap_mm) &&
      std::isfinite(last_joint_->gap_mm) &&
      std::abs(obs.gap_mm - last_joint_->gap_mm) > params_.partial_gap_tol_mm)
    full = false;  // only part of the joint is in the laser plane
  if (full) {
    if (miss_first_ && last_joint_)
      counters_.longest_gap_mm = std::max(counters_.longest_gap_mm, travel(*last_joint_, obs));
    last_joint_ = obs;
    miss_first_.reset();
    miss_count_ = 0;
    return std::nullopt;
  }
  if (!miss_first_) miss_first_ = obs;
  ++miss_count_;
  const Observation& since = last_joint_ ? *last_joint_ : *miss_first_;
  const double missing_mm = travel(since, obs);
  if (state_ == SensorState::LookingForEnd) {
    if (miss_count_ < params_.end_profiles || missing_mm < params_.end_mm || !last_joint_)
      return std::nullopt;
    const Eigen::Vector3d p = last_joint_->track_point_world;
    const Eigen::Vector3d d = seam_direction(*last_joint_);
    const double t = along_to_plane(p, d, *miss_first_);  // positive: ahead of p
    end_ = p + 0.5 * t * d;
    counters_.longest_gap_mm = std::max(counters_.longest_gap_mm, missing_mm);
    state_ = SensorState::EndFound;
    return Event::EndFound;
  }
  if (miss_count_ < params_.lost_profiles || missing_mm < params_.lost_mm) return std::nullopt;
  counters_.longest_gap_mm = std::max(counters_.longest_gap_mm, missing_mm);
  state_ = SensorState::SeamLost;
  return Event::SeamLost;
}

}  // namespace vts::tracker
