#pragma once
// Synthetic profiles for the tracker's unit tests: polylines in the sensor
// frame sampled along rays from the origin, the way the sensor's columns
// sample (tangents evenly spaced across a 40-degree fan), worked out here
// without any tracker code.
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <utility>
#include <vector>

#include "tracker/types.h"

namespace synth {

using vts::tracker::Vec2;

struct Profile {
  std::vector<float> y, z;
  std::vector<std::uint8_t> valid;
  vts::tracker::ProfileView view() const { return {y, z, valid}; }
  int size() const { return static_cast<int>(y.size()); }
  void invalidate(int first, int last) {
    for (int i = first; i <= last; ++i) {
      valid[i] = 0;
      y[i] = z[i] = 0.0f;
    }
  }
};

// A surface piece: the segment from a to b (sensor frame, mm).
using Piece = std::pair<Vec2, Vec2>;

inline double column_tan(int i, int n, double half_fan_deg = 20.0) {
  return std::tan(half_fan_deg * std::numbers::pi / 180.0) * (2.0 * (i + 0.5) / n - 1.0);
}

// Each column's ray (t, 1) from the origin hits the nearest piece.
inline Profile sample(const std::vector<Piece>& pieces, int n = 512, double half_fan_deg = 20.0) {
  Profile p;
  p.y.assign(n, 0.0f);
  p.z.assign(n, 0.0f);
  p.valid.assign(n, 0);
  for (int i = 0; i < n; ++i) {
    const Vec2 d(column_tan(i, n, half_fan_deg), 1.0);
    double best = std::numeric_limits<double>::infinity();
    for (const auto& [a, b] : pieces) {
      // s d = a + u (b - a)  ->  [d, a - b] (s, u) = a
      const Vec2 e = a - b;
      const double det = d.x() * e.y() - d.y() * e.x();
      if (std::abs(det) < 1e-15) continue;
      const double s = (a.x() * e.y() - a.y() * e.x()) / det;
      const double u = (d.x() * a.y() - d.y() * a.x()) / det;
      if (s > 0.0 && u >= 0.0 && u <= 1.0 && s < best) best = s;
    }
    if (std::isfinite(best)) {
      p.y[i] = static_cast<float>(best * d.x());
      p.z[i] = static_cast<float>(best * d.y());
      p.valid[i] = 1;
    }
  }
  return p;
}

// Point i moved by d along its ray (d > 0: away from the sensor).
inline void along_ray(Profile& p, int i, double d) {
  const double r = std::hypot(p.y[i], p.z[i]);
  p.y[i] = static_cast<float>(p.y[i] * (r + d) / r);
  p.z[i] = static_cast<float>(p.z[i] * (r + d) / r);
}

// Range noise of standard deviation sigma on every valid point, along its
// ray: a sum of three uniforms from a fixed LCG (the same on every platform).
inline void add_noise(Profile& p, double sigma, std::uint32_t seed) {
  std::uint32_t x = seed * 2654435761u + 12345u;
  auto u = [&] {
    x = x * 1664525u + 1013904223u;
    return (x >> 8) * (1.0 / 16777216.0) - 0.5;
  };
  for (int i = 0; i < p.size(); ++i) {
    const double n = (u() + u() + u()) * 2.0 * sigma;
    if (p.valid[i]) along_ray(p, i, n);
  }
}

inline Vec2 dir_deg(double deg) {
  const double r = deg * std::numbers::pi / 180.0;
  return Vec2(std::cos(r), std::sin(r));
}

// A 90-degree-style inside corner opening towards the sensor: two plates
// from `root`, the first going to the sensor's left (-y) and the second to
// its right (+y), each `len` mm long, at `angle_deg` between them, the
// bisector pointing at the sensor (-z).
inline std::vector<Piece> valley(const Vec2& root, double angle_deg, double len = 80.0) {
  const double half = 0.5 * angle_deg;
  const Vec2 left = dir_deg(-90.0 - half), right = dir_deg(-90.0 + half);
  return {{root + len * left, root}, {root, root + len * right}};
}

// A closed 60-degree v-groove root at (0.4, 120) (the bevels' lines meet
// there), its plate tops at 110 on both sides: the root, the bevels' top
// edges and the section.
struct ClosedVGroove {
  Vec2 root{0.4, 120};
  Vec2 lt = root + Vec2(-10.0 * std::tan(std::numbers::pi / 6), -10);
  Vec2 rt = root + Vec2(10.0 * std::tan(std::numbers::pi / 6), -10);
  std::vector<Piece> pieces{{Vec2(-80, 110), lt}, {lt, root}, {root, rt}, {rt, Vec2(80, 110)}};
};

// An outside corner (ridge) pointing at the sensor, inside angle angle_deg.
inline std::vector<Piece> ridge(const Vec2& apex, double angle_deg, double len = 80.0) {
  const double half = 0.5 * angle_deg;
  const Vec2 left = dir_deg(90.0 + half), right = dir_deg(90.0 - half);
  return {{apex + len * left, apex}, {apex, apex + len * right}};
}

}  // namespace synth
