#include "sensor/rays.h"

#include <cmath>
#include <numbers>

namespace vts {

double column_tan(const ScannerDesc& desc, int column) {
  const double half = 0.5 * desc.fan_deg * std::numbers::pi / 180.0;
  const double n = desc.points;
  return std::tan(half) * (2.0 * (column + 0.5) / n - 1.0);
}

std::vector<Eigen::Vector3f> column_directions(const ScannerDesc& desc) {
  std::vector<Eigen::Vector3f> dirs(desc.points);
  for (int i = 0; i < desc.points; ++i)
    dirs[i] = Eigen::Vector3d(0.0, column_tan(desc, i), 1.0).normalized().cast<float>();
  return dirs;
}

}  // namespace vts
