// libFuzzer target: sensor/planar_merge.h on meshes decoded from the bytes.
// The bytes build a grid of vertices whose heights come from a small set
// (so that flat regions, folds and near-flat steps are common), the grid's
// triangles each kept, dropped, flipped or doubled, then arbitrary triangles
// over the same vertices; a few vertices may be NaN or huge. Zero-area and
// non-finite triangles are filtered out first, as the raster source does.
// Whatever is merged: no crash or UB, every index inside the positions, no
// output triangle of zero area, no more triangles than went in, and the
// area kept within the tolerance times the input's edge length.
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <vector>

#include <Eigen/Geometry>

#include "sensor/planar_merge.h"

namespace {

void check(bool ok) {
  if (!ok) std::abort();
}

struct Bytes {
  const std::uint8_t* data;
  std::size_t size, at = 0;
  std::uint8_t next() { return at < size ? data[at++] : 0; }
  bool done() const { return at >= size; }
};

Eigen::Vector3d point(const std::vector<float>& p, std::uint32_t v) {
  return {p[3 * std::size_t(v)], p[3 * std::size_t(v) + 1], p[3 * std::size_t(v) + 2]};
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  Bytes in{data, size};
  const int n = 2 + in.next() % 11, m = 2 + in.next() % 11;  // quads across, along
  const std::uint8_t mode = in.next();
  const double tol = mode & 1 ? 1e-4 : std::pow(10.0, -7.0 + (mode >> 1) % 6);
  // Heights: 0, a nudge below or above the tolerance, a fold, a step.
  const double heights[8] = {0.0, 0.0, 0.0, 0.1 * tol, 3.0 * tol, 0.5, -1.0, 0.0};
  std::vector<float> positions;
  for (int j = 0; j <= m; ++j)
    for (int i = 0; i <= n; ++i) {
      const std::uint8_t b = in.next();
      double z = heights[b & 7];
      if ((b >> 3) == 31) z = std::numeric_limits<double>::quiet_NaN();
      if ((b >> 3) == 30) z = 1e30;
      if ((b >> 3) >= 24 && (b >> 3) < 30) z += 0.25 * i;  // a tilted patch
      positions.insert(positions.end(), {float(i), float(j), float(z)});
    }
  const std::uint32_t nv = static_cast<std::uint32_t>(positions.size() / 3);
  std::vector<std::uint32_t> raw;
  for (int j = 0; j < m; ++j)
    for (int i = 0; i < n; ++i) {
      const std::uint32_t a = j * (n + 1) + i, b = a + 1, d = (j + 1) * (n + 1) + i, c = d + 1;
      const std::uint8_t op = in.next();
      for (const auto& t : {std::array<std::uint32_t, 3>{a, b, c}, std::array<std::uint32_t, 3>{a, c, d}}) {
        switch (op % 8) {
          case 0: break;  // dropped
          case 1: raw.insert(raw.end(), {t[0], t[2], t[1]}); break;            // flipped
          case 2: raw.insert(raw.end(), {t[0], t[1], t[2], t[0], t[1], t[2]}); break;  // doubled
          default: raw.insert(raw.end(), {t[0], t[1], t[2]}); break;
        }
      }
    }
  while (!in.done()) raw.insert(raw.end(), {in.next() % nv, in.next() % nv, in.next() % nv});

  // As the raster source: only triangles of non-zero, finite area.
  std::vector<std::uint32_t> indices;
  double area_in = 0.0, perimeter_in = 0.0;
  for (std::size_t t = 0; t + 2 < raw.size(); t += 3) {
    const Eigen::Vector3d a = point(positions, raw[t]), b = point(positions, raw[t + 1]),
                          c = point(positions, raw[t + 2]);
    const double area = 0.5 * (b - a).cross(c - a).norm();
    if (!(area > 0.0) || !std::isfinite(area)) continue;
    indices.insert(indices.end(), {raw[t], raw[t + 1], raw[t + 2]});
    area_in += area;
    perimeter_in += (b - a).norm() + (c - b).norm() + (a - c).norm();
  }
  vts::PlanarMergeStats stats;
  const auto out = vts::merge_planar_regions(positions, indices, tol, &stats);

  check(out.size() % 3 == 0);
  check(out.size() <= indices.size());
  check(stats.triangles_in == indices.size() / 3 && stats.triangles_out == out.size() / 3);
  check(stats.merged_regions <= stats.regions);
  double area_out = 0.0;
  for (std::size_t t = 0; t < out.size(); t += 3) {
    for (int k = 0; k < 3; ++k) check(out[t + k] < positions.size() / 3);
    const Eigen::Vector3d a = point(positions, out[t]);
    const double area = 0.5 * (point(positions, out[t + 1]) - a).cross(point(positions, out[t + 2]) - a).norm();
    check(area > 0.0 && std::isfinite(area));
    area_out += area;
  }
  check(std::abs(area_out - area_in) <= 1e-6 * area_in + 2.0 * tol * perimeter_in + 1e-9);
  return 0;
}
