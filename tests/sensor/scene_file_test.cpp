#include "sensor/scene_file.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <numbers>
#include <string>

namespace {

using vts::Cell;
using vts::Pose;
using vts::SceneError;
using vts::Vec3;

const std::filesystem::path kExamples = std::filesystem::path(VTS_SOURCE_DIR) / "examples";
constexpr double kDeg = std::numbers::pi / 180.0;

// Parses `text` as "bad.yaml" and checks that it fails at `line`, on `field`,
// with a message containing `fragment`.
void expect_error(const std::string& text, int line, const std::string& field,
                  const std::string& fragment) {
  INFO("scene:\n" << text);
  try {
    vts::parse_scene(text, "bad.yaml");
    FAIL("parse_scene accepted the scene");
  } catch (const SceneError& e) {
    const std::string what = e.what();
    INFO("what(): " << what);
    CHECK(e.file == "bad.yaml");
    CHECK(e.line == line);
    CHECK(e.field == field);
    const std::string prefix =
        "bad.yaml:" + std::to_string(line) + ": " + (field.empty() ? "" : field + ": ");
    CHECK(what.rfind(prefix, 0) == 0);
    CHECK(what.find(fragment) != std::string::npos);
  }
}

// A valid scene with one line replaced: lines are numbered from 1.
const char* const kBase =
    "name: base\n"                         // 1
    "scanner:\n"                           // 2
    "  points: 256\n"                      // 3
    "  rate_hz: 20\n"                      // 4
    "workpieces:\n"                        // 5
    "  - joint: fillet\n"                  // 6
    "    gap_mm: 2\n"                      // 7
    "    pose:\n"                          // 8
    "      position_mm: [0, 0, 0]\n"       // 9
    "      rpy_deg: [0, 0, 0]\n"           // 10
    "path:\n"                              // 11
    "  start:\n"                           // 12
    "    position_mm: [20, 70, 70]\n"      // 13
    "    look_at_mm: [20, 0, 0]\n"         // 14
    "  direction: [1, 0, 0]\n"             // 15
    "  step_mm: 0.5\n"                     // 16
    "  profiles: 10\n";                    // 17

std::string with_line(int line, const std::string& replacement) {
  std::string out;
  int n = 1;
  std::size_t pos = 0;
  const std::string base = kBase;
  while (pos < base.size()) {
    const std::size_t end = base.find('\n', pos);
    const std::string l = base.substr(pos, end - pos);
    out += (n == line ? replacement : l) + "\n";
    pos = end + 1;
    ++n;
  }
  return out;
}

void check_pose(const Pose& a, const Pose& b) {
  CHECK((a.matrix() - b.matrix()).cwiseAbs().maxCoeff() <= 1e-9);
}

void check_same_cell(const Cell& a, const Cell& b) {
  CHECK(a.name == b.name);
  CHECK(a.scanner.name == b.scanner.name);
  CHECK(a.scanner.fan_deg == b.scanner.fan_deg);
  CHECK(a.scanner.points == b.scanner.points);
  CHECK(a.scanner.min_range_mm == b.scanner.min_range_mm);
  CHECK(a.scanner.max_range_mm == b.scanner.max_range_mm);
  CHECK(a.scanner.max_hit_mm == b.scanner.max_hit_mm);
  CHECK(a.scanner.rate_hz == b.scanner.rate_hz);
  check_pose(a.scanner.tool_from_laser, b.scanner.tool_from_laser);
  REQUIRE(a.workpieces.size() == b.workpieces.size());
  for (std::size_t i = 0; i < a.workpieces.size(); ++i) {
    const auto& wa = a.workpieces[i];
    const auto& wb = b.workpieces[i];
    CHECK(wa.type == wb.type);
    CHECK(wa.params.length_mm == wb.params.length_mm);
    CHECK(wa.params.width_mm == wb.params.width_mm);
    CHECK(wa.params.thickness_mm == wb.params.thickness_mm);
    CHECK(wa.params.height_mm == wb.params.height_mm);
    CHECK(wa.params.gap_mm == wb.params.gap_mm);
    CHECK(wa.params.angle_deg == wb.params.angle_deg);
    CHECK(wa.params.mismatch_mm == wb.params.mismatch_mm);
    CHECK(wa.params.root_face_mm == wb.params.root_face_mm);
    CHECK(wa.params.segment_mm == wb.params.segment_mm);
    CHECK(wa.params.cell_mm == wb.params.cell_mm);
    CHECK(wa.params.passes == wb.params.passes);
    CHECK(wa.params.layer_mm == wb.params.layer_mm);
    CHECK(wa.params.crown_mm == wb.params.crown_mm);
    CHECK(wa.params.radius_mm == wb.params.radius_mm);
    check_pose(wa.world_from_joint, wb.world_from_joint);
    CHECK(wa.plates.size() == wb.plates.size());
    CHECK(wa.is_mesh() == wb.is_mesh());
    CHECK(wa.has_joint() == wb.has_joint());
    CHECK(wa.mesh_file == wb.mesh_file);
    CHECK(wa.mesh_unit_mm == wb.mesh_unit_mm);
  }
  check_pose(a.path.start, b.path.start);
  CHECK((a.path.direction - b.path.direction).norm() <= 1e-12);
  CHECK(a.path.step_mm == b.path.step_mm);
  CHECK(a.path.profiles == b.path.profiles);
}

}  // namespace

TEST_CASE("scene file: fillet_gap example", "[scene]") {
  const Cell c = vts::load_scene(kExamples / "fillet_gap.yaml");
  CHECK(c.name == "fillet-gap");
  REQUIRE(c.workpieces.size() == 1);
  CHECK(c.workpieces[0].type == vts::JointType::Fillet);
  CHECK(c.workpieces[0].params.gap_mm == 1.5);
  CHECK(c.workpieces[0].params.angle_deg == 90.0);  // fillet default
  // Laser origin 80 mm from the root at (20, 0, 0), looking at it at 45
  // degrees to both plates (flange normal z, web normal y).
  const Vec3 eye = c.path.start.translation();
  CHECK((eye - Vec3(20, 0, 0)).norm() == Approx(80.0).margin(1e-9));
  const Vec3 axis = c.path.start.linear().col(2);
  CHECK(std::acos(-axis.z()) / kDeg == Approx(45.0).margin(1e-9));
  CHECK(std::acos(-axis.y()) / kDeg == Approx(45.0).margin(1e-9));
  CHECK((c.path.start.linear().col(0) - Vec3::UnitX()).norm() <= 1e-12);
  CHECK(c.path.step_mm == 0.5);
  CHECK(c.path.profiles == 100);
}

TEST_CASE("scene file: vgroove example", "[scene]") {
  const Cell c = vts::load_scene(kExamples / "vgroove.yaml");
  REQUIRE(c.workpieces.size() == 1);
  CHECK(c.workpieces[0].type == vts::JointType::VGroove);
  CHECK(c.workpieces[0].params.gap_mm == 2.0);
  CHECK(c.workpieces[0].params.mismatch_mm == 0.5);
  CHECK(c.scanner.points == 1024);
  CHECK(c.scanner.rate_hz == 50.0);
  CHECK(c.scanner.fan_deg == 40.0);  // not given: ScannerDesc default
  CHECK(c.path.step_mm == Approx(10.0 / 50.0).margin(1e-15));  // speed / rate
  CHECK(c.path.profiles == 200);
  // roll 180: optical axis straight down, travel along +x.
  CHECK((c.path.start.linear().col(2) - Vec3(0, 0, -1)).norm() <= 1e-12);
  CHECK((c.path.start.linear().col(0) - Vec3(1, 0, 0)).norm() <= 1e-12);
  CHECK((c.path.start.translation() - Vec3(20, 0, 110)).norm() <= 1e-12);
}

TEST_CASE("scene file: lap_tilted example", "[scene]") {
  const Cell c = vts::load_scene(kExamples / "lap_tilted.yaml");
  REQUIRE(c.workpieces.size() == 1);
  const auto& w = c.workpieces[0];
  CHECK(w.type == vts::JointType::Lap);
  CHECK(w.params.gap_mm == 0.5);
  // yaw 30 about world z, roll 15 about the seam.
  const Vec3 seam(std::cos(30 * kDeg), std::sin(30 * kDeg), 0);
  CHECK((w.seam_direction() - seam).norm() <= 1e-12);
  CHECK((w.seam_origin() - Vec3(100, 50, 0)).norm() <= 1e-12);
  const Vec3 joint_z = w.world_from_joint.linear().col(2);
  CHECK(std::acos(joint_z.z()) / kDeg == Approx(15.0).margin(1e-9));
  CHECK(joint_z.dot(seam) == Approx(0.0).margin(1e-12));
  // The sensor looks straight down the joint's z at the seam from 100 mm.
  const Vec3 axis = c.path.start.linear().col(2);
  CHECK((axis + joint_z).norm() <= 1e-9);
  const Vec3 target = Vec3(100, 50, 0) + 20.0 * seam;
  CHECK((c.path.start.translation() - target).norm() == Approx(100.0).margin(1e-9));
  CHECK((c.path.direction - seam).norm() <= 1e-12);
}

TEST_CASE("scene file: defaults when scanner and path are omitted", "[scene]") {
  const Cell c = vts::parse_scene("workpieces:\n  - joint: butt\n", "dir/my-butt.yaml");
  CHECK(c.name == "my-butt");  // file stem
  CHECK(c.scanner.points == vts::ScannerDesc{}.points);
  REQUIRE(c.workpieces.size() == 1);
  CHECK(c.workpieces[0].params.gap_mm == vts::default_params(vts::JointType::Butt).gap_mm);
  const vts::ScanPath expected = vts::default_path(c.workpieces[0], 100.0);
  check_pose(c.path.start, expected.start);
  CHECK(c.path.profiles == expected.profiles);
  CHECK(c.path.step_mm == expected.step_mm);
  // Straight above the butt seam at x = 20, 100 mm up.
  CHECK((c.path.start.translation() - Vec3(20, 0, 100)).norm() <= 1e-9);
}

TEST_CASE("scene file: base scene used by the error tests is valid", "[scene]") {
  const Cell c = vts::parse_scene(kBase, "bad.yaml");
  CHECK(c.name == "base");
  CHECK(c.scanner.points == 256);
  CHECK(c.path.profiles == 10);
}

TEST_CASE("scene file: YAML syntax errors", "[scene]") {
  expect_error(with_line(9, "      position_mm: [0, 0, 0"), 10, "", "YAML syntax error");
  expect_error(with_line(4, "   rate_hz: 20"), 4, "", "YAML syntax error");
  expect_error("", 1, "", "empty scene");
  expect_error("- 1\n- 2\n", 1, "", "expected a map, got a list of 2");
}

TEST_CASE("scene file: unknown and duplicate keys", "[scene]") {
  expect_error(with_line(5, "wokpieces:"), 5, "wokpieces", "unknown key");
  expect_error(with_line(7, "    gapp_mm: 2"), 7, "workpieces[0].gapp_mm",
               "unknown key (expected one of: joint, pose, length_mm");
  expect_error(with_line(3, "  pionts: 256"), 3, "scanner.pionts", "unknown key");
  expect_error(with_line(10, "      rpy: [0, 0, 0]"), 10, "workpieces[0].pose.rpy", "unknown key");
  expect_error(with_line(16, "  stepmm: 0.5"), 16, "path.stepmm", "unknown key");
  expect_error(with_line(17, "  step_mm: 1"), 17, "path.step_mm", "duplicate key (first given on line 16)");
}

TEST_CASE("scene file: wrong types", "[scene]") {
  expect_error(with_line(7, "    gap_mm: abc"), 7, "workpieces[0].gap_mm", "expected a number, got 'abc'");
  expect_error(with_line(7, "    gap_mm: '2'"), 7, "workpieces[0].gap_mm", "expected a number, got '2'");
  expect_error(with_line(7, "    gap_mm: [2]"), 7, "workpieces[0].gap_mm", "expected a number, got a list of 1");
  expect_error(with_line(7, "    gap_mm:"), 7, "workpieces[0].gap_mm", "expected a number, got nothing");
  expect_error(with_line(3, "  points: 256.5"), 3, "scanner.points", "expected an integer, got '256.5'");
  expect_error(with_line(17, "  profiles: many"), 17, "path.profiles", "expected an integer, got 'many'");
  expect_error(with_line(9, "      position_mm: 5"), 9, "workpieces[0].pose.position_mm",
               "expected a list of 3 numbers [x, y, z], got '5'");
  expect_error(with_line(10, "      rpy_deg: [0, 0]"), 10, "workpieces[0].pose.rpy_deg",
               "expected a list of 3 numbers [x, y, z], got a list of 2");
  expect_error(with_line(13, "    position_mm: [20, x, 70]"), 13, "path.start.position_mm[1]",
               "expected a number, got 'x'");
  expect_error(with_line(6, "  - joint: {type: fillet}"), 6, "workpieces[0].joint",
               "expected a string, got a map");
  expect_error("workpieces:\n  - joint: plate\n    pose: [0, 0, 0]\n", 3, "workpieces[0].pose",
               "expected a map, got a list of 3");
  expect_error("scanner: 5\nworkpieces:\n  - joint: plate\n", 1, "scanner", "expected a map, got '5'");
  expect_error("workpieces:\n  - joint: plate\n  - 7\n", 3, "workpieces[1]", "expected a map, got '7'");
  expect_error("workpieces:\n  joint: fillet\n", 1, "workpieces", "expected a list of workpieces, got a map");
}

TEST_CASE("scene file: non-finite numbers", "[scene]") {
  expect_error(with_line(7, "    gap_mm: .nan"), 7, "workpieces[0].gap_mm", "must be a finite number, got '.nan'");
  expect_error(with_line(7, "    gap_mm: nan"), 7, "workpieces[0].gap_mm", "must be a finite number");
  expect_error(with_line(16, "  step_mm: .inf"), 16, "path.step_mm", "must be a finite number");
  expect_error(with_line(4, "  rate_hz: -.inf"), 4, "scanner.rate_hz", "must be a finite number");
  expect_error(with_line(10, "      rpy_deg: [0, .nan, 0]"), 10, "workpieces[0].pose.rpy_deg[1]",
               "must be a finite number");
}

TEST_CASE("scene file: out-of-range values report validate()'s message", "[scene]") {
  expect_error(with_line(7, "    gap_mm: -1"), 7, "workpieces[0].gap_mm", "gap_mm = -1: must be >= 0");
  expect_error(with_line(7, "    thickness_mm: 0"), 7, "workpieces[0].thickness_mm", "thickness_mm = 0: must be > 0");
  expect_error(with_line(7, "    length_mm: -200"), 7, "workpieces[0].length_mm", "must be > 0");
  expect_error(with_line(7, "    angle_deg: 10"), 7, "workpieces[0].angle_deg", "angle_deg = 10");
  expect_error(with_line(7, "    cell_mm: -1"), 7, "workpieces[0].cell_mm", "cell_mm = -1: must be >= 0 (0: no grid)");
  expect_error(with_line(7, "    cell_mm: 0.01"), 7, "workpieces[0].cell_mm",
               "cell_mm = 0.01: too small: the mesh would have more than 20000000 triangles");
  expect_error(with_line(3, "  points: 8"), 3, "scanner.points", "points = 8: must be between 16 and 4096");
  expect_error(with_line(3, "  fan_deg: 200"), 3, "scanner.fan_deg", "fan_deg = 200");
  expect_error(with_line(4, "  rate_hz: 0"), 4, "scanner.rate_hz", "rate_hz = 0: must be > 0");
  expect_error(with_line(3, "  max_range_mm: 10"), 3, "scanner.max_range_mm",
               "must be greater than min_range_mm");
}

TEST_CASE("scene file: joints and poses and paths that make no sense", "[scene]") {
  expect_error(with_line(6, "  - joint: tee"), 6, "workpieces[0].joint",
               "unknown joint 'tee' (expected one of: fillet, corner, lap, butt, vgroove, bevel, ugroove, jgroove, plate)");
  expect_error(with_line(6, "  - jiont: fillet"), 6, "workpieces[0].jiont", "unknown key");
  expect_error("workpieces:\n  - gap_mm: 1\n", 2, "workpieces[0].joint", "missing (required)");
  expect_error("name: x\n", 1, "workpieces", "missing (required)");
  expect_error("workpieces: []\n", 1, "workpieces", "needs at least one workpiece");
  expect_error(with_line(14, "    rpy_deg: [0, 0, 0]\n    look_at_mm: [20, 0, 0]"), 15, "path.start.look_at_mm",
               "give either rpy_deg or look_at_mm, not both");
  expect_error(with_line(14, "    travel: [1, 0, 0]"), 14, "path.start.travel",
               "travel is only used with look_at_mm");
  expect_error(with_line(14, ""), 12, "path.start", "needs rpy_deg or look_at_mm");
  expect_error(with_line(13, ""), 12, "path.start.position_mm", "missing (required)");
  expect_error(with_line(14, "    look_at_mm: [20, 70, 70]"), 14, "path.start.look_at_mm",
               "must differ from position_mm");
  expect_error(with_line(14, "    look_at_mm: [20, 0, 0]\n    travel: [0, 1, 1]"), 15, "path.start.travel",
               "parallel");
  expect_error(with_line(15, "  direction: [0, 0, 0]"), 15, "path.direction", "direction must not be zero");
  expect_error(with_line(17, "  profiles: 0"), 17, "path.profiles", "profiles = 0: must be between 1");
  expect_error(with_line(17, "  profiles: -5"), 17, "path.profiles", "profiles = -5");
  expect_error(with_line(16, "  step_mm: 0"), 16, "path.step_mm", "step_mm = 0: must be > 0");
  expect_error(with_line(16, "  step_mm: -1"), 16, "path.step_mm", "step_mm = -1: must be > 0");
  expect_error(with_line(16, "  step_mm: 0.5\n  speed_mm_s: 10"), 17, "path.speed_mm_s",
               "give either step_mm or speed_mm_s, not both");
  expect_error(with_line(16, "  speed_mm_s: -10"), 16, "path.speed_mm_s", "must be > 0");
  expect_error(with_line(12, "  standoff_mm: 80\n  start:"), 12, "path.standoff_mm",
               "give either start or standoff_mm");
}

TEST_CASE("scene file: groove joints and their keys", "[scene][groove]") {
  const Cell c = vts::parse_scene(with_line(6, "  - joint: ugroove\n    passes: 2\n    layer_mm: 2.5\n    crown_mm: -0.2\n"
                                               "    radius_mm: 6\n    thickness_mm: 30"),
                                  "u.yaml");
  const vts::JointParams& p = c.workpieces.at(0).params;
  CHECK(c.workpieces[0].type == vts::JointType::UGroove);
  CHECK(p.passes == 2);
  CHECK(p.layer_mm == 2.5);
  CHECK(p.crown_mm == -0.2);
  CHECK(p.radius_mm == 6.0);
  CHECK(p.gap_mm == 2.0);
  CHECK(c.workpieces[0].truth.track_yz.y() == Approx(5.0 - 0.2));
  check_same_cell(c, vts::parse_scene(vts::scene_to_yaml(c), "roundtrip.yaml"));
  for (const char* joint : {"bevel", "jgroove", "vgroove"}) {
    const Cell j = vts::parse_scene(with_line(6, std::string("  - joint: ") + joint + "\n    passes: 1"), "j.yaml");
    CHECK(j.workpieces.at(0).params.passes == 1);
    check_same_cell(j, vts::parse_scene(vts::scene_to_yaml(j), "roundtrip.yaml"));
  }
  // An empty v-groove's scene reads as before the beads: no new keys written.
  const Cell v = vts::parse_scene(with_line(6, "  - joint: vgroove"), "v.yaml");
  CHECK(vts::scene_to_yaml(v).find("passes") == std::string::npos);
}

TEST_CASE("scene file: bad groove keys name the key, its line and what is wrong", "[scene][groove]") {
  const auto groove = [](const std::string& joint, const std::string& line) {
    return with_line(6, "  - joint: " + joint + "\n" + line);
  };
  expect_error(groove("bevel", "    passes: 1.5"), 7, "workpieces[0].passes", "expected an integer, got '1.5'");
  expect_error(groove("bevel", "    passes: -1"), 7, "workpieces[0].passes", "passes = -1: must be >= 0");
  expect_error(groove("bevel", "    passes: 99999999999"), 7, "workpieces[0].passes", "out of range");
  expect_error(groove("bevel", "    passes: 4"), 7, "workpieces[0].passes",
               "passes = 4: the fill (passes x layer_mm = 12 mm, crown_mm 0.5) must stay below the plate tops");
  expect_error(groove("vgroove", "    layer_mm: 0"), 7, "workpieces[0].layer_mm", "layer_mm = 0: must be > 0");
  expect_error(groove("vgroove", "    crown_mm: high"), 7, "workpieces[0].crown_mm", "expected a number, got 'high'");
  expect_error(groove("ugroove", "    radius_mm: 40"), 7, "workpieces[0].radius_mm",
               "radius_mm = 40: the bottom arc does not fit");
  expect_error(groove("jgroove", "    radius_mm: 0"), 7, "workpieces[0].radius_mm", "radius_mm = 0: must be > 0");
  expect_error(groove("bevel", "    passes: 1\n    crown_mm: 3"), 8, "workpieces[0].crown_mm",
               "crown_mm = 3: must be smaller in size than half the cap's width");
  expect_error(groove("bevel", "    angle_deg: 95"), 7, "workpieces[0].angle_deg", "angle_deg = 95: bevel angle");
}

TEST_CASE("scene file: missing file", "[scene]") {
  try {
    vts::load_scene("/nonexistent/dir/missing.yaml");
    FAIL("no error");
  } catch (const SceneError& e) {
    CHECK(e.line == 0);
    CHECK(std::string(e.what()) == "/nonexistent/dir/missing.yaml:0: scene file not found");
  }
}

TEST_CASE("scene file: cell_mm meshes a joint as a grid and keeps its truth", "[scene]") {
  const Cell c = vts::parse_scene("workpieces:\n  - joint: butt\n    gap_mm: 2\n    cell_mm: 2.5\n", "g.yaml");
  const vts::Workpiece& w = c.workpieces.at(0);
  CHECK(w.params.cell_mm == 2.5);
  CHECK(w.truth.gap_mm == 2.0);
  vts::JointParams p = w.params;
  p.cell_mm = 0.0;
  const vts::Workpiece plain = vts::build_workpiece(vts::JointType::Butt, p);
  CHECK(w.mesh().triangle_count() > 50 * plain.mesh().triangle_count());
  CHECK(vts::parse_scene(vts::scene_to_yaml(c), "r.yaml").workpieces.at(0).params.cell_mm == 2.5);
}

TEST_CASE("scene file: path options", "[scene]") {
  // standoff_mm re-derives the default path at that distance.
  const Cell c = vts::parse_scene(
      "workpieces:\n  - joint: plate\npath:\n  standoff_mm: 150\n  speed_mm_s: 40\n", "s.yaml");
  CHECK((c.path.start.translation() - Vec3(20, 0, 150)).norm() <= 1e-9);
  CHECK(c.path.step_mm == Approx(2.0));  // 40 mm/s at the default 20 Hz
  // look_at_mm without travel: travel is the path direction.
  const Cell d = vts::parse_scene(
      "workpieces:\n  - joint: plate\npath:\n  direction: [0, 2, 0]\n"
      "  start:\n    position_mm: [0, 0, 100]\n    look_at_mm: [0, 0, 0]\n",
      "s.yaml");
  CHECK((d.path.direction - Vec3::UnitY()).norm() <= 1e-15);
  CHECK((d.path.start.linear().col(0) - Vec3::UnitY()).norm() <= 1e-12);
  CHECK((d.path.start.linear().col(2) + Vec3::UnitZ()).norm() <= 1e-12);
}

TEST_CASE("scene file: round trip through scene_to_yaml", "[scene]") {
  SECTION("built-in cells") {
    for (const std::string& name : vts::builtin_cell_names()) {
      INFO(name);
      const auto cell = vts::builtin_cell(name);
      REQUIRE(cell);
      const std::string text = vts::scene_to_yaml(*cell);
      INFO(text);
      check_same_cell(*cell, vts::parse_scene(text, "roundtrip.yaml"));
    }
  }
  SECTION("examples") {
    for (const char* file : {"fillet_gap.yaml", "vgroove.yaml", "lap_tilted.yaml"}) {
      INFO(file);
      const Cell cell = vts::load_scene(kExamples / file);
      check_same_cell(cell, vts::parse_scene(vts::scene_to_yaml(cell), "roundtrip.yaml"));
    }
  }
  SECTION("several workpieces, awkward poses and values") {
    Cell cell;
    cell.name = "odd \"name\": with # and \\";
    cell.scanner.name = "custom";
    cell.scanner.points = 777;
    cell.scanner.fan_deg = 0.1 + 0.2;  // not exactly representable in short form
    cell.scanner.rate_hz = 1.0 / 3.0;
    cell.scanner.tool_from_laser = vts::pose_from_xyz_rpy(Vec3(50, 0, 100), Vec3(0, 10, 0));
    vts::JointParams p = vts::default_params(vts::JointType::Corner);
    p.gap_mm = std::nextafter(1.0, 2.0);
    cell.workpieces.push_back(vts::build_workpiece(
        vts::JointType::Corner, p, vts::pose_from_xyz_rpy(Vec3(1e-7, -3, 1e5), Vec3(10, 90, 20))));
    cell.workpieces.push_back(vts::build_workpiece(
        vts::JointType::Butt, vts::default_params(vts::JointType::Butt),
        vts::pose_from_xyz_rpy(Vec3(0, 300, 0), Vec3(-179.9, -45, 179))));
    cell.workpieces.push_back(vts::build_workpiece(
        vts::JointType::Plate, vts::default_params(vts::JointType::Plate),
        vts::pose_from_xyz_rpy(Vec3(5, 6, 7), Vec3(30, -90, 40))));
    cell.path.start = vts::pose_from_xyz_rpy(Vec3(1.0 / 7.0, 2, 3), Vec3(123, -89.999, -170));
    cell.path.direction = Vec3(1, 2, 3).normalized();
    cell.path.step_mm = 0.1;
    cell.path.profiles = 123456;
    const std::string text = vts::scene_to_yaml(cell);
    INFO(text);
    check_same_cell(cell, vts::parse_scene(text, "roundtrip.yaml"));
  }
}
