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

}  // namespace vts
