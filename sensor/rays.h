#pragma once
// The one definition of the column rays, shared by the raster emulator and the
// ray-cast reference so both cast exactly the same rays.
//
// Sensor frame. Columns sample the laser line like a camera row, not at equal
// angles: column i (0 <= i < N) looks through (0, t_i, 1) with
//   t_i = tan(fan/2) * (2 * (i + 0.5) / N - 1),
// which is exactly the centre of pixel i of an N-wide perspective image whose
// horizontal half-angle is fan/2. Directions are unit vectors stored as float
// (the precision both GL and Embree consume).
#include <vector>

#include <Eigen/Core>

#include "sensor/scanner.h"

namespace vts {

double column_tan(const ScannerDesc& desc, int column);
std::vector<Eigen::Vector3f> column_directions(const ScannerDesc& desc);

}  // namespace vts
