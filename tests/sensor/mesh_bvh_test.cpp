// sensor/mesh_bvh.h against brute force over every triangle: the laser-plane
// query (crossing_planes) finds exactly the triangles a direct test finds,
// for any number of parallel planes; the region query (inside_planes, in
// float) keeps at least every triangle the exact double test keeps.
#include <catch2/catch.hpp>

#include <algorithm>
#include <random>
#include <set>
#include <vector>

#include <Eigen/Geometry>

#include "sensor/mesh_bvh.h"

using namespace vts;

namespace {

// A seeded soup of small triangles in a 200 mm cube.
MeshBvh random_soup(int triangles, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> at(-100.0f, 100.0f), off(-3.0f, 3.0f);
  std::vector<float> positions;
  std::vector<std::uint32_t> indices;
  for (int t = 0; t < triangles; ++t) {
    const float cx = at(rng), cy = at(rng), cz = at(rng);
    for (int v = 0; v < 3; ++v) {
      indices.push_back(static_cast<std::uint32_t>(positions.size() / 3));
      positions.insert(positions.end(), {cx + off(rng), cy + off(rng), cz + off(rng)});
    }
  }
  return MeshBvh(positions, indices);
}

// A closed box [0, sx] x [0, sy] x [0, sz], each face cut into a grid of
// cells of about `cell` mm, two triangles each, wound outwards: leaves of
// the hierarchy hold triangles of one face, so whole nodes face away.
MeshBvh gridded_box(double sx, double sy, double sz, double cell) {
  std::vector<float> positions;
  std::vector<std::uint32_t> indices;
  const Eigen::Vector3d size(sx, sy, sz);
  for (int axis = 0; axis < 3; ++axis) {
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    const int nu = std::max(1, static_cast<int>(size[u] / cell)), nv = std::max(1, static_cast<int>(size[v] / cell));
    for (int side = 0; side < 2; ++side) {
      const auto base = static_cast<std::uint32_t>(positions.size() / 3);
      for (int j = 0; j <= nv; ++j)
        for (int i = 0; i <= nu; ++i) {
          Eigen::Vector3d p = Eigen::Vector3d::Zero();
          p[axis] = side * size[axis];
          p[u] = size[u] * i / nu;
          p[v] = size[v] * j / nv;
          positions.insert(positions.end(), {float(p.x()), float(p.y()), float(p.z())});
        }
      for (int j = 0; j < nv; ++j)
        for (int i = 0; i < nu; ++i) {
          const std::uint32_t a = base + j * (nu + 1) + i, b = a + 1, c = a + nu + 1, d = c + 1;
          // u x v points along +axis: counter-clockwise seen from outside on side 1.
          if (side == 1) indices.insert(indices.end(), {a, b, d, a, d, c});
          else indices.insert(indices.end(), {a, d, b, a, c, d});
        }
    }
  }
  return MeshBvh(positions, indices);
}

// How far the front side of entry e's triangle ((b - a) x (c - a), corners
// as given) faces the box at best: the largest signed distance of a box
// corner from its plane; and whether it is a sliver (area small against its
// edges), whose margin in the queries grows as its area shrinks.
std::pair<double, bool> facing_margin(const MeshBvh& bvh, std::uint32_t e, const MeshBvh::Box3& box) {
  const auto& c = bvh.corners(e);
  const Eigen::Vector3d a(c[0], c[1], c[2]), b(c[3], c[4], c[5]), cc(c[6], c[7], c[8]);
  const Eigen::Vector3d nrm = (b - a).cross(cc - a);
  const double edges = (b - a).norm() + (cc - a).norm();
  const bool sliver = nrm.norm() < 0.05 * edges * edges;
  double best = -1e300;
  for (int k = 0; k < 8; ++k) {
    const Eigen::Vector3d p(k & 1 ? box.hi.x() : box.lo.x(), k & 2 ? box.hi.y() : box.lo.y(),
                            k & 4 ? box.hi.z() : box.lo.z());
    best = std::max(best, nrm.dot(p - a) / nrm.norm());  // signed distance of the nearest-facing point
  }
  return {best, sliver};
}

}  // namespace

TEST_CASE("mesh bvh: crossing_planes finds what a direct test finds for 1 to 150 planes", "[bvh]") {
  const MeshBvh bvh = random_soup(20000, 3);
  const Eigen::Vector3d n = Eigen::Vector3d(0.3, -0.5, 0.8).normalized();
  const Eigen::Vector3d box_lo = Eigen::Vector3d::Constant(-1e3), box_hi = Eigen::Vector3d::Constant(1e3);
  const double tol = 0.01;
  for (int planes : {1, 16, 64, 65, 150}) {
    std::vector<double> d(planes);
    for (int k = 0; k < planes; ++k) d[k] = -90.0 + 170.0 * k / std::max(1, planes - 1) + (k % 3) * 0.1;
    std::reverse(d.begin(), d.end());  // not in increasing order
    std::vector<std::vector<std::uint32_t>> out(planes);
    bvh.crossing_planes(n, d, box_lo, box_hi, tol, out);
    for (int k = 0; k < planes; ++k) {
      std::set<std::uint32_t> expected;
      for (std::uint32_t e = 0; e < bvh.triangle_count(); ++e) {
        const auto& c = bvh.corners(e);
        double lo = 1e300, hi = -1e300;
        for (int v = 0; v < 3; ++v) {
          const double s = n[0] * c[3 * v] + n[1] * c[3 * v + 1] + n[2] * c[3 * v + 2];
          lo = std::min(lo, s);
          hi = std::max(hi, s);
        }
        if (lo <= d[k] + tol && hi >= d[k] - tol) expected.insert(e);
      }
      INFO(planes << " planes, plane " << k);
      CHECK(std::set<std::uint32_t>(out[k].begin(), out[k].end()) == expected);
      CHECK(out[k].size() == expected.size());  // each once
    }
  }
}

TEST_CASE("mesh bvh: crossing_planes with half-spaces to keep drops exactly the triangles outside one", "[bvh]") {
  const MeshBvh bvh = random_soup(20000, 6);
  const Eigen::Vector3d n = Eigen::Vector3d(0.3, -0.5, 0.8).normalized();
  const Eigen::Vector3d box_lo = Eigen::Vector3d::Constant(-1e3), box_hi = Eigen::Vector3d::Constant(1e3);
  const double tol = 0.01;
  std::mt19937 rng(7);
  std::normal_distribution<double> dir(0.0, 1.0);
  std::uniform_real_distribution<double> offset(-40.0, 40.0);
  for (int trial = 0; trial < 12; ++trial) {
    // 0 to 4 half-spaces, like the two sides of a laser fan (or none).
    std::vector<Eigen::Vector4d> keep;
    for (int k = 0; k < trial % 5; ++k) {
      const Eigen::Vector3d h = Eigen::Vector3d(dir(rng), dir(rng), dir(rng)).normalized();
      keep.emplace_back(h.x(), h.y(), h.z(), offset(rng));
    }
    const int planes = 1 + 5 * trial;
    std::vector<double> d(planes);
    for (int k = 0; k < planes; ++k) d[k] = -80.0 + 160.0 * k / std::max(1, planes - 1);
    std::vector<std::vector<std::uint32_t>> out(planes);
    bvh.crossing_planes(n, d, box_lo, box_hi, tol, out, nullptr, keep);
    std::size_t found = 0;
    for (int k = 0; k < planes; ++k) {
      std::set<std::uint32_t> expected;
      for (std::uint32_t e = 0; e < bvh.triangle_count(); ++e) {
        const auto& c = bvh.corners(e);
        double lo = 1e300, hi = -1e300;
        bool outside_one = false;
        for (int v = 0; v < 3; ++v) {
          const double s = n[0] * c[3 * v] + n[1] * c[3 * v + 1] + n[2] * c[3 * v + 2];
          lo = std::min(lo, s);
          hi = std::max(hi, s);
        }
        for (const Eigen::Vector4d& h : keep) {
          bool all_out = true;
          for (int v = 0; v < 3; ++v)
            all_out = all_out && h[0] * c[3 * v] + h[1] * c[3 * v + 1] + h[2] * c[3 * v + 2] + h[3] < 0.0;
          outside_one = outside_one || all_out;
        }
        if (lo <= d[k] + tol && hi >= d[k] - tol && !outside_one) expected.insert(e);
      }
      INFO(keep.size() << " half-spaces, " << planes << " planes, plane " << k);
      CHECK(std::set<std::uint32_t>(out[k].begin(), out[k].end()) == expected);
      CHECK(out[k].size() == expected.size());
      found += expected.size();
    }
    CHECK(found > 0);
  }
}

TEST_CASE("mesh bvh: inside_planes keeps every triangle the exact test keeps", "[bvh]") {
  const MeshBvh bvh = random_soup(20000, 4);
  std::mt19937 rng(5);
  std::normal_distribution<double> dir(0.0, 1.0);
  std::uniform_real_distribution<double> offset(-20.0, 60.0);
  for (int trial = 0; trial < 20; ++trial) {
    std::vector<Eigen::Vector4d> planes;
    for (int k = 0; k < 1 + trial % 8; ++k) {
      const Eigen::Vector3d nv = Eigen::Vector3d(dir(rng), dir(rng), dir(rng)).normalized();
      planes.emplace_back(nv.x(), nv.y(), nv.z(), offset(rng));
    }
    std::vector<std::uint32_t> out;
    bvh.inside_planes(planes, out);
    const std::set<std::uint32_t> got(out.begin(), out.end());
    int expected = 0;
    for (std::uint32_t e = 0; e < bvh.triangle_count(); ++e) {
      const auto& c = bvh.corners(e);
      bool outside_one = false;
      for (const Eigen::Vector4d& p : planes) {
        bool all_out = true;
        for (int v = 0; v < 3; ++v)
          all_out = all_out && p[0] * c[3 * v] + p[1] * c[3 * v + 1] + p[2] * c[3 * v + 2] + p[3] < 0.0;
        outside_one = outside_one || all_out;
      }
      if (outside_one) continue;
      ++expected;
      INFO("trial " << trial << ", entry " << e);
      CHECK(got.count(e) == 1);
    }
    CHECK(got.size() == out.size());  // each once
    CHECK(static_cast<int>(out.size()) >= expected);
  }
}

// With a facing box, both queries keep every triangle whose front side
// ((b - a) x (c - a), corners as given) faces some point of the box (checked
// over the box's corners: n . (p - a) is linear in p), and drop those turned
// away from all of it: every one by more than 2 mm, and nearly all by more
// than 0.01 mm (the queries keep a margin for the corners' float rounding,
// a fraction of a millimetre on these 6 mm triangles 250 mm from the origin;
// slivers, whose margin grows as their area shrinks, are left out).
TEST_CASE("mesh bvh: a facing box drops the triangles turned away from it, and only those", "[bvh]") {
  const MeshBvh bvh = random_soup(20000, 6);
  // Slivers (area small against the edges) turn with the rounding of their
  // corners: the queries' margin grows for them; not checked.
  auto facing_margin = [&](std::uint32_t e, const MeshBvh::Box3& box) { return ::facing_margin(bvh, e, box); };
  const MeshBvh::Box3 boxes[] = {
      {Eigen::Vector3d(0.0, 0.0, 150.0), Eigen::Vector3d(0.0, 0.0, 150.0)},    // a point (a camera)
      {Eigen::Vector3d(-5.0, 20.0, 120.0), Eigen::Vector3d(3.0, 20.0, 120.0)},  // a short path of laser origins
      {Eigen::Vector3d(-40.0, -10.0, -10.0), Eigen::Vector3d(40.0, 10.0, 10.0)},  // inside the soup
  };
  int dropped = 0, kept = 0, away = 0, away_dropped = 0;
  for (const MeshBvh::Box3& box : boxes) {
    // Laser planes through the soup.
    const Eigen::Vector3d n = Eigen::Vector3d(1.0, 0.2, -0.1).normalized();
    std::vector<double> d = {-30.0, -10.0, 0.0, 25.0};
    std::vector<std::vector<std::uint32_t>> all(d.size()), faced(d.size());
    bvh.crossing_planes(n, d, Eigen::Vector3d::Constant(-1e3), Eigen::Vector3d::Constant(1e3), 0.01, all);
    bvh.crossing_planes(n, d, Eigen::Vector3d::Constant(-1e3), Eigen::Vector3d::Constant(1e3), 0.01, faced, &box);
    for (std::size_t k = 0; k < d.size(); ++k) {
      const std::set<std::uint32_t> got(faced[k].begin(), faced[k].end());
      CHECK(got.size() == faced[k].size());
      for (std::uint32_t e : faced[k]) CHECK(std::count(all[k].begin(), all[k].end(), e) == 1);
      for (std::uint32_t e : all[k]) {
        const auto [m, sliver] = facing_margin(e, box);
        INFO("plane " << k << ", entry " << e << ", facing by " << m << " mm");
        if (m > 0.0) CHECK(got.count(e) == 1);
        if (sliver) continue;
        if (m < -2.0) CHECK(got.count(e) == 0);
        if (m < -0.01) ++away;
        if (m < -0.01 && !got.count(e)) ++away_dropped;
        (got.count(e) ? kept : dropped) += 1;
      }
    }
    // A region: the half space z > -20.
    const std::vector<Eigen::Vector4d> region = {Eigen::Vector4d(0.0, 0.0, 1.0, 20.0)};
    std::vector<std::uint32_t> all_in, faced_in;
    bvh.inside_planes(region, all_in);
    bvh.inside_planes(region, faced_in, &box);
    const std::set<std::uint32_t> got(faced_in.begin(), faced_in.end());
    const std::set<std::uint32_t> every(all_in.begin(), all_in.end());
    for (std::uint32_t e : faced_in) CHECK(every.count(e) == 1);
    for (std::uint32_t e : all_in) {
      const auto [m, sliver] = facing_margin(e, box);
      INFO("region, entry " << e << ", facing by " << m << " mm");
      if (m > 0.0) CHECK(got.count(e) == 1);
      if (sliver) continue;
      if (m < -2.0) CHECK(got.count(e) == 0);
      if (m < -0.01) ++away;
      if (m < -0.01 && !got.count(e)) ++away_dropped;
    }
  }
  CHECK(away_dropped >= 0.95 * away);
  // The soup faces every way: both outcomes occur.
  CHECK(dropped > 1000);
  CHECK(kept > 1000);
}

// On a finely meshed closed box the hierarchy drops whole nodes of faces
// turned away from the facing box (their normals bounded per node): still
// every triangle facing some point of the box is kept, and every one turned
// away from all of it by more than 0.01 mm is dropped.
TEST_CASE("mesh bvh: a facing box drops whole nodes of a meshed box's far faces, and only those", "[bvh]") {
  const MeshBvh bvh = gridded_box(120.0, 60.0, 6.0, 0.8);
  const MeshBvh::Box3 boxes[] = {
      {Eigen::Vector3d(50.0, 30.0, 90.0), Eigen::Vector3d(50.0, 30.0, 90.0)},   // a camera over the top
      {Eigen::Vector3d(20.0, 70.0, 60.0), Eigen::Vector3d(28.0, 70.0, 60.0)},   // laser origins, top and side
      {Eigen::Vector3d(-30.0, 10.0, -40.0), Eigen::Vector3d(-30.0, 14.0, -40.0)},  // below, off an end
  };
  const Eigen::Vector3d n = Eigen::Vector3d(1.0, 0.1, 0.05).normalized();
  const std::vector<double> d = {3.0, 17.3, 40.0, 40.5, 41.0, 99.9};
  const std::vector<Eigen::Vector4d> region = {Eigen::Vector4d(0.0, -1.0, 0.0, 35.0),
                                               Eigen::Vector4d(1.0, 0.0, 0.0, -10.0)};  // y <= 35, x >= 10
  int kept = 0, dropped = 0;
  auto check = [&](std::uint32_t e, bool got, const MeshBvh::Box3& box) {
    const auto [m, sliver] = facing_margin(bvh, e, box);
    INFO("entry " << e << ", facing by " << m << " mm");
    REQUIRE_FALSE(sliver);
    if (m > 0.0) CHECK(got);
    if (m < -0.01) CHECK_FALSE(got);
    (got ? kept : dropped) += 1;
  };
  for (const MeshBvh::Box3& box : boxes) {
    std::vector<std::vector<std::uint32_t>> all(d.size()), faced(d.size());
    bvh.crossing_planes(n, d, Eigen::Vector3d::Constant(-1e3), Eigen::Vector3d::Constant(1e3), 0.01, all);
    bvh.crossing_planes(n, d, Eigen::Vector3d::Constant(-1e3), Eigen::Vector3d::Constant(1e3), 0.01, faced, &box);
    for (std::size_t k = 0; k < d.size(); ++k) {
      const std::set<std::uint32_t> got(faced[k].begin(), faced[k].end());
      CHECK(got.size() == faced[k].size());
      for (std::uint32_t e : faced[k]) CHECK(std::count(all[k].begin(), all[k].end(), e) == 1);
      for (std::uint32_t e : all[k]) check(e, got.count(e) == 1, box);
    }
    std::vector<std::uint32_t> all_in, faced_in;
    bvh.inside_planes(region, all_in);
    bvh.inside_planes(region, faced_in, &box);
    const std::set<std::uint32_t> got(faced_in.begin(), faced_in.end());
    const std::set<std::uint32_t> every(all_in.begin(), all_in.end());
    for (std::uint32_t e : faced_in) CHECK(every.count(e) == 1);
    for (std::uint32_t e : all_in) check(e, got.count(e) == 1, box);
  }
  CHECK(kept > 1000);
  CHECK(dropped > 1000);
}
