#pragma once
// A recorded sensor head behind the sensor interface: replays the profiles of
// a vts EXR (sensor/profile_exr.h) written by an earlier run, row by row. The
// request must match the recording: row `index` must exist, carry that index
// and time, and have been taken with the tool where the master now puts it
// (within pose_tolerance_mm); otherwise acquire() fails and error() says why.
#include <filesystem>
#include <string>

#include "sensor/profile_exr.h"
#include "tracker/sensor_interface.h"

namespace vts {

class RecordedProfileStream final : public tracker::ProfileStream {
 public:
  explicit RecordedProfileStream(ProfileRecording recording, double pose_tolerance_mm = 1e-3);
  // Reads the file; throws ExrError naming it.
  static std::unique_ptr<RecordedProfileStream> open(const std::filesystem::path& path);

  bool acquire(std::int64_t index, double time_s, const Pose& world_from_tool,
               tracker::SensorProfile& out) override;
  double rate_hz() const override { return rec_.info.scanner.rate_hz; }
  const Pose& tool_from_sensor() const override { return rec_.info.scanner.tool_from_laser; }
  std::string error() const override { return error_; }
  const ProfileRecording& recording() const { return rec_; }

 private:
  ProfileRecording rec_;
  double tol_mm_;
  std::string error_;
};

}  // namespace vts
