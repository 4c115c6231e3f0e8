#pragma once
// A recording made by formula, without random numbers, so that a file
// written from it can be checked value by value: the version-1 EXR fixture in
// tests/data (written by the version-1 writer, tests/data/README.md) and the
// version-2 round trip. Every value is basic arithmetic on doubles rounded
// once (or a square root), the same on every IEEE machine.
#include <cmath>
#include <cstdint>

#include "sensor/pose.h"
#include "sensor/profile.h"
#include "sensor/profile_exr.h"

namespace vts::test {

inline constexpr int kFixturePoints = 32;
inline constexpr int kFixtureRows = 40;

// With the reference and the error model: every channel a file can have.
inline ProfileFileInfo fixture_info(int points = kFixturePoints, int rows = kFixtureRows) {
  ProfileFileInfo info;
  info.scanner.name = "fixture scanner";
  info.scanner.points = points;
  info.scanner.fan_deg = 0.1 + 0.2;
  info.scanner.rate_hz = 299.999;
  info.scanner.tool_from_laser = pose_from_quat(Vec3(50.0, -1e-7, 100.0 / 7.0), Eigen::Quaterniond(0.9, 0.1, -0.3, 0.2));
  info.scanner.ideal = false;
  info.scene_name = "fixture.yaml";
  info.scene_text = "# a scene text, not parsed: caf\xC3\xA9\nname: fixture\n";
  info.profiles = rows;
  info.has_reference = true;
  info.error_model = true;
  info.seed = 7;
  return info;
}

inline bool fixture_valid(int row, int i, int shift) { return (i * 7 + row * 3 + shift) % 5 != 0; }
inline double fixture_y(int row, int i) { return -60.0 + 3.75 * i + row / 64.0 + 1.0 / 3.0; }
inline double fixture_z(int row, int i) { return 250.0 + (i % 7) * 0.3125 - row * 0.1 + 1.0 / 7.0; }

// Row `row` of the main channels (shift 0) or of the reference (shift 1,
// other points valid, y and z moved by half a millimetre).
inline Profile fixture_profile(int points, int row, int shift = 0) {
  Profile p;
  p.resize(points);
  const double d = 0.5 * shift;
  for (int i = 0; i < points; ++i) {
    if (shift == 0) {
      p.true_valid[i] = fixture_valid(row, i, 0) || i % 4 == 0;
      p.true_y_mm[i] = p.true_valid[i] ? static_cast<float>(fixture_y(row, i) + 0.01) : 0.0f;
      p.true_z_mm[i] = p.true_valid[i] ? static_cast<float>(fixture_z(row, i) - 0.02) : 0.0f;
    }
    if (!fixture_valid(row, i, shift)) continue;
    p.valid[i] = 1;
    p.y_mm[i] = static_cast<float>(fixture_y(row, i) + d);
    p.z_mm[i] = static_cast<float>(fixture_z(row, i) + d);
    p.range_mm[i] = static_cast<float>(std::sqrt(double(p.y_mm[i]) * p.y_mm[i] + double(p.z_mm[i]) * p.z_mm[i]));
    if (shift == 0) p.intensity[i] = static_cast<float>(((i + 2 * row) % 11) / 10.0);
  }
  p.world_from_sensor = pose_from_quat(Vec3(100.0 + row * 1.1, -20.0 / 3.0, 300.0 + row / 7.0),
                                       Eigen::Quaterniond(1.0, 0.01 * row, -0.02, 0.003 * row));
  p.time_s = 12345.0 + row / 299.999 + 1e-9 * row;
  p.index = row;
  return p;
}

}  // namespace vts::test
