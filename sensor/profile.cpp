#include "sensor/profile.h"

#include <algorithm>
#include <cmath>

namespace vts {

void Profile::resize(int n) {
  y_mm.assign(n, 0.0f);
  z_mm.assign(n, 0.0f);
  range_mm.assign(n, 0.0f);
  valid.assign(n, 0);
  cos_incidence.assign(n, 0.0f);
  camera_visible.assign(n, 0);
  intensity.assign(n, 0.0f);
  true_y_mm.assign(n, 0.0f);
  true_z_mm.assign(n, 0.0f);
  true_valid.assign(n, 0);
}

bool Profile::sized(int n) const {
  const auto s = static_cast<std::size_t>(n);
  return y_mm.size() == s && z_mm.size() == s && range_mm.size() == s && valid.size() == s &&
         cos_incidence.size() == s && camera_visible.size() == s && intensity.size() == s &&
         true_y_mm.size() == s && true_z_mm.size() == s && true_valid.size() == s;
}

int Profile::valid_count() const {
  return static_cast<int>(std::count(valid.begin(), valid.end(), std::uint8_t{1}));
}

void set_column(const ScannerDesc& desc, const Eigen::Vector3f& direction, int column,
                float hit_distance_mm, Profile& out, float cos_incidence) {
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
