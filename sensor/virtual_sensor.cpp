#include "sensor/virtual_sensor.h"

namespace vts {

void to_sensor_profile(const Profile& p, tracker::SensorProfile& out) {
  out.index = p.index;
  out.time_s = p.time_s;
  out.world_from_sensor = p.world_from_sensor;
  out.y_mm.assign(p.y_mm.begin(), p.y_mm.end());
  out.z_mm.assign(p.z_mm.begin(), p.z_mm.end());
  out.valid.assign(p.valid.begin(), p.valid.end());
}

VirtualProfileStream::VirtualProfileStream(ProfileSource& source, std::uint64_t seed) : source_(source) {
  state_.seed = seed;
}

bool VirtualProfileStream::acquire(std::int64_t index, double time_s, const Pose& world_from_tool,
                                   tracker::SensorProfile& out) {
  const Pose pose = world_from_tool * source_.scanner().tool_from_laser;
  if (moving_part) source_.move_part(*moving_part);
  source_.scan(actual_from_reported ? Pose(*actual_from_reported * pose) : pose, ideal_);
  ideal_.world_from_sensor = pose;
  ideal_.time_s = time_s;
  ideal_.index = index;
  // With scanner().ideal the error model passes the ideal points through.
  apply_error_model(source_.scanner(), ideal_, state_, measured_);
  if (alter) alter(measured_);
  if (record) record(measured_);
  to_sensor_profile(measured_, out);
  // The sensor reports its pose as position and unit quaternion, the way a
  // recording (EXR) stores it, so that a replay delivers the same bits.
  out.world_from_sensor = pose_from_quat(pose.translation(), rotation_quat(pose));
  return true;
}

}  // namespace vts
