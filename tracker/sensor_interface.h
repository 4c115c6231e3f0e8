#pragma once
// The sensor interface of the paper's section 5.2: the command set a master
// program (robot controller) talks to. Behind it sits the sensor's control
// unit (SensorUnit: tracker + sequence logic) fed by a ProfileStream, which is
// either the virtual sensor scanning the simulated cell (sensor/virtual_sensor.h)
// or a recording of one (sensor/recorded_sensor.h): the master cannot tell
// them apart.
//
// Frames: world (mm) as the robot knows it; the sensor frame of tracker/types.h
// (y along the laser line, z the range; x = y cross z, the travel direction).
// Tool frame: the TCP, where the master moves the robot; the sensor is mounted
// on it at tool_from_sensor (fixed).
#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Geometry>

#include "tracker/follower.h"
#include "tracker/sequence.h"
#include "tracker/tracker.h"

namespace vts::tracker {

using Pose3 = Eigen::Isometry3d;

// The pose a fraction t of the way from a to b: the position linearly, the
// rotation by slerp. (robot/perfect_robot.h has its twin: robot/ depends on
// none of our libraries.)
Pose3 interpolate(const Pose3& a, const Pose3& b, double t);

// One profile as the sensor head delivers it: points in the sensor frame, the
// pose the robot reported for the sensor at the moment of the scan, and the time.
struct SensorProfile {
  std::int64_t index = 0;  // profile number since the run started
  double time_s = 0.0;
  Pose3 world_from_sensor = Pose3::Identity();
  std::vector<float> y_mm, z_mm;   // sensor frame, per column
  std::vector<std::uint8_t> valid; // 1 measured
  ProfileView view() const { return {y_mm, z_mm, valid}; }
};

// Below the interface: the source of profiles. acquire() takes the profile
// `index` due at time_s, with the robot's tool at world_from_tool (a recorded
// stream returns its recorded row instead and checks that index and time
// match). Returns false when no profile can be delivered (end of a recording,
// or a recording that does not match the request); error() then says why.
class ProfileStream {
 public:
  virtual ~ProfileStream() = default;
  virtual bool acquire(std::int64_t index, double time_s, const Pose3& world_from_tool,
                       SensorProfile& out) = 0;
  virtual double rate_hz() const = 0;
  virtual const Pose3& tool_from_sensor() const = 0;
  virtual std::string error() const { return {}; }
};

// What latest_joint() answers: the last accepted joint, in world and sensor
// coordinates, with the data's age.
struct JointData {
  std::int64_t profile_index = 0;
  double time_s = 0.0;       // when the profile was taken
  double age_s = 0.0;        // now - time_s, at the request
  Pose3 world_from_sensor = Pose3::Identity();
  std::array<std::optional<Vec2>, kMaxBreakPoints> break_points;  // sensor frame (y, z)
  Vec2 track_point_sensor = Vec2::Zero();                        // sensor frame (y, z)
  Eigen::Vector3d track_point_world = Eigen::Vector3d::Zero();   // mm
  double gap_mm = kNotMeasured;
  double angle_deg = kNotMeasured;
  double confidence = 0.0;  // TrackResult::confidence of the reading
};

// The command set. Commands answer at once; profiles are taken in advance(),
// which the master calls as its clock runs, telling the sensor where the tool
// is (as the robot reports its pose to a real sensor).
class SensorInterface {
 public:
  virtual ~SensorInterface() = default;
  // Lights the laser; true once confirmed (the stream delivers profiles).
  virtual bool laser_on() = 0;
  virtual void laser_off() = 0;
  // Start search: the start point is reported by an Event::StartFound alert
  // (and start_point()).
  virtual void search_start() = 0;
  virtual void start_tracking() = 0;
  // Keep tracking, and alert (Event::EndFound) when the joint ends.
  virtual void look_for_end() = 0;
  virtual void idle() = 0;
  // Runs the sensor up to time_s with the tool at world_from_tool: every
  // profile due in (last call, time_s] is taken (with the laser on) and
  // processed. Returns the alerts raised, in order.
  virtual std::vector<Event> advance(double time_s, const Pose3& world_from_tool) = 0;
  // The last accepted joint data with its age at `now_s`; empty if none since
  // the laser went on.
  virtual std::optional<JointData> latest_joint(double now_s) const = 0;
  virtual SensorState state() const = 0;
  virtual std::optional<Eigen::Vector3d> start_point() const = 0;
  virtual std::optional<Eigen::Vector3d> end_point() const = 0;
  virtual const SequenceCounters& counters() const = 0;
  // Why the last laser_on() failed or the stream stopped; empty if it did not.
  virtual std::string error() const = 0;
};

// The control unit over a profile stream: the Tracker (one profile -> joint)
// and the Sequence (states and alerts). Both the virtual and the recorded
// sensor are this class over their stream.
class SensorUnit final : public SensorInterface {
 public:
  SensorUnit(std::unique_ptr<ProfileStream> stream, const TrackerParams& tracker_params,
             const SequenceParams& sequence_params = {}, const FollowParams& follow_params = {});

  bool laser_on() override;
  void laser_off() override;
  void search_start() override;
  void start_tracking() override;
  void look_for_end() override;
  void idle() override;
  std::vector<Event> advance(double time_s, const Pose3& world_from_tool) override;
  std::optional<JointData> latest_joint(double now_s) const override;
  SensorState state() const override { return sequence_.state(); }
  std::optional<Eigen::Vector3d> start_point() const override { return sequence_.start_point(); }
  std::optional<Eigen::Vector3d> end_point() const override { return sequence_.end_point(); }
  const SequenceCounters& counters() const override { return sequence_.counters(); }
  std::string error() const override { return error_; }

  // The last profile taken and its tracker result (for viewers and logs).
  const SensorProfile& last_profile() const { return profile_; }
  const TrackResult& last_result() const { return result_; }
  ProfileStream& stream() { return *stream_; }

  // Called at the end of every profile taken, with its tracker result, the
  // joint data it produced (null when it was not accepted) and the alert it
  // raised: for a server's per-profile pushes, joint queues and event times.
  // May be empty.
  std::function<void(const SensorProfile&, const TrackResult&, const JointData*, std::optional<Event>)> on_profile;

 private:
  bool take(std::int64_t index, double time_s, const Pose3& world_from_tool, std::vector<Event>& events);

  std::unique_ptr<ProfileStream> stream_;
  Follower follower_;  // the tracker over the profile sequence (tracker/follower.h)
  Sequence sequence_;
  SensorProfile profile_;
  TrackResult result_;
  std::optional<JointData> latest_;
  std::int64_t next_index_ = 0;  // profiles taken so far (the laser's on-time only)
  double clock_s_ = 0.0;         // time of the last advance()
  Pose3 last_tool_ = Pose3::Identity();  // tool pose at the last advance()
  bool have_tool_ = false;
  bool laser_ = false;
  std::string error_;
};

// The distance (mm) from `point` (sensor frame) to the nearest usable profile
// point: how well the profile supports a break point.
double support_distance_mm(const ProfileView& profile, const Vec2& point);

}  // namespace vts::tracker
