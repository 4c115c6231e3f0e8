// sensor/planar_merge.h: flat regions become the few triangles their outline
// needs, and nothing else changes. Truth: hand counts (a box is 12
// triangles), the area and volume of the input, brute-force ray casts
// against the input mesh, and the edge pairing of a watertight mesh.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <random>
#include <set>
#include <tuple>
#include <vector>

#include <Eigen/Geometry>

#include "sensor/cell.h"
#include "sensor/planar_merge.h"
#include "sensor/workpiece.h"

using namespace vts;

namespace {

struct Soup {
  std::vector<float> positions;
  std::vector<std::uint32_t> indices;
  std::uint32_t add(const Eigen::Vector3d& p) {
    positions.insert(positions.end(), {float(p.x()), float(p.y()), float(p.z())});
    return static_cast<std::uint32_t>(positions.size() / 3 - 1);
  }
  Eigen::Vector3d at(std::uint32_t v) const {
    return {positions[3 * v], positions[3 * v + 1], positions[3 * v + 2]};
  }
  std::size_t triangles() const { return indices.size() / 3; }
};

// An n x m grid of unit quads, corner o, edges along u and v (counter-
// clockwise about u x v); skip(i, j) leaves quad (i, j) out; lift(i, j)
// offsets vertex (i, j) along u x v.
template <class Skip, class Lift>
void grid(Soup& s, int n, int m, const Eigen::Vector3d& o, const Eigen::Vector3d& u, const Eigen::Vector3d& v,
          Skip skip, Lift lift) {
  std::vector<std::uint32_t> id((n + 1) * (m + 1));
  const Eigen::Vector3d w = u.cross(v).normalized();
  for (int j = 0; j <= m; ++j)
    for (int i = 0; i <= n; ++i) id[j * (n + 1) + i] = s.add(o + i * u + j * v + lift(i, j) * w);
  for (int j = 0; j < m; ++j)
    for (int i = 0; i < n; ++i) {
      if (skip(i, j)) continue;
      const std::uint32_t a = id[j * (n + 1) + i], b = a + 1, d = id[(j + 1) * (n + 1) + i], c = d + 1;
      s.indices.insert(s.indices.end(), {a, b, c, a, c, d});
    }
}

const auto kNoSkip = [](int, int) { return false; };
const auto kFlat = [](int, int) { return 0.0; };

double area(const Soup& s, const std::vector<std::uint32_t>& idx) {
  double total = 0.0;
  for (std::size_t t = 0; t < idx.size(); t += 3)
    total += 0.5 * (s.at(idx[t + 1]) - s.at(idx[t])).cross(s.at(idx[t + 2]) - s.at(idx[t])).norm();
  return total;
}

double volume(const Soup& s, const std::vector<std::uint32_t>& idx) {
  double total = 0.0;
  for (std::size_t t = 0; t < idx.size(); t += 3)
    total += s.at(idx[t]).dot(s.at(idx[t + 1]).cross(s.at(idx[t + 2]))) / 6.0;
  return total;
}

// Directed edges without their reverse (a closed mesh has none; a
// T-junction leaves some).
std::multiset<std::pair<std::uint32_t, std::uint32_t>> open_edges(const std::vector<std::uint32_t>& idx) {
  std::multiset<std::pair<std::uint32_t, std::uint32_t>> edges, open;
  for (std::size_t t = 0; t < idx.size(); t += 3)
    for (int k = 0; k < 3; ++k) edges.insert({idx[t + k], idx[t + (k + 1) % 3]});
  for (const auto& [a, b] : edges)
    if (!edges.count({b, a})) open.insert({a, b});
  return open;
}

// Nearest hit along o + t d (t > 0) over the triangles, brute force.
double nearest(const Soup& s, const std::vector<std::uint32_t>& idx, const Eigen::Vector3d& o,
               const Eigen::Vector3d& d) {
  double best = INFINITY;
  for (std::size_t t = 0; t < idx.size(); t += 3) {
    const Eigen::Vector3d a = s.at(idx[t]), e1 = s.at(idx[t + 1]) - a, e2 = s.at(idx[t + 2]) - a;
    const Eigen::Vector3d p = d.cross(e2);
    const double det = e1.dot(p);
    if (std::abs(det) < 1e-14) continue;
    const Eigen::Vector3d tv = o - a;
    const double u = tv.dot(p) / det;
    const Eigen::Vector3d q = tv.cross(e1);
    const double v = d.dot(q) / det, h = e2.dot(q) / det;
    if (u >= 0 && v >= 0 && u + v <= 1 && h > 0) best = std::min(best, h);
  }
  return best;
}

Soup box(double cell_mm) {
  Plate plate{{{0.0, 0.0}, {20.0, 0.0}, {20.0, 6.0}, {0.0, 6.0}}, 0.0, 30.0};
  const Pose pose = Pose(Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized())) *
                    Eigen::Translation3d(5.0, -40.0, 120.0);
  const Mesh m = plate_mesh(plate, 1000.0, pose, cell_mm);
  Soup s;
  for (const auto& v : m.vertices) s.add(v.cast<double>());
  for (const auto& t : m.triangles) s.indices.insert(s.indices.end(), t.begin(), t.end());
  return s;
}

}  // namespace

TEST_CASE("planar merge: a finely meshed box becomes 12 triangles, the same solid", "[merge]") {
  Soup s = box(0.5);
  REQUIRE(s.triangles() > 5000);
  REQUIRE(open_edges(s.indices).empty());
  const std::size_t vertices = s.positions.size();
  PlanarMergeStats stats;
  const auto out = merge_planar_regions(s.positions, s.indices, planar_merge_tolerance(s.positions), &stats);
  CHECK(out.size() / 3 == 12);
  CHECK(stats.regions == 6);
  CHECK(stats.merged_regions == 6);
  CHECK(stats.triangles_in == s.triangles());
  CHECK(stats.triangles_out == 12);
  CHECK(s.positions.size() == vertices);  // every face fanned from a corner
  CHECK(open_edges(out).empty());         // still closed, consistently wound
  CHECK(volume(s, out) == Approx(20.0 * 6.0 * 30.0).epsilon(1e-6));
  CHECK(area(s, out) == Approx(2 * (20.0 * 6.0 + 20.0 * 30.0 + 6.0 * 30.0)).epsilon(1e-6));
}

TEST_CASE("planar merge: rays hit the merged box where they hit the input", "[merge]") {
  Soup s = box(1.0);
  const auto in = s.indices;
  const auto out = merge_planar_regions(s.positions, s.indices, planar_merge_tolerance(s.positions));
  REQUIRE(out.size() / 3 == 12);
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (std::uint32_t v = 0; v < s.positions.size() / 3; ++v) centre += s.at(v);
  centre /= static_cast<double>(s.positions.size() / 3);
  std::mt19937 rng(11);
  std::normal_distribution<double> g(0.0, 1.0);
  std::uniform_real_distribution<double> aim(-18.0, 18.0);
  int hits = 0;
  for (int r = 0; r < 1500; ++r) {
    const Eigen::Vector3d dir = Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized();
    const Eigen::Vector3d target = centre + Eigen::Vector3d(aim(rng), aim(rng), aim(rng));
    const Eigen::Vector3d o = target - 100.0 * dir;
    const double a = nearest(s, in, o, dir), b = nearest(s, out, o, dir);
    REQUIRE(std::isfinite(a) == std::isfinite(b));
    if (std::isfinite(a)) {
      ++hits;
      REQUIRE(std::abs(a - b) < 1e-4);
    }
  }
  CHECK(hits > 300);
}

TEST_CASE("planar merge: a flat grid is one quad, flatness within the tolerance", "[merge]") {
  const double tol = 1e-3;
  SECTION("flat") {
    Soup s;
    grid(s, 8, 6, {1, 2, 3}, {1, 0, 0}, {0, 1, 0}, kNoSkip, kFlat);
    const auto out = merge_planar_regions(s.positions, s.indices, tol);
    CHECK(out.size() / 3 == 2);
    CHECK(area(s, out) == Approx(48.0));
    // The open border is the rectangle's four sides.
    CHECK(open_edges(out).size() == 4);
  }
  SECTION("one vertex off the plane by a tenth of the tolerance") {
    Soup s;
    grid(s, 8, 6, {1, 2, 3}, {1, 0, 0}, {0, 1, 0}, kNoSkip,
         [&](int i, int j) { return i == 3 && j == 3 ? 0.1 * tol : 0.0; });
    CHECK(merge_planar_regions(s.positions, s.indices, tol).size() / 3 == 2);
  }
  SECTION("one vertex off the plane by ten times the tolerance: a hole in the flat region") {
    Soup s;
    grid(s, 8, 6, {1, 2, 3}, {1, 0, 0}, {0, 1, 0}, kNoSkip,
         [&](int i, int j) { return i == 3 && j == 3 ? 10.0 * tol : 0.0; });
    PlanarMergeStats stats;
    const auto out = merge_planar_regions(s.positions, s.indices, tol, &stats);
    CHECK(out.size() == s.indices.size());
    CHECK(stats.merged_regions == 0);
  }
}

TEST_CASE("planar merge: non-convex, holed and curved regions stay as they are", "[merge]") {
  Soup s;
  SECTION("L-shaped") {
    grid(s, 6, 6, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, [](int i, int j) { return i >= 3 && j >= 3; }, kFlat);
  }
  SECTION("with a hole") {
    grid(s, 6, 6, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, [](int i, int j) { return i == 2 && j == 3; }, kFlat);
  }
  SECTION("a doubly curved patch, radius 500 mm, quads 2 mm") {
    grid(s, 10, 10, {0, 0, 0}, {2, 0, 0}, {0, 2, 0}, kNoSkip,
         [](int i, int j) { return (4.0 * i * i + 4.0 * j * j) / 1000.0; });
  }
  const auto in = s.indices;
  const auto out = merge_planar_regions(s.positions, s.indices, planar_merge_tolerance(s.positions));
  std::multiset<std::vector<std::uint32_t>> a, b;
  for (std::size_t t = 0; t < in.size(); t += 3) a.insert({in[t], in[t + 1], in[t + 2]});
  for (std::size_t t = 0; t < out.size(); t += 3) b.insert({out[t], out[t + 1], out[t + 2]});
  CHECK(a == b);
}

TEST_CASE("planar merge: a cylinder meshed in strips along its axis is one quad per strip", "[merge]") {
  // Every strip between two neighbouring generators is flat, however finely
  // it is cut along the axis: 10 strips of 10 quads -> 10 x 2 triangles.
  Soup s;
  grid(s, 10, 10, {0, 0, 0}, {2, 0, 0}, {0, 2, 0}, kNoSkip, kFlat);
  for (std::size_t v = 0; v < s.positions.size() / 3; ++v) {
    const double y = s.positions[3 * v + 1];
    s.positions[3 * v + 1] = float(500.0 * std::sin(y / 500.0));
    s.positions[3 * v + 2] = float(500.0 * (1.0 - std::cos(y / 500.0)));
  }
  const auto in = s.indices;
  const auto out = merge_planar_regions(s.positions, s.indices, planar_merge_tolerance(s.positions));
  CHECK(out.size() / 3 == 20);
  CHECK(area(s, out) == Approx(area(s, in)).epsilon(1e-6));
  CHECK(open_edges(out).size() == 2 * 10 + 2);  // the long sides cut at each strip, the ends whole
}

TEST_CASE("planar merge: a face next to one left as it was keeps their shared vertices", "[merge]") {
  // A flat 4 x 4 square (z = 0) and, below its edge y = 0, an L-shaped wall
  // (y = 0) that stays triangle for triangle: the square must keep the
  // wall's vertices on their shared edge (no T-junction), so it is fanned
  // from its centre: 4 corners + 3 edge vertices = 7 triangles.
  Soup s;
  grid(s, 4, 4, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, kNoSkip, kFlat);
  const std::size_t square = s.triangles();
  // Wall: vertex (i, j) at (i, 0, -j) for i, j in 0..4; wound so that its
  // top edge runs opposite to the square's bottom edge.
  grid(s, 4, 4, {0, 0, 0}, {0, 0, -1}, {1, 0, 0}, [](int i, int j) { return i >= 2 && j >= 2; }, kFlat);
  // The two grids have separate vertices along y = z = 0: weld them.
  std::map<std::tuple<float, float, float>, std::uint32_t> first;
  for (auto& v : s.indices) {
    const auto key = std::make_tuple(s.positions[3 * v], s.positions[3 * v + 1], s.positions[3 * v + 2]);
    v = first.emplace(key, v).first->second;
  }
  const std::size_t vertices = s.positions.size() / 3;
  const auto in = s.indices;
  PlanarMergeStats stats;
  const auto out = merge_planar_regions(s.positions, s.indices, 1e-4, &stats);
  CHECK(stats.merged_regions == 1);
  CHECK(out.size() / 3 == 7 + (s.triangles() - square));
  CHECK(s.positions.size() / 3 == vertices + 1);  // the fan's centre
  CHECK(area(s, out) == Approx(area(s, in)));
  // The open edges are the outer border, now with the square's three long
  // sides as single edges; none lies on the shared edge y = z = 0.
  const auto open = open_edges(out);
  for (const auto& [a, b] : open) {
    const bool on_shared = s.at(a).y() == 0 && s.at(a).z() == 0 && s.at(b).y() == 0 && s.at(b).z() == 0;
    CHECK_FALSE(on_shared);
  }
  CHECK(open.size() == open_edges(in).size() - 3 * 3);
}

TEST_CASE("planar merge: the built-in cells' plates are prisms of one polygon per face", "[merge]") {
  // A prism over a convex k-gon has k rectangular sides (2 triangles each)
  // and two k-gon caps (k - 2 each): 12 for a box, 16 for the v-groove's
  // bevelled pentagons, however finely the plates are meshed.
  for (const char* name : {"fillet", "lap", "vgroove", "plate", "fillet-1m"}) {
    const Cell cell = *builtin_cell(name);
    std::size_t expected = 0;
    for (const Plate& plate : cell.workpieces.front().plates) {
      const std::size_t k = plate.section_yz.size();
      expected += 2 * k + 2 * (k - 2);
    }
    const Mesh m = cell.mesh();
    Soup s;
    for (const auto& v : m.vertices) s.add(v.cast<double>());
    for (const auto& t : m.triangles) s.indices.insert(s.indices.end(), t.begin(), t.end());
    const auto out = merge_planar_regions(s.positions, s.indices, planar_merge_tolerance(s.positions));
    INFO(name << ": " << m.triangle_count() << " triangles");
    CHECK(out.size() / 3 == expected);
    CHECK(open_edges(out).empty());
    CHECK(volume(s, out) == Approx(volume(s, s.indices)).epsilon(1e-7));
  }
}

TEST_CASE("planar merge: damaged flat meshes keep their area and get no degenerate triangle", "[merge]") {
  // Seeded damage to a folded, finely meshed sheet (two flat halves at an
  // angle): triangles dropped, duplicated or flipped, vertices nudged by
  // about the tolerance, a vertex index shared by far-apart triangles.
  // Whatever is merged or kept, the area stays and no triangle is flat.
  for (std::uint32_t seed = 1; seed <= 60; ++seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    Soup s;
    grid(s, 12, 6, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, kNoSkip, kFlat);
    grid(s, 12, 6, {0, 6, 0}, {1, 0, 0}, {0, 0.6, 0.8}, kNoSkip, kFlat);
    const double tol = 1e-4;
    for (std::size_t v = 0; v < s.positions.size(); ++v)
      if (unit(rng) < 0.05) s.positions[v] += float((unit(rng) - 0.5) * 4.0 * tol);
    std::vector<std::uint32_t> damaged;
    for (std::size_t t = 0; t < s.indices.size(); t += 3) {
      const double r = unit(rng);
      std::uint32_t a = s.indices[t], b = s.indices[t + 1], c = s.indices[t + 2];
      if (r < 0.05) continue;                       // dropped
      if (r < 0.08) std::swap(b, c);                // flipped
      damaged.insert(damaged.end(), {a, b, c});
      if (r > 0.97) damaged.insert(damaged.end(), {a, b, c});  // duplicated
    }
    if (unit(rng) < 0.5) damaged[1] = damaged[damaged.size() - 2];  // a stray shared vertex
    // Only triangles of non-zero area go in (as the raster source filters).
    std::vector<std::uint32_t> in;
    for (std::size_t t = 0; t < damaged.size(); t += 3) {
      const auto a = s.at(damaged[t]);
      if ((s.at(damaged[t + 1]) - a).cross(s.at(damaged[t + 2]) - a).norm() > 0.0)
        in.insert(in.end(), {damaged[t], damaged[t + 1], damaged[t + 2]});
    }
    const auto out = merge_planar_regions(s.positions, in, tol);
    INFO("seed " << seed << ": " << in.size() / 3 << " -> " << out.size() / 3 << " triangles");
    REQUIRE(out.size() % 3 == 0);
    CHECK(out.size() <= in.size());
    CHECK(area(s, out) == Approx(area(s, in)).epsilon(1e-4));
    for (std::size_t t = 0; t < out.size(); t += 3) {
      REQUIRE(out[t + 2] < s.positions.size() / 3);
      const auto a = s.at(out[t]);
      CHECK((s.at(out[t + 1]) - a).cross(s.at(out[t + 2]) - a).norm() > 1e-9);
    }
  }
}
