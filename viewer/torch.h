#pragma once
// The torch the keyboard drives, the sensor mounted on it and the clock the
// sensor scans by. Pure math, no GL, no window.
//
// Tool frame: origin at the TCP (wire tip), z along the torch axis into the
// work, x the travel direction, y = z cross x (viewer/geometry.h).
#include <cstdint>
#include <vector>

#include "sensor/cell.h"
#include "sensor/pose.h"

namespace vts::viewer {

// The sensor runs this far ahead of the torch (the paper: about 50 mm).
inline constexpr double kLookAheadMm = 50.0;

// The viewer's sensor mount for a scanner whose tool_from_laser is left at
// identity (unset): the laser kLookAheadMm ahead of the TCP along travel and
// standoff_mm back along the optical axis, which is parallel to the torch
// axis. With the TCP on the work, the fan crosses the work kLookAheadMm ahead.
Pose default_tool_from_laser(double standoff_mm);

// Distance from the laser origin along the optical axis to the first surface
// at the cell's path start (the centre column of a ray-cast scan); fallback_mm
// if the centre ray hits nothing.
double standoff_at_start(const Cell& cell, double fallback_mm = 100.0);

// Held-key motion for one frame: each component -1, 0 or +1.
struct MotionInput {
  Vec3 translate = Vec3::Zero();  // along tool x, y, z (world x, y, z with world_axes)
  Vec3 rotate = Vec3::Zero();     // about tool x, y, z through the TCP (world axes with world_axes)
  bool any() const { return !translate.isZero() || !rotate.isZero(); }
};

// The torch pose after dt_s of motion at speed_mm_s and turn_deg_s.
Pose move_torch(const Pose& world_from_torch, const MotionInput& input, double speed_mm_s,
                double turn_deg_s, double dt_s, bool world_axes);

// Translation interpolated linearly, rotation by slerp; t in [0, 1].
Pose interpolate(const Pose& a, const Pose& b, double t);

// Simulated time and the sensor's scans: scan k is due at time k / rate_hz.
struct ScanClock {
  double rate_hz = 20.0;
  double time_s = 0.0;
  std::int64_t next_scan = 0;  // index of the next scan due

  struct Due {
    std::int64_t index = 0;
    double time_s = 0.0;
    double fraction = 0.0;  // where in this frame's step: 0 at its start, 1 at its end
  };
  // Advances the clock by dt_s and lists the scans that fall due, at most
  // max_scans: if more would, the clock advances only as far as the last one
  // listed (the simulation then runs slower than real time).
  std::vector<Due> advance(double dt_s, int max_scans);
};

}  // namespace vts::viewer
