#pragma once
// Sequence tracking (docs/JOINTS.md, "Sequence tracking"): the tracker over
// the consecutive profiles of one seam, as real seam trackers read them. Once
// locked on the joint, each profile is searched only near where the joint is
// predicted from the profiles before (a region of interest whose radius grows
// with the travel since the last reading), so a reading that jumps away (a
// reflection, a scratch, a second edge) is rejected rather than taken for a
// new joint; the track point is smoothed by an alpha-beta filter.
//
// Frames: with the sensor's pose per profile (world_from_sensor), the joint
// is followed in the world, and its prediction is where the seam line through
// the last readings meets the current laser plane (the sensor's y-z plane);
// without poses, in the sensor frame, the profiles assumed to be taken along
// the seam at the given travel per profile.
#include <optional>

#include <Eigen/Geometry>

#include "tracker/tracker.h"

namespace vts::tracker {

struct FollowParams {
  // Lock: this many consecutive Ok readings, each within the gate of the
  // prediction from the ones before.
  int lock_profiles = 3;
  // The region of interest: gate_mm plus max_slope times the travel since
  // the last accepted reading (the seam may run across the laser plane or
  // towards the sensor at up to max_slope mm per mm of travel).
  double gate_mm = 1.5;
  double max_slope = 0.5;
  // Lost: after this much travel (and at least 3 profiles) without a reading
  // in the region, the lock is released and whole profiles are searched
  // again.
  double lost_mm = 10.0;
  // Alpha-beta filter gains on the track point (position, velocity per mm
  // of travel); alpha 1, beta 0: no smoothing.
  double alpha = 0.6;
  double beta = 0.1;
  // Travel per profile when no poses are given (mm).
  double travel_per_profile_mm = 1.0;
};

class Follower {
 public:
  explicit Follower(const TrackerParams& tracker_params = {}, const FollowParams& params = {});

  // Tracks the next profile. world_from_sensor: the sensor's pose when it was
  // taken (nullptr: none; FollowParams::travel_per_profile_mm is the
  // travel). Until locked, readings are Rejected ("acquiring: k of n
  // consistent readings"), their values kept; locked, readings outside the
  // region are not considered: the result is Rejected ("no joint within ...
  // of the predicted point") when none is inside.
  const TrackResult& track(const ProfileView& profile, const Eigen::Isometry3d* world_from_sensor = nullptr);

  bool locked() const { return locked_; }
  // The last profile was read (the tracker's Ok), confirmed or, while
  // acquiring, not yet (then the result says "acquiring").
  bool read() const { return read_; }
  // The smoothed track point of the last accepted reading, sensor frame of
  // that profile; empty before the first.
  std::optional<Vec2> filtered() const { return filtered_; }
  // The region of interest used for the last profile (empty when unlocked).
  const std::optional<TrackPrior>& region() const { return region_; }
  const TrackResult& result() const { return result_; }
  Tracker& tracker() { return tracker_; }
  void reset();

 private:
  FollowParams params_;
  Tracker tracker_;
  TrackResult result_;
  std::optional<TrackPrior> region_;
  std::optional<Vec2> filtered_;
  bool locked_ = false;
  bool read_ = false;
  int run_ = 0;               // consecutive consistent Ok readings while unlocked
  double since_mm_ = 0.0;     // travel since the last accepted reading
  int misses_ = 0;            // profiles since the last accepted reading
  // The filter, in the world (with poses) or the sensor frame (without):
  // position and velocity per mm of travel.
  Eigen::Vector3d pos_ = Eigen::Vector3d::Zero(), vel_ = Eigen::Vector3d::Zero();
  bool have_state_ = false;
  std::optional<Eigen::Isometry3d> last_pose_;
};

}  // namespace vts::tracker
