#include "tracker/follower.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace vts::tracker {
namespace {

Eigen::Vector3d in_world(const Eigen::Isometry3d& world_from_sensor, const Vec2& yz) {
  return world_from_sensor * Eigen::Vector3d(0.0, yz.x(), yz.y());
}

Vec2 in_sensor(const Eigen::Isometry3d& world_from_sensor, const Eigen::Vector3d& p) {
  const Eigen::Vector3d s = world_from_sensor.inverse() * p;
  return Vec2(s.y(), s.z());
}

}  // namespace

Follower::Follower(const TrackerParams& tracker_params, const FollowParams& params)
    : params_(params), tracker_(tracker_params) {}

void Follower::reset() {
  region_.reset();
  filtered_.reset();
  locked_ = false;
  read_ = false;
  run_ = 0;
  since_mm_ = 0.0;
  misses_ = 0;
  have_state_ = false;
  last_pose_.reset();
}

const TrackResult& Follower::track(const ProfileView& profile, const Eigen::Isometry3d* world_from_sensor) {
  // The pose of this profile: given, or the last one moved along its x axis
  // (the travel direction) by the travel per profile.
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  if (world_from_sensor) {
    pose = *world_from_sensor;
  } else if (last_pose_) {
    pose = *last_pose_;
    pose.translation() += params_.travel_per_profile_mm * pose.linear().col(0);
  }
  const double step = last_pose_ ? (pose.translation() - last_pose_->translation()).norm() : 0.0;
  last_pose_ = pose;
  since_mm_ += step;

  // Where the joint should be: the filter's point carried along its seam
  // direction by the travel since it was updated.
  std::optional<Vec2> predicted;
  if (have_state_) predicted = in_sensor(pose, pos_ + vel_ * since_mm_);
  const double radius = params_.gate_mm + params_.max_slope * since_mm_;

  region_.reset();
  if (locked_ && predicted) region_ = TrackPrior{*predicted, radius};
  tracker_.track(profile, result_, region_ ? &*region_ : nullptr);
  const bool ok = result_.status == TrackStatus::Ok && result_.track_point;
  read_ = ok;

  auto start_filter = [&](const Eigen::Vector3d& m) {
    pos_ = m;
    vel_ = pose.linear().col(0);  // the seam point moves with the laser plane
    have_state_ = true;
  };
  if (ok) {
    const Eigen::Vector3d m = in_world(pose, *result_.track_point);
    const bool consistent = predicted && (*result_.track_point - *predicted).norm() <= radius;
    if (locked_ || consistent) {
      // Alpha-beta update over the travel since the last reading.
      const Eigen::Vector3d p = pos_ + vel_ * since_mm_;
      const Eigen::Vector3d r = m - p;
      pos_ = p + params_.alpha * r;
      if (since_mm_ > 1e-9) vel_ += (params_.beta / since_mm_) * r;
      run_ = std::min(run_ + 1, params_.lock_profiles);
    } else {
      start_filter(m);
      run_ = 1;
    }
    if (run_ >= params_.lock_profiles) locked_ = true;
    since_mm_ = 0.0;
    misses_ = 0;
    filtered_ = in_sensor(pose, pos_);
    // Until the joint is confirmed by lock_profiles consistent readings, a
    // reading is no joint yet: a decoy or reflection read alone must not
    // pass for one.
    if (!locked_) {
      result_.status = TrackStatus::Rejected;
      result_.reason = "acquiring: " + std::to_string(run_) + " of " + std::to_string(params_.lock_profiles) +
                       " consistent readings";
    }
    return result_;
  }
  ++misses_;
  if (!locked_) {
    // A run that confirms the joint must be unbroken.
    run_ = 0;
    have_state_ = false;
  } else if (since_mm_ > params_.lost_mm && misses_ >= 3) {
    locked_ = false;
    run_ = 0;
    have_state_ = false;
  }
  return result_;
}

}  // namespace vts::tracker
