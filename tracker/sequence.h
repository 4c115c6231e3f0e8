#pragma once
// The sensor's sequence logic after the paper's section 5.2: laser on, search
// for the start point, track, look for the end of the seam, laser off, idle.
// Fed one observation per profile (joint seen or not, where, and the sensor's
// pose); decides when the start is found, the end is found or the seam is
// lost, and counts invalid profiles. Pure: Eigen only, no tracker internals.
//
// Distances are travel of the laser origin (world, mm), so the logic does not
// depend on the profile rate.
#include <cstdint>
#include <limits>
#include <optional>
#include <string_view>
#include <vector>

#include <Eigen/Geometry>

namespace vts::tracker {

enum class SensorState {
  Idle,           // laser off
  LaserOn,        // laser on and confirmed, no task
  Searching,      // looking for the start point
  StartFound,     // start point found; waiting for start_tracking()
  Tracking,       // tracking the joint
  LookingForEnd,  // tracking, and alerting when the joint ends
  EndFound,       // the joint ended (end point known)
  SeamLost,       // the joint disappeared while tracking (not looking for the end)
};
std::string_view to_string(SensorState state);

// Alerts the sensor raises to the master.
enum class Event {
  StartFound,   // start_point() is set
  StartBehind,  // the joint was already there when the search began: back off and search again
  EndFound,     // end_point() is set
  SeamLost,     // tracking lost the joint for SequenceParams::lost_mm
  StreamEnded,  // the profile stream delivered no profile (recording ended or mismatched)
};
std::string_view to_string(Event event);

struct SequenceParams {
  // Start: the joint seen in consecutive profiles over at least this travel
  // and this many profiles.
  double confirm_mm = 1.0;
  int confirm_profiles = 3;
  // Up to this many consecutive profiles without the joint (an outlier, a
  // dropout) do not break the run that confirms the start.
  int start_bridge_profiles = 1;
  // A wall that enters or leaves the laser plane at a slant shows as a stub
  // standing off the plate, i.e. as a wider gap. The start is where the
  // joint's gap first matches (within this) the gap at confirmation; while
  // looking for the end, a joint whose gap differs by more than this from the
  // last full one's counts as absent.
  double partial_gap_tol_mm = 0.3;
  // End (LookingForEnd): the joint absent over this travel and this many profiles.
  double end_mm = 2.0;
  int end_profiles = 3;
  // Loss (Tracking): the joint absent over this travel and this many profiles.
  double lost_mm = 5.0;
  int lost_profiles = 5;
};

// One processed profile.
struct Observation {
  std::int64_t index = 0;
  double time_s = 0.0;
  Eigen::Isometry3d world_from_sensor = Eigen::Isometry3d::Identity();
  bool joint = false;  // the joint was recognised (and its root is measured)
  Eigen::Vector3d track_point_world = Eigen::Vector3d::Zero();  // when joint
  double gap_mm = std::numeric_limits<double>::quiet_NaN();      // when joint; NaN: not measured
};

struct SequenceCounters {
  std::int64_t profiles = 0;        // observations while a task ran
  std::int64_t joint_profiles = 0;  // with the joint
  std::int64_t invalid_profiles = 0;  // without (during tracking: dropouts, outliers)
  double longest_gap_mm = 0.0;      // longest travel without the joint while tracking
};

class Sequence {
 public:
  explicit Sequence(const SequenceParams& params = {}) : params_(params) {}

  // Commands. laser_on() from Idle -> LaserOn; laser_off() -> Idle from any
  // state; idle() stops the current task (-> LaserOn, or Idle with the laser off).
  void laser_on();
  void laser_off();
  void search_start();    // -> Searching (laser must be on; else ignored)
  void start_tracking();  // -> Tracking (from LaserOn, StartFound or a finished task)
  void look_for_end();    // -> LookingForEnd (from Tracking)
  void idle();

  // Feeds one observation; returns the alert it raises, if any.
  std::optional<Event> update(const Observation& obs);

  SensorState state() const { return state_; }
  const SequenceParams& params() const { return params_; }
  std::optional<Eigen::Vector3d> start_point() const { return start_; }
  std::optional<Eigen::Vector3d> end_point() const { return end_; }
  const SequenceCounters& counters() const { return counters_; }
  // The last observation with the joint since the current task began.
  const std::optional<Observation>& last_joint() const { return last_joint_; }

 private:
  void reset_runs();
  Eigen::Vector3d seam_direction(const Observation& at) const;

  SequenceParams params_;
  SensorState state_ = SensorState::Idle;
  SequenceCounters counters_;
  std::optional<Eigen::Vector3d> start_, end_;
  // Searching: the current run of joint observations and the last one without.
  std::vector<Observation> run_;
  int run_misses_ = 0;  // consecutive profiles without the joint inside the run
  std::optional<Observation> last_without_;
  // Tracking: the last joint observation and the current run without.
  std::optional<Observation> last_joint_, miss_first_;
  int miss_count_ = 0;
};

}  // namespace vts::tracker
