#pragma once
// One laser profile: N samples in scan order (column 0 at the most negative y).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "sensor/pose.h"
#include "sensor/scanner.h"

namespace vts {

struct Profile {
  // Per column, sensor frame, mm: the profile as measured (the error model's
  // output), or the ideal geometric one (a source's output, or --ideal).
  // For an invalid column y, z and range are 0.
  std::vector<float> y_mm;      // along the laser line
  std::vector<float> z_mm;      // along the optical axis
  std::vector<float> range_mm;  // distance from the laser origin along the column ray
  std::vector<std::uint8_t> valid;  // 1 measured, 0 no return

  // Per column, filled by the sources with the ideal geometry, read by the
  // error model (sensor/error_model.h), which passes them through.
  std::vector<float> cos_incidence;  // cos of the angle between the column ray and the
                                     // surface normal, 0..1; 0 where invalid
  std::vector<std::uint8_t> camera_visible;  // 1: the camera sees the lit point; 0:
                                             // camera shadow, or invalid

  // Per column, filled by the error model; zero in ideal profiles.
  std::vector<float> intensity;  // relative return intensity, 0..1
  std::vector<float> true_y_mm;  // the ideal point of the column (ground truth),
  std::vector<float> true_z_mm;  // sensor frame, mm; 0 where true_valid is 0
  std::vector<std::uint8_t> true_valid;

  Pose world_from_sensor = Pose::Identity();
  double time_s = 0.0;
  std::int64_t index = 0;       // profile number in its run

  // Sizes every per-column vector to n and zeroes it.
  void resize(int n);
  int size() const { return static_cast<int>(range_mm.size()); }
  // True when every per-column vector has n entries.
  bool sized(int n) const;
  int valid_count() const;
};

// Ray parameter meaning "no intersection".
inline constexpr float kNoHit = std::numeric_limits<float>::infinity();

// Turns a raw ray distance along column i into the ideal sample: applies the
// maximum hit distance and the depth of field, fills y, z, range, valid and
// cos_incidence (|cos| of the ray/normal angle, clamped to 0..1; 0 when the
// column is invalid). camera_visible is set to valid; a source that tests the
// camera shadow clears it afterwards. Both profile sources call this, so their
// filtering is identical. Inline: the raster calls it for every column.
inline void set_column(const ScannerDesc& desc, const Eigen::Vector3f& direction, int column,
                       float hit_distance_mm, Profile& out, float cos_incidence = 1.0f) {
  const float y = hit_distance_mm * direction.y();
  const float z = hit_distance_mm * direction.z();
  const bool ok = std::isfinite(hit_distance_mm) && hit_distance_mm > 0.0f &&
                  hit_distance_mm <= desc.max_hit_mm && z >= desc.min_range_mm &&
                  z <= desc.max_range_mm;
  out.valid[column] = ok ? 1 : 0;
  out.range_mm[column] = ok ? hit_distance_mm : 0.0f;
  out.y_mm[column] = ok ? y : 0.0f;
  out.z_mm[column] = ok ? z : 0.0f;
  const float c = std::isfinite(cos_incidence) ? std::min(1.0f, std::abs(cos_incidence)) : 0.0f;
  out.cos_incidence[column] = ok ? c : 0.0f;
  out.camera_visible[column] = ok ? 1 : 0;
}

}  // namespace vts
