#include "sensor/planar_merge.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>
#include <utility>

#include <Eigen/Geometry>

namespace vts {

namespace {

constexpr std::uint32_t kNone = ~0u;

using Vec3 = Eigen::Vector3d;

}  // namespace

double planar_merge_tolerance(std::span<const float> positions) {
  float largest = 0.0f;
  for (const float c : positions)
    if (std::isfinite(c)) largest = std::max(largest, std::abs(c));
  return 16.0 * std::numeric_limits<float>::epsilon() * std::max(1.0f, largest);
}

std::vector<std::uint32_t> merge_planar_regions(std::vector<float>& positions,
                                                std::span<const std::uint32_t> indices,
                                                double tol, PlanarMergeStats* stats) {
  const std::size_t nt = indices.size() / 3;
  const std::size_t nv = positions.size() / 3;
  // (Reads the vertices as given; fan centres are appended only at the end.)
  auto point = [&](std::uint32_t v) {
    return Vec3(positions[3 * std::size_t(v)], positions[3 * std::size_t(v) + 1],
                positions[3 * std::size_t(v) + 2]);
  };
  PlanarMergeStats local;
  PlanarMergeStats& st = stats ? *stats : local;
  st = {};
  st.triangles_in = nt;

  // Across each edge (3 t + k, from corner k to k + 1): the triangle on the
  // other side when exactly two use it, once in each direction; else kNone.
  std::vector<std::uint32_t> across(3 * nt, kNone);
  {
    std::vector<std::pair<std::uint64_t, std::uint32_t>> edges(3 * nt);
    for (std::size_t h = 0; h < 3 * nt; ++h) {
      const std::uint32_t a = indices[h], b = indices[h - h % 3 + (h % 3 + 1) % 3];
      edges[h] = {std::uint64_t(std::min(a, b)) << 32 | std::max(a, b), static_cast<std::uint32_t>(h)};
    }
    std::sort(edges.begin(), edges.end());
    for (std::size_t i = 0; i < edges.size();) {
      std::size_t j = i + 1;
      while (j < edges.size() && edges[j].first == edges[i].first) ++j;
      if (j == i + 2) {
        const std::uint32_t h0 = edges[i].second, h1 = edges[i + 1].second;
        if (indices[h0] != indices[h1]) {  // opposite directions
          across[h0] = h1 / 3;
          across[h1] = h0 / 3;
        }
      }
      i = j;
    }
  }

  // Regions: flood fill from each unassigned triangle over shared edges,
  // keeping triangles whose corners lie within tol of the seed's plane and
  // that face the same way.
  std::vector<std::uint32_t> region(nt, kNone);
  std::vector<std::uint32_t> order;  // triangles grouped by region
  std::vector<std::uint32_t> region_begin;
  std::vector<Vec3> region_normal;
  order.reserve(nt);
  for (std::uint32_t seed = 0; seed < nt; ++seed) {
    if (region[seed] != kNone) continue;
    const std::uint32_t r = static_cast<std::uint32_t>(region_begin.size());
    const Vec3 a = point(indices[3 * seed]);
    const Vec3 n = (point(indices[3 * seed + 1]) - a).cross(point(indices[3 * seed + 2]) - a).normalized();
    const double w = n.dot(a);
    region_begin.push_back(static_cast<std::uint32_t>(order.size()));
    region_normal.push_back(n);
    region[seed] = r;
    order.push_back(seed);
    for (std::size_t q = order.size() - 1; q < order.size(); ++q) {
      const std::uint32_t t = order[q];
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t u = across[3 * t + k];
        if (u == kNone || region[u] != kNone) continue;
        const Vec3 p0 = point(indices[3 * u]), p1 = point(indices[3 * u + 1]), p2 = point(indices[3 * u + 2]);
        if (std::abs(n.dot(p0) - w) > tol || std::abs(n.dot(p1) - w) > tol || std::abs(n.dot(p2) - w) > tol)
          continue;
        if (!((p1 - p0).cross(p2 - p0).dot(n) > 0.0)) continue;
        region[u] = r;
        order.push_back(u);
      }
    }
  }
  const std::size_t nr = region_begin.size();
  region_begin.push_back(static_cast<std::uint32_t>(order.size()));
  auto size_of = [&](std::size_t r) { return region_begin[r + 1] - region_begin[r]; };

  // Per vertex: the regions meeting at it (the first two; `many` if more).
  std::vector<std::uint32_t> reg1(nv, kNone), reg2(nv, kNone);
  std::vector<std::uint8_t> many(nv, 0), bent(nv, 0);
  for (std::size_t t = 0; t < nt; ++t)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t v = indices[3 * t + k], r = region[t];
      if (reg1[v] == kNone || reg1[v] == r) reg1[v] = r;
      else if (reg2[v] == kNone || reg2[v] == r) reg2[v] = r;
      else many[v] = 1;
    }

  // Each region's border as one loop, in winding order (kNone: not a disk).
  std::vector<std::uint8_t> candidate(nr, 0);
  std::vector<std::uint32_t> loop_begin(nr + 1, 0), loops;
  std::vector<std::uint32_t> next(nv, kNone);
  for (std::size_t r = 0; r < nr; ++r) {
    loop_begin[r] = static_cast<std::uint32_t>(loops.size());
    if (size_of(r) < 3) continue;
    ++st.regions;
    std::size_t border = 0;
    bool ok = true;
    std::uint32_t start = kNone;
    std::vector<std::uint32_t> touched;
    for (std::uint32_t q = region_begin[r]; q < region_begin[r + 1]; ++q) {
      const std::uint32_t t = order[q];
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t u = across[3 * t + k];
        if (u != kNone && region[u] == r) continue;
        const std::uint32_t a = indices[3 * t + k], b = indices[3 * t + (k + 1) % 3];
        if (next[a] != kNone) ok = false;  // two border edges leave a: pinched
        next[a] = b;
        touched.push_back(a);
        start = a;
        ++border;
      }
    }
    if (ok && start != kNone) {
      std::size_t steps = 0;
      std::uint32_t v = start;
      do {
        loops.push_back(v);
        v = next[v];
      } while (v != kNone && v != start && ++steps <= border);
      ok = v == start && loops.size() - loop_begin[r] == border;
    }
    for (const std::uint32_t a : touched) next[a] = kNone;
    if (!ok) {
      loops.resize(loop_begin[r]);
      continue;
    }
    candidate[r] = 1;
    // Where the border does not run straight through a vertex, no region
    // may drop it.
    const std::uint32_t* lp = &loops[loop_begin[r]];
    for (std::size_t i = 0; i < border; ++i) {
      const Vec3 u = point(lp[(i + border - 1) % border]), v = point(lp[i]), x = point(lp[(i + 1) % border]);
      const Vec3 ux = x - u;
      const double len = ux.norm();
      const bool straight = len > 0.0 && (v - u).cross(ux).norm() <= tol * len && (v - u).dot(ux) > 0.0 &&
                            (x - v).dot(ux) > 0.0;
      if (!straight) bent[lp[i]] = 1;
    }
  }
  loop_begin[nr] = static_cast<std::uint32_t>(loops.size());

  // A candidate stays one while its outline, without the droppable vertices,
  // is a strictly convex polygon of the region's area. Dropping depends on
  // the neighbours staying candidates: repeat until nothing changes.
  auto droppable = [&](std::uint32_t v) {
    if (many[v] || bent[v]) return false;
    if (reg1[v] != kNone && !candidate[reg1[v]]) return false;
    if (reg2[v] != kNone && !candidate[reg2[v]]) return false;
    return true;
  };
  std::vector<std::uint32_t> kept;
  auto outline = [&](std::size_t r) {  // the kept loop vertices into `kept`
    kept.clear();
    for (std::uint32_t i = loop_begin[r]; i < loop_begin[r + 1]; ++i)
      if (!droppable(loops[i])) kept.push_back(loops[i]);
  };
  // Strictly convex but for kept vertices the border runs straight through
  // (within tol), at least three corners, fewer triangles than the region,
  // and the region's area.
  std::size_t corners = 0;
  auto convex_and_same_area = [&](std::size_t r) {
    const std::size_t m = kept.size();
    corners = 0;
    if (m < 3) return false;
    const Vec3& n = region_normal[r];
    const Vec3 o = point(kept[0]);
    double poly_area = 0.0, perimeter = 0.0, turning = 0.0;
    for (std::size_t i = 0; i < m; ++i) {
      const Vec3 u = point(kept[(i + m - 1) % m]), v = point(kept[i]), x = point(kept[(i + 1) % m]);
      // (u, v, x) turns left about n when (x - u) x (v - u) . n < 0; its
      // size over |x - u| is v's distance from the line u x.
      const Vec3 ux = x - u;
      const double len = ux.norm();
      if (!(len > 0.0)) return false;
      const double left = -ux.cross(v - u).dot(n);
      if (left > tol * len) {
        ++corners;
      } else if (!(std::abs(left) <= tol * len && (v - u).dot(ux) > 0.0 && (x - v).dot(ux) > 0.0)) {
        return false;  // turns right, or doubles back
      }
      poly_area += 0.5 * (v - o).cross(x - o).dot(n);
      perimeter += (x - v).norm();
      turning += std::atan2((v - u).cross(x - v).dot(n), (v - u).dot(x - v));
    }
    if (corners < 3) return false;
    // Turning left everywhere, once around: a star that winds twice (a
    // region of overlapping triangles can have that outline) turns 4 pi.
    if (!(turning < 3.0 * std::numbers::pi)) return false;
    // Worth it only with fewer triangles than the region has (a fan from a
    // corner needs m - 2, one from the centroid m).
    if ((corners == m ? m - 2 : m) >= size_of(r)) return false;
    double area = 0.0;
    for (std::uint32_t q = region_begin[r]; q < region_begin[r + 1]; ++q) {
      const std::uint32_t t = order[q];
      const Vec3 a = point(indices[3 * t]);
      area += 0.5 * (point(indices[3 * t + 1]) - a).cross(point(indices[3 * t + 2]) - a).norm();
    }
    return std::abs(poly_area - area) <= 1e-9 * area + 2.0 * tol * perimeter;
  };
  for (bool changed = true; changed;) {
    changed = false;
    for (std::size_t r = 0; r < nr; ++r) {
      if (!candidate[r]) continue;
      outline(r);
      if (!convex_and_same_area(r)) {
        candidate[r] = 0;
        changed = true;
      }
    }
  }

  std::vector<std::uint32_t> out;
  out.reserve(indices.size());
  for (std::size_t r = 0; r < nr; ++r) {
    if (candidate[r]) {
      ++st.merged_regions;
      outline(r);
      convex_and_same_area(r);  // counts the corners
      const std::size_t m = kept.size();
      if (corners == m) {  // a fan from the first corner
        for (std::size_t i = 1; i + 1 < m; ++i) out.insert(out.end(), {kept[0], kept[i], kept[i + 1]});
        continue;
      }
      // Vertices kept on straight runs (shared with a region left as it
      // was): a fan from the centroid of the vertices, strictly inside, so
      // every border piece stays an edge and no triangle is degenerate.
      Vec3 c = Vec3::Zero();
      for (const std::uint32_t v : kept) c += point(v);
      c /= static_cast<double>(m);
      const std::uint32_t centre = static_cast<std::uint32_t>(positions.size() / 3);
      positions.insert(positions.end(), {float(c.x()), float(c.y()), float(c.z())});
      for (std::size_t i = 0; i < m; ++i) out.insert(out.end(), {centre, kept[i], kept[(i + 1) % m]});
      continue;
    }
    for (std::uint32_t q = region_begin[r]; q < region_begin[r + 1]; ++q) {
      const std::uint32_t t = order[q];
      out.insert(out.end(), {indices[3 * t], indices[3 * t + 1], indices[3 * t + 2]});
    }
  }
  st.triangles_out = out.size() / 3;
  return out;
}

}  // namespace vts
