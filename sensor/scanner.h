#pragma once
// The scanner description: fixed for a run (MuJoCo's mjModel to ScanState's
// mjData). Sensor frame: origin at the laser, z along the optical axis (range),
// y along the laser line, x = y cross z (the travel direction).
#include <string>

#include "sensor/pose.h"

namespace vts {

struct ScannerDesc {
  std::string name = "mspot";   // preset name, informational
  double fan_deg = 40.0;        // full opening angle of the laser fan, in the y-z plane
  int points = 512;             // columns per profile, 16..4096
  double min_range_mm = 20.0;   // depth of field: nearest measurable z
  double max_range_mm = 1000.0; // depth of field: farthest measurable z
  double max_hit_mm = 1200.0;   // longest ray distance that counts as a hit
  double rate_hz = 20.0;        // profile rate
  // Where the laser (sensor frame) sits on the torch: tool_from_laser.
  // Default: 50 mm ahead of the TCP along travel, 100 mm up along the tool axis.
  Pose tool_from_laser = Pose::Identity();
};

inline constexpr int kMinPoints = 16;
inline constexpr int kMaxPoints = 4096;

// Empty when the description is usable, else a message naming the first bad
// field and its value, e.g. "points = 8: must be between 16 and 4096".
std::string validate(const ScannerDesc& desc);

}  // namespace vts
