#include <catch2/catch.hpp>

#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>

#include "sensor/cell.h"
#include "sensor/mesh_file.h"
#include "sensor/workpiece.h"

using namespace vts;

namespace {
constexpr double kDeg = std::numbers::pi / 180.0;

// True if the triangle lies in one of the planes and its winding gives that plane's outward normal.
bool on_outward_face(const Mesh& m, const std::array<std::uint32_t, 3>& t,
                     const std::vector<std::pair<Vec3, double>>& planes) {
  const Vec3 a = m.vertices[t[0]].cast<double>(), b = m.vertices[t[1]].cast<double>(),
             c = m.vertices[t[2]].cast<double>();
  const Vec3 n = (b - a).cross(c - a).normalized();
  for (const auto& [pn, d] : planes)
    if (pn.dot(n) > 1.0 - 1e-5 && std::abs(pn.dot(a) - d) < 1e-3 && std::abs(pn.dot(b) - d) < 1e-3 &&
        std::abs(pn.dot(c) - d) < 1e-3)
      return true;
  return false;
}
}  // namespace

TEST_CASE("every joint's mesh triangles lie on the plates' analytic faces and wind outward", "[geometry]") {
  for (JointType type : {JointType::Fillet, JointType::Corner, JointType::Lap, JointType::Butt,
                         JointType::VGroove, JointType::Plate}) {
    const Pose pose = pose_from_xyz_rpy({10, -20, 5}, {3, -7, 25});
    const Workpiece w = build_workpiece(type, default_params(type), pose);
    const Mesh m = w.mesh();
    const auto planes = w.face_planes();
    INFO(to_string(type));
    REQUIRE(m.triangle_count() > 0);
    for (const auto& t : m.triangles) REQUIRE(on_outward_face(m, t, planes));
  }
}

TEST_CASE("fillet: web toe sits gap above the flange on the line through the root", "[geometry]") {
  JointParams p = default_params(JointType::Fillet);
  p.gap_mm = 2.0;
  p.angle_deg = 75.0;
  const Workpiece w = build_workpiece(JointType::Fillet, p);
  Vec2 toe = Vec2::Zero();
  for (const auto& [name, pt] : w.truth.features)
    if (name == "web_toe") toe = pt;
  CHECK(toe.y() == Approx(2.0));
  // The toe lies on the ray from the root at 75 degrees: y = z / tan(75 deg).
  CHECK(toe.x() == Approx(2.0 / std::tan(75.0 * kDeg)));
  CHECK(w.truth.angle_deg == 75.0);
  CHECK(w.truth.gap_mm == 2.0);
  // The web's bottom face is horizontal at z = gap.
  int at_gap = 0;
  for (const auto& v : w.plates[1].section_yz) at_gap += std::abs(v.y() - 2.0) < 1e-12;
  CHECK(at_gap == 2);
}

TEST_CASE("v-groove truth: depth and open area by hand", "[geometry]") {
  const JointParams p = default_params(JointType::VGroove);  // t 12, rf 1.5, 60 deg, gap 1
  const Workpiece w = build_workpiece(JointType::VGroove, p);
  const double d = 12.0 - 1.5;
  CHECK(w.truth.depth_mm == Approx(d));
  // Trapezoid: bottom 1 mm, top 1 + 2 d tan 30, height d.
  CHECK(w.truth.area_mm2 == Approx(d * (1.0 + d * std::tan(30.0 * kDeg))));
  CHECK(w.truth.area_mm2 == Approx(74.1532).epsilon(1e-5));
}

TEST_CASE("seam line follows the workpiece pose", "[geometry]") {
  const Pose pose = pose_from_xyz_rpy({100, 50, 0}, {0, 0, 90});
  const Workpiece w = build_workpiece(JointType::Butt, default_params(JointType::Butt), pose);
  CHECK((w.seam_origin() - Vec3(100, 50, 0)).norm() < 1e-12);
  CHECK((w.seam_direction() - Vec3(0, 1, 0)).norm() < 1e-12);
}

TEST_CASE("in_sensor_frame: where the laser plane cuts a feature's line, also obliquely", "[geometry]") {
  // A butt in a posed joint frame; the sensor above its right edge, square
  // to the seam, then leaning 20 degrees along it and turned 15 about its axis.
  const Pose joint = pose_from_xyz_rpy({10, -20, 5}, {3, -2, 30});
  const Workpiece w = build_workpiece(JointType::Butt, default_params(JointType::Butt), joint);
  const Vec2 edge(0.5, 0.0);  // right_edge: (g / 2, mismatch)
  Pose square = sensor_pose_looking_at(joint * Vec3(60, edge.x(), edge.y()), joint.linear() * Vec3::UnitZ(), 100.0,
                                       w.seam_direction());
  CHECK((w.in_sensor_frame(square, edge) - Vec2(0.0, 100.0)).norm() < 1e-9);
  for (const auto& [lean, turn] : {std::pair{20.0, 0.0}, {0.0, 15.0}, {20.0, 15.0}, {-35.0, -10.0}}) {
    Pose oblique = square;
    oblique.rotate(Eigen::AngleAxisd(lean * kDeg, Vec3::UnitY()));
    oblique.rotate(Eigen::AngleAxisd(turn * kDeg, Vec3::UnitZ()));
    const Vec2 s = w.in_sensor_frame(oblique, edge);
    // In the laser plane (sensor x = 0) by construction; on the edge's line:
    // back in the joint frame its y and z are the edge's.
    const Vec3 in_joint = joint.inverse() * (oblique * Vec3(0.0, s.x(), s.y()));
    INFO("lean " << lean << ", turn " << turn << ": joint " << in_joint.transpose());
    CHECK(std::abs(in_joint.y() - edge.x()) < 1e-9);
    CHECK(std::abs(in_joint.z() - edge.y()) < 1e-9);
    // Leaning along the seam moves the cut by the standoff times tan(lean).
    if (turn == 0.0) CHECK(in_joint.x() == Approx(60.0 + 100.0 * std::tan(lean * kDeg)).margin(1e-9));
  }
}

TEST_CASE("invalid joint parameters are named with their value", "[geometry]") {
  JointParams p = default_params(JointType::VGroove);
  p.gap_mm = -1.0;
  CHECK(validate(JointType::VGroove, p) == "gap_mm = -1: must be >= 0");
  p = default_params(JointType::VGroove);
  p.root_face_mm = 20.0;
  CHECK(validate(JointType::VGroove, p).rfind("root_face_mm = 20", 0) == 0);
  p = default_params(JointType::Fillet);
  p.thickness_mm = std::nan("");
  CHECK(validate(JointType::Fillet, p).rfind("thickness_mm = nan", 0) == 0);
  p = default_params(JointType::Corner);
  p.angle_deg = 60.0;
  CHECK(validate(JointType::Corner, p).rfind("angle_deg = 60", 0) == 0);
  for (JointType t : {JointType::Fillet, JointType::Corner, JointType::Lap, JointType::Butt,
                      JointType::VGroove, JointType::Plate})
    CHECK(validate(t, default_params(t)).empty());
}

TEST_CASE("static setups: sensor at the Table 2 distance with the optical axis at 45 degrees to both plates",
          "[geometry][cells]") {
  for (const auto& s : kStaticSetups) {
    const auto cell = builtin_cell(std::string("static-") + s.label);
    REQUIRE(cell);
    const Workpiece& w = cell->workpieces.at(0);
    CHECK(w.truth.gap_mm == s.gap_mm);
    const Pose p = cell->path.start;
    const Vec3 root(20.0, 0.0, 0.0);  // default path starts 20 mm along the seam
    CHECK((p.translation() - root).norm() == Approx(s.distance_mm));
    const Vec3 axis = p.linear().col(2);
    // Looking at the root: the axis points from the laser to the root.
    CHECK((root - p.translation()).normalized().dot(axis) == Approx(1.0));
    // 45 degrees to the flange (z = 0) and to the web (y = 0).
    CHECK(std::acos(std::abs(axis.dot(Vec3::UnitZ()))) / kDeg == Approx(45.0));
    CHECK(std::acos(std::abs(axis.dot(Vec3::UnitY()))) / kDeg == Approx(45.0));
    // Travel along the seam; the laser line lies in the cross-section.
    CHECK(p.linear().col(0).dot(Vec3::UnitX()) == Approx(1.0));
  }
}

TEST_CASE("built-in cells all exist and the path steps along the seam", "[cells]") {
  CHECK(builtin_cell_names(CellSet::Small).size() + 2 == builtin_cell_names().size());  // fillet-1m, saddle-1m
  for (const auto& name : builtin_cell_names(CellSet::Small)) {
    INFO(name);
    const auto cell = builtin_cell(name);
    REQUIRE(cell);
    CHECK_FALSE(builtin_cell_description(name).empty());
    CHECK(cell->mesh().triangle_count() > 0);
    const Pose p10 = cell->path.pose_at(10);
    CHECK((p10.translation() - cell->path.start.translation() - 10 * cell->path.step_mm * Vec3::UnitX())
              .norm() < 1e-12);
  }
  CHECK_FALSE(builtin_cell("nope"));
}

TEST_CASE("pose helpers: rpy round trip and look-at frame", "[pose]") {
  const Pose p = pose_from_xyz_rpy({1, 2, 3}, {10, -20, 30});
  CHECK((rpy_deg_of(p) - Vec3(10, -20, 30)).norm() < 1e-9);
  const Pose q = pose_from_quat(p.translation(), rotation_quat(p));
  CHECK((q.matrix() - p.matrix()).norm() < 1e-12);
  Pose look;
  REQUIRE(pose_look_at({0, 0, 100}, {0, 0, 0}, {1, 0, 0}, look));
  CHECK((look.linear().col(2) - Vec3(0, 0, -1)).norm() < 1e-12);
  CHECK((look.linear().col(0) - Vec3(1, 0, 0)).norm() < 1e-12);
  CHECK((look.linear().col(0) - look.linear().col(1).cross(look.linear().col(2))).norm() < 1e-12);
  CHECK_FALSE(pose_look_at({0, 0, 100}, {0, 0, 0}, {0, 0, 1}, look));
}

TEST_CASE("cell_mm: every joint's grid mesh is closed and lies on the analytic faces", "[geometry][mesh]") {
  for (JointType type : {JointType::Fillet, JointType::Corner, JointType::Lap, JointType::Butt,
                         JointType::VGroove, JointType::Plate}) {
    INFO(to_string(type));
    JointParams p = default_params(type);
    p.gap_mm = type == JointType::Lap || type == JointType::Fillet ? 1.5 : p.gap_mm;
    p.cell_mm = 3.0;
    REQUIRE(validate(type, p).empty());
    const Pose pose = pose_from_xyz_rpy({10, -20, 5}, {3, -7, 25});
    const Workpiece w = build_workpiece(type, p, pose);
    const Mesh m = w.mesh();
    std::int64_t expected = 0;
    for (const Plate& plate : w.plates) expected += plate_triangle_count(plate, p.segment_mm, p.cell_mm);
    CHECK(static_cast<std::int64_t>(m.triangle_count()) == expected);
    const MeshLoadStats edges = mesh_edge_stats(m);
    CHECK(edges.closed());
    const auto planes = w.face_planes();
    for (const auto& t : m.triangles) REQUIRE(on_outward_face(m, t, planes));
    // Far denser than the plain mesh, with no edge longer than a grid cell's
    // diagonal except in the fanned caps of the five-sided v-groove plates.
    CHECK(m.triangle_count() > 20 * build_workpiece(type, default_params(type), pose).mesh().triangle_count());
    if (type != JointType::VGroove)
      for (const auto& t : m.triangles)
        for (int k = 0; k < 3; ++k)
          REQUIRE((m.vertices[t[k]] - m.vertices[t[(k + 1) % 3]]).norm() <= 3.0f * std::sqrt(2.0f) + 1e-3f);
  }
  // cell_mm = 0 is the plain mesh; the count function agrees with it.
  for (const auto& name : builtin_cell_names(CellSet::Small)) {
    const Cell cell = *builtin_cell(name);
    const Workpiece& w = cell.workpieces.front();
    if (w.saddle) continue;  // not made of plates (tests/sensor/saddle_test.cpp)
    std::int64_t expected = 0;
    for (const Plate& plate : w.plates) expected += plate_triangle_count(plate, w.params.segment_mm);
    CHECK(static_cast<std::int64_t>(w.mesh().triangle_count()) == expected);
  }
}

TEST_CASE("cell_mm: negative and too fine grids are refused", "[geometry][mesh]") {
  JointParams p = default_params(JointType::Fillet);
  p.cell_mm = -1.0;
  CHECK(validate(JointType::Fillet, p) == "cell_mm = -1: must be >= 0 (0: no grid)");
  p.cell_mm = 0.05;
  CHECK(validate(JointType::Fillet, p) ==
        "cell_mm = 0.05: too small: the mesh would have more than 20000000 triangles");
  p.cell_mm = std::numeric_limits<double>::min();
  CHECK_FALSE(validate(JointType::Fillet, p).empty());
  p.cell_mm = 1e300;
  CHECK(validate(JointType::Fillet, p).empty());
  CHECK(build_workpiece(JointType::Fillet, p).mesh().triangle_count() == 2 * 20 * 8 + 2 * 2 * 2);
}

TEST_CASE("fillet-1m: 1010888 triangles on the fillet's analytic faces", "[cells][mesh]") {
  const auto start = std::chrono::steady_clock::now();
  const auto cell = builtin_cell("fillet-1m");
  REQUIRE(cell);
  const Mesh m = cell->mesh();
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  WARN("fillet-1m: " << m.triangle_count() << " triangles, " << m.vertices.size() << " vertices, built in "
                     << seconds << " s");
  CHECK(m.triangle_count() == 1010888);
  CHECK(builtin_cell_description("fillet-1m").find("1010888 triangles") != std::string::npos);
  const Workpiece& w = cell->workpieces.front();
  CHECK(w.type == JointType::Fillet);
  CHECK(w.params.length_mm == 600.0);
  CHECK(w.params.cell_mm == 0.78);
  CHECK(mesh_edge_stats(m).closed());
  // Every triangle lies on one analytic face (wound outward), and no edge is
  // longer than a cell's diagonal: the mesh is within cell_mm of the planes
  // everywhere, and on them to float precision.
  const auto planes = w.face_planes();
  const float diagonal = static_cast<float>(w.params.cell_mm * std::sqrt(2.0)) + 1e-4f;
  std::size_t off_face = 0, too_long = 0;
  for (const auto& t : m.triangles) {
    off_face += !on_outward_face(m, t, planes);
    for (int k = 0; k < 3; ++k) too_long += (m.vertices[t[k]] - m.vertices[t[(k + 1) % 3]]).norm() > diagonal;
  }
  CHECK(off_face == 0);
  CHECK(too_long == 0);
  // The same seam and default path as the built-in fillet.
  const Cell fillet = *builtin_cell("fillet");
  CHECK((cell->path.start.matrix() - fillet.path.start.matrix()).cwiseAbs().maxCoeff() < 1e-12);
}
