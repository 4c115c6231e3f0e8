#include "sensor/profile.h"

#include <algorithm>
#include <cmath>

namespace vts {

void Profile::resize(int n) {
  y_mm.assign(n, 0.0f);
  z_mm.assign(n, 0.0f);
  range_mm.assign(n, 0.0f);
  valid.assign(n, 0);
}

int Profile::valid_count() const {
  return static_cast<int>(std::count(valid.begin(), valid.end(), std::uint8_t{1}));
}

void set_column(const ScannerDesc& desc, const Eigen::Vector3f& direction, int column,
                float hit_distance_mm, Profile& out) {
  const float y = hit_distance_mm * direction.y();
  const float z = hit_distance_mm * direction.z();
  const bool ok = std::isfinite(hit_distance_mm) && hit_distance_mm > 0.0f &&
                  hit_distance_mm <= desc.max_hit_mm && z >= desc.min_range_mm &&
                  z <= desc.max_range_mm;
  out.valid[column] = ok ? 1 : 0;
  out.range_mm[column] = ok ? hit_distance_mm : 0.0f;
  out.y_mm[column] = ok ? y : 0.0f;
  out.z_mm[column] = ok ? z : 0.0f;
}

}  // namespace vts
