#include "sensor/recorded_sensor.h"

#include <cmath>
#include <sstream>

#include "sensor/virtual_sensor.h"

namespace vts {

RecordedProfileStream::RecordedProfileStream(ProfileRecording recording, double pose_tolerance_mm)
    : rec_(std::move(recording)), tol_mm_(pose_tolerance_mm) {}

std::unique_ptr<RecordedProfileStream> RecordedProfileStream::open(const std::filesystem::path& path) {
  return std::make_unique<RecordedProfileStream>(read_profile_exr(path));
}

bool RecordedProfileStream::acquire(std::int64_t index, double time_s, const Pose& world_from_tool,
                                    tracker::SensorProfile& out) {
  std::ostringstream why;
  const auto rows = static_cast<std::int64_t>(rec_.profiles.size());
  if (index < 0 || index >= rows) {
    why << "profile " << index << " requested at " << time_s << " s: the recording ("
        << rec_.info.scene_name << ") has " << rows << " profiles";
    error_ = why.str();
    return false;
  }
  const Profile& p = rec_.profiles[static_cast<std::size_t>(index)];
  const Pose expected = world_from_tool * rec_.info.scanner.tool_from_laser;
  const double dpos = (p.world_from_sensor.translation() - expected.translation()).norm();
  // Rotation difference as the largest column change times a 100 mm lever.
  const double drot = 100.0 * (p.world_from_sensor.linear() - expected.linear()).cwiseAbs().maxCoeff();
  if (p.index != index || std::abs(p.time_s - time_s) > 1e-9 || dpos > tol_mm_ || drot > tol_mm_) {
    why << "profile " << index << " does not match the request: recorded at " << p.time_s
        << " s with the sensor at (" << p.world_from_sensor.translation().transpose() << ") mm, requested at "
        << time_s << " s at (" << expected.translation().transpose()
        << ") mm; the master did not move as in the recorded run";
    error_ = why.str();
    return false;
  }
  to_sensor_profile(p, out);
  return true;
}

}  // namespace vts
