#pragma once
// The virtual sensor head behind the sensor interface (tracker/sensor_interface.h):
// scans the cell through a vts::ProfileSource (raster emulator or ray-cast
// reference) with the laser mounted on the tool at ScannerDesc::tool_from_laser,
// and turns each ideal profile into a measured one with the error model.
// Wrap it in a tracker::SensorUnit to get the sensor interface.
#include <cstdint>
#include <functional>
#include <optional>

#include "sensor/error_model.h"
#include "sensor/profile_source.h"
#include "tracker/sensor_interface.h"

namespace vts {

class VirtualProfileStream final : public tracker::ProfileStream {
 public:
  // `source` must outlive the stream; its scanner() is the sensor (rate,
  // mount, error model switch). seed: the error model's draws (ScanState).
  VirtualProfileStream(ProfileSource& source, std::uint64_t seed);

  bool acquire(std::int64_t index, double time_s, const Pose& world_from_tool,
               tracker::SensorProfile& out) override;
  double rate_hz() const override { return source_.scanner().rate_hz; }
  const Pose& tool_from_sensor() const override { return source_.scanner().tool_from_laser; }

  // Called with every measured profile before it is delivered: `alter` may
  // change it (tests inject faults), then `record` sees the final profile.
  std::function<void(Profile&)> alter;
  std::function<void(const Profile&)> record;
  // Where the sensor really is against where the robot reports it (a robot
  // with absolute-accuracy errors, robot/arm_robot.h): set, the laser scans
  // the cell at actual_from_reported * the reported pose, and the profile
  // keeps the reported pose, as a real sensor's data are stamped with the
  // controller's idea of its pose. Empty: the reported pose is the actual one.
  std::optional<Pose> actual_from_reported;
  // Where the source's moving part lies (ProfileSource::move_part, in the
  // frame the sensor scans in): set, it is placed there before each scan.
  std::optional<Pose> moving_part;

  const ScanState& scan_state() const { return state_; }
  const Profile& last_measured() const { return measured_; }

 private:
  ProfileSource& source_;
  ScanState state_;
  Profile ideal_, measured_;
};

// Copies the measured points, pose, time and index of a vts::Profile.
void to_sensor_profile(const Profile& p, tracker::SensorProfile& out);

}  // namespace vts
