#pragma once
// One laser profile: N samples in scan order (column 0 at the most negative y).
#include <cstdint>
#include <limits>
#include <vector>

#include "sensor/pose.h"
#include "sensor/scanner.h"

namespace vts {

struct Profile {
  // Per column, sensor frame, mm. For an invalid column y, z and range are 0.
  std::vector<float> y_mm;      // along the laser line
  std::vector<float> z_mm;      // along the optical axis
  std::vector<float> range_mm;  // distance from the laser origin along the column ray
  std::vector<std::uint8_t> valid;  // 1 measured, 0 no return
  Pose world_from_sensor = Pose::Identity();
  double time_s = 0.0;
  std::int64_t index = 0;       // profile number in its run

  void resize(int n);
  int size() const { return static_cast<int>(range_mm.size()); }
  int valid_count() const;
};

// Ray parameter meaning "no intersection".
inline constexpr float kNoHit = std::numeric_limits<float>::infinity();

// Turns a raw ray distance along column i into the measured sample: applies
// the maximum hit distance and the depth of field, fills y, z, range, valid.
// Both profile sources call this, so their filtering is identical.
void set_column(const ScannerDesc& desc, const Eigen::Vector3f& direction, int column,
                float hit_distance_mm, Profile& out);

}  // namespace vts
