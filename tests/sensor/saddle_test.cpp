// The pipe saddle (sensor/saddle.h): its mesh against the two cylinders and
// the intersection curve worked out here from their equations, its truth
// against the same formulas, scene-file keys. Scans: tests/render/saddle_scan_test.cpp.
#include <catch2/catch.hpp>

#include <cmath>
#include <map>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "sensor/cell.h"
#include "sensor/mesh_file.h"
#include "sensor/planar_merge.h"
#include "sensor/saddle.h"
#include "sensor/scene_file.h"
#include "sensor/workpiece.h"

using namespace vts;

namespace {

constexpr double kPi = std::numbers::pi;

// The curve from its definition: x = r cos t, y = r sin t, z = sqrt(R^2 - r^2 sin^2 t).
Vec3 curve(double R, double r, double t) {
  return Vec3(r * std::cos(t), r * std::sin(t), std::sqrt(R * R - r * r * std::sin(t) * std::sin(t)));
}

// Sagitta of a chord c on a circle of radius rho.
double sagitta(double rho, double c) { return rho - std::sqrt(rho * rho - 0.25 * c * c); }

struct MeshCheck {
  int on_main = 0, on_branch = 0, on_curve = 0, on_caps = 0, off = 0;
  int main_tris = 0, branch_tris = 0, cap_tris = 0, bad_tris = 0, inward = 0;
  double worst_sag_excess = 0.0;  // how far a triangle's centroid is inside its cylinder beyond the sagitta bound
  double longest_edge = 0.0;
};

// Every vertex on the main cylinder (y^2 + z^2 = R^2, |x| <= L/2), the
// branch (x^2 + y^2 = r^2, z <= H) or an end disc; every triangle on one of
// them, its centroid inside its cylinder by no more than the sagitta of its
// longest edge, its normal outward.
MeshCheck check_mesh(const Mesh& m, const SaddleParams& p) {
  const double R = p.main_radius_mm, r = p.branch_radius_mm, L = p.main_length_mm, H = p.branch_height_mm;
  constexpr double kEps = 2e-4;  // float positions at ~200 mm
  MeshCheck c;
  enum Where { kMain = 1, kBranch = 2, kCapL = 4, kCapR = 8, kTop = 16 };
  std::vector<int> where(m.vertices.size(), 0);
  for (std::size_t i = 0; i < m.vertices.size(); ++i) {
    const Vec3 v = m.vertices[i].cast<double>();
    int w = 0;
    if (std::abs(std::hypot(v.y(), v.z()) - R) < kEps && std::abs(v.x()) <= 0.5 * L + kEps && v.z() >= -R) w |= kMain;
    if (std::abs(std::hypot(v.x(), v.y()) - r) < kEps && v.z() <= H + kEps) w |= kBranch;
    if (std::abs(v.x() + 0.5 * L) < kEps) w |= kCapL;
    if (std::abs(v.x() - 0.5 * L) < kEps) w |= kCapR;
    if (std::abs(v.z() - H) < kEps && std::hypot(v.x(), v.y()) <= r + kEps) w |= kTop;
    where[i] = w;
    if ((w & kMain) && (w & kBranch)) {
      ++c.on_curve;
      // On both cylinders: on the curve, z = sqrt(R^2 - r^2 sin^2 t).
      const double t = std::atan2(v.y(), v.x());
      CHECK((v - curve(R, r, t)).norm() < 4e-4);
    }
    if (w & kMain) ++c.on_main;
    if (w & kBranch) ++c.on_branch;
    if (w & (kCapL | kCapR | kTop)) ++c.on_caps;
    if (!w) ++c.off;
  }
  for (const auto& t : m.triangles) {
    const int common = where[t[0]] & where[t[1]] & where[t[2]];
    const Vec3 a = m.vertices[t[0]].cast<double>(), b = m.vertices[t[1]].cast<double>(),
               d = m.vertices[t[2]].cast<double>();
    const Vec3 centroid = (a + b + d) / 3.0;
    const Vec3 n = (b - a).cross(d - a);
    const double edge = std::max({(b - a).norm(), (d - b).norm(), (a - d).norm()});
    if (common & (kMain | kBranch)) c.longest_edge = std::max(c.longest_edge, edge);  // not the fanned discs
    Vec3 outward;
    double inside = 0.0, bound = 0.0;
    if (common & kMain) {
      ++c.main_tris;
      outward = Vec3(0.0, centroid.y(), centroid.z());
      inside = R - outward.norm();
      bound = sagitta(R, edge);
    } else if (common & kBranch) {
      ++c.branch_tris;
      outward = Vec3(centroid.x(), centroid.y(), 0.0);
      inside = r - outward.norm();
      bound = sagitta(r, edge);
    } else if (common & (kCapL | kCapR | kTop)) {
      ++c.cap_tris;
      outward = (common & kCapL) ? Vec3(-1, 0, 0) : (common & kCapR) ? Vec3(1, 0, 0) : Vec3(0, 0, 1);
    } else {
      ++c.bad_tris;
      continue;
    }
    if (n.dot(outward) <= 0.0) ++c.inward;
    c.worst_sag_excess = std::max(c.worst_sag_excess, std::max(-inside, inside - bound) - kEps);
  }
  return c;
}

}  // namespace

TEST_CASE("saddle: the mesh lies on the two cylinders within the sagitta, closed, outward", "[saddle][mesh]") {
  for (const double cell_mm : {4.0, 2.0}) {
    INFO("cell_mm " << cell_mm);
    SaddleParams p;
    p.cell_mm = cell_mm;
    REQUIRE(validate(p).empty());
    const Mesh m = saddle_mesh(p);
    CHECK(mesh_edge_stats(m).closed());
    const MeshCheck c = check_mesh(m, p);
    CHECK(c.off == 0);
    CHECK(c.bad_tris == 0);
    CHECK(c.inward == 0);
    CHECK(c.worst_sag_excess <= 0.0);
    CHECK(c.on_curve > 2.0 * kPi * p.branch_radius_mm / cell_mm);  // the curve at least as fine as the lattice
    CHECK(c.main_tris + c.branch_tris + c.cap_tris == static_cast<int>(m.triangle_count()));
    // The pitch holds: no edge of the pipes' walls much longer than a cell
    // (the O-grid's corners stretch a little), and the estimate is near the count.
    CHECK(c.longest_edge < 2.0 * cell_mm);
    CHECK(std::abs(saddle_triangle_estimate(p) / m.triangle_count() - 1.0) < 0.1);
    WARN("saddle cell_mm " << cell_mm << ": " << m.triangle_count() << " triangles, " << c.on_curve
                           << " vertices on the curve, longest edge " << c.longest_edge << " mm");
  }
}

TEST_CASE("saddle: nothing to merge but the end discs", "[saddle][mesh]") {
  SaddleParams p;
  const Mesh m = saddle_mesh(p, pose_from_xyz_rpy({10, -20, 30}, {5, -3, 20}));
  std::vector<float> positions;
  for (const auto& v : m.vertices) positions.insert(positions.end(), {v.x(), v.y(), v.z()});
  std::vector<std::uint32_t> indices;
  for (const auto& t : m.triangles) indices.insert(indices.end(), t.begin(), t.end());
  PlanarMergeStats stats;
  merge_planar_regions(positions, indices, planar_merge_tolerance(positions), &stats);
  // Only the three end discs are flat regions; a fan of a disc gives back
  // about as many triangles as it had.
  CHECK(stats.regions == 3);
  CHECK(stats.triangles_out + 10 >= stats.triangles_in);
}

TEST_CASE("saddle: truth against the curve's formula", "[saddle][truth]") {
  SaddleParams p;
  const double R = p.main_radius_mm, r = p.branch_radius_mm;
  // The crown and the flank, by hand.
  const SaddlePoint crown = saddle_point(p, 0.0);
  CHECK((crown.root - Vec3(r, 0, R)).norm() < 1e-12);
  CHECK((crown.tangent - Vec3(0, 1, 0)).norm() < 1e-12);
  CHECK(crown.open_angle_deg == Approx(90.0));
  CHECK((crown.bisector - Vec3(1, 0, 1).normalized()).norm() < 1e-12);
  const SaddlePoint flank = saddle_point(p, 0.5 * kPi);
  CHECK((flank.root - Vec3(0, r, std::sqrt(R * R - r * r))).norm() < 1e-12);
  CHECK((flank.tangent - Vec3(-1, 0, 0)).norm() < 1e-12);
  CHECK(flank.open_angle_deg == Approx(90.0 + std::asin(r / R) * 180.0 / kPi));  // 120 for r = R / 2
  CHECK((flank.branch_side - Vec3(0, 0, 1)).norm() < 1e-12);
  CHECK((flank.main_side - Vec3(0, std::sqrt(R * R - r * r) / R, -r / R)).norm() < 1e-12);
  // Anywhere: the root on the formula, the tangent its finite difference,
  // the two sides square to the tangent and in their surfaces.
  std::mt19937_64 rng(24);
  std::uniform_real_distribution<double> u(0.0, 2.0 * kPi);
  for (int k = 0; k < 200; ++k) {
    const double t = u(rng);
    const SaddlePoint q = saddle_point(p, t);
    CHECK((q.root - curve(R, r, t)).norm() < 1e-9);
    const Vec3 fd = (curve(R, r, t + 1e-6) - curve(R, r, t - 1e-6)).normalized();
    CHECK((q.tangent - fd).norm() < 1e-6);
    CHECK(std::abs(q.main_side.dot(q.tangent)) < 1e-12);
    CHECK(std::abs(q.branch_side.dot(q.tangent)) < 1e-12);
    CHECK(std::abs(q.main_side.dot(Vec3(0, q.root.y(), q.root.z()))) < 1e-9);   // tangent to y^2 + z^2 = R^2
    CHECK(std::abs(q.branch_side.dot(Vec3(q.root.x(), q.root.y(), 0))) < 1e-9);  // tangent to x^2 + y^2 = r^2
    CHECK(q.open_angle_deg >= 90.0 - 1e-9);
    CHECK(q.open_angle_deg <= 120.0 + 1e-9);
    CHECK(std::abs(q.bisector.dot(q.main_side) - q.bisector.dot(q.branch_side)) < 1e-12);
  }
}

TEST_CASE("saddle: the truth nearest a laser plane", "[saddle][truth]") {
  SaddleParams p;
  const Pose world_from_saddle = pose_from_xyz_rpy({100, -50, 20}, {10, 20, -30});
  std::mt19937_64 rng(19);
  std::uniform_real_distribution<double> u(0.0, 2.0 * kPi), jitter(-3.0, 3.0);
  for (int k = 0; k < 50; ++k) {
    const double t = u(rng);
    const Pose s = saddle_sensor_pose(p, world_from_saddle, t, 80.0 + 40.0 * std::abs(jitter(rng)));
    const auto q = saddle_truth_in_plane(p, world_from_saddle, s);
    REQUIRE(q);
    CHECK((q->root - world_from_saddle * curve(p.main_radius_mm, p.branch_radius_mm, t)).norm() < 1e-6);
    // The sensor looks at it along the bisector, its laser plane square to the seam.
    const Vec3 in_sensor = s.inverse() * q->root;
    CHECK(std::abs(in_sensor.x()) < 1e-6);
    CHECK(std::abs(in_sensor.y()) < 1e-6);
    CHECK((s.linear().col(2) + q->bisector).norm() < 1e-9);
    CHECK(std::abs(s.linear().col(0).dot(q->tangent)) == Approx(1.0));
    // Moved along its travel, the plane cuts the curve where x_sensor = 0.
    Pose moved = s;
    moved.translation() += jitter(rng) * s.linear().col(0);
    const auto m = saddle_truth_in_plane(p, world_from_saddle, moved);
    REQUIRE(m);
    CHECK(std::abs((moved.inverse() * m->root).x()) < 1e-6);
  }
  // A plane that misses the pipes' curve.
  const Pose far = pose_from_xyz_rpy({1000, 0, 0}, {0, 0, 0});
  CHECK_FALSE(saddle_truth_in_plane(p, Pose::Identity(), far));
}

TEST_CASE("saddle: bad parameters are refused by name", "[saddle]") {
  SaddleParams p;
  CHECK(validate(p).empty());
  p.branch_radius_mm = 90.0;
  CHECK(validate(p).rfind("branch_radius_mm = 90: must be below 0.866 * main_radius_mm = 86.6025", 0) == 0);
  p = {};
  p.cell_mm = -1.0;
  CHECK(validate(p) == "cell_mm = -1: must be > 0");
  p.cell_mm = 20.0;
  CHECK(validate(p) == "cell_mm = 20: must be at most branch_radius_mm / 4 = 12.5");
  p.cell_mm = 0.05;
  CHECK(validate(p) == "cell_mm = 0.05: too small: the mesh would have more than 20000000 triangles");
  p = {};
  p.main_length_mm = 100.0;
  CHECK(validate(p).rfind("main_length_mm = 100: must be at least 140", 0) == 0);
  p = {};
  p.branch_height_mm = 105.0;
  CHECK(validate(p).rfind("branch_height_mm = 105: must be at least main_radius_mm + 2 * cell_mm = 108", 0) == 0);
  p = {};
  p.main_radius_mm = std::nan("");
  CHECK(validate(p) == "main_radius_mm = nan: must be a finite number");
}

TEST_CASE("saddle cells: built in, scene round trip, scene keys checked", "[saddle][cells][scene]") {
  const Cell c = *builtin_cell("saddle");
  REQUIRE(c.workpieces.size() == 1);
  const Workpiece& w = c.workpieces.front();
  REQUIRE(w.saddle);
  CHECK(w.is_mesh());
  CHECK(w.has_joint());
  CHECK(w.type == JointType::Fillet);
  // The default path looks at the flank t = 3 pi / 2 from 100 mm at its middle profile.
  const Pose mid = c.path.pose_at(c.path.profiles / 2);
  const auto q = saddle_truth_in_plane(*w.saddle, w.world_from_joint, mid);
  REQUIRE(q);
  CHECK((q->root - curve(100.0, 50.0, 1.5 * kPi)).norm() < 1e-9);
  CHECK((mid.translation() - q->root).norm() == Approx(100.0));
  CHECK(c.path.direction.isApprox(Vec3::UnitX()));
  CHECK(builtin_cell_names(CellSet::Small).size() + 2 == builtin_cell_names().size());

  // Scene text: the keys, a pose; written back the same.
  const std::string text =
      "workpieces:\n"
      "  - saddle:\n"
      "      main_radius_mm: 80\n"
      "      branch_radius_mm: 30\n"
      "      main_length_mm: 300\n"
      "      branch_height_mm: 150\n"
      "      cell_mm: 3\n"
      "    pose:\n"
      "      position_mm: [1, 2, 3]\n"
      "      rpy_deg: [0, 0, 90]\n";
  const Cell s = parse_scene(text, "saddle.yaml");
  REQUIRE(s.workpieces.front().saddle);
  const SaddleParams& sp = *s.workpieces.front().saddle;
  CHECK(sp.main_radius_mm == 80.0);
  CHECK(sp.branch_radius_mm == 30.0);
  CHECK(sp.main_length_mm == 300.0);
  CHECK(sp.branch_height_mm == 150.0);
  CHECK(sp.cell_mm == 3.0);
  // No path given: the saddle's own default path (no start needed, unlike a mesh file).
  CHECK(s.path.direction.isApprox(s.workpieces.front().world_from_joint.linear() * Vec3::UnitX()));
  const Cell back = parse_scene(scene_to_yaml(s), "back.yaml");
  REQUIRE(back.workpieces.front().saddle);
  CHECK(back.workpieces.front().saddle->branch_radius_mm == 30.0);
  CHECK(back.workpieces.front().world_from_joint.isApprox(s.workpieces.front().world_from_joint, 1e-12));
  CHECK(back.path.start.isApprox(s.path.start, 1e-12));
  CHECK(back.mesh().triangle_count() == s.mesh().triangle_count());

  const auto error = [](const std::string& t) {
    try {
      parse_scene(t, "bad.yaml");
    } catch (const SceneError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string bad_radius = error("workpieces:\n  - saddle:\n      branch_radius_mm: 95\n");
  CHECK(bad_radius.find("bad.yaml:3:") != std::string::npos);
  CHECK(bad_radius.find("branch_radius_mm = 95: must be below") != std::string::npos);
  const std::string unknown = error("workpieces:\n  - saddle:\n      radius_mm: 95\n");
  CHECK(unknown.find("radius_mm") != std::string::npos);
  CHECK(unknown.find("bad.yaml:3:") != std::string::npos);
  const std::string not_number = error("workpieces:\n  - saddle:\n      cell_mm: fine\n");
  CHECK(not_number.find("cell_mm") != std::string::npos);
}

TEST_CASE("saddle-1m: about a million triangles on the cylinders", "[saddle][cells][mesh]") {
  const Cell c = *builtin_cell("saddle-1m");
  const Mesh m = c.mesh();
  WARN("saddle-1m: " << m.triangle_count() << " triangles, " << m.vertices.size() << " vertices");
  CHECK(m.triangle_count() > 950'000);
  CHECK(m.triangle_count() < 1'100'000);
  CHECK(builtin_cell_description("saddle-1m").find(std::to_string(m.triangle_count())) != std::string::npos);
  CHECK(mesh_edge_stats(m).closed());
  const MeshCheck k = check_mesh(m, *c.workpieces.front().saddle);
  CHECK(k.off == 0);
  CHECK(k.bad_tris == 0);
  CHECK(k.inward == 0);
  CHECK(k.worst_sag_excess <= 0.0);
}
