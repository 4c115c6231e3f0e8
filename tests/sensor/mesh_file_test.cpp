#include <catch2/catch.hpp>

#include <unistd.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "tests/common/temp_dir.h"
#include "sensor/cell.h"
#include "sensor/mesh_file.h"
#include "sensor/reference_source.h"
#include "sensor/scene_file.h"

namespace fs = std::filesystem;
using vts::Mesh;
using vts::MeshFileError;
using vts::MeshLoadStats;
using vts::Vec3;

namespace {

// A fresh directory under the system temp dir, removed at the end of the test.
struct TempDir : vts::test::TempDir {
  TempDir() : vts::test::TempDir("vts_mesh_test") {}
};

// The box lo..hi: vertex i has x = hi.x if bit 0 of i is set, y if bit 1, z
// if bit 2; six faces as counter-clockwise quads seen from outside, in the
// order -z, +z, -y, +y, -x, +x.
using Quad = std::array<int, 4>;
constexpr Quad kBoxFaces[6] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                               {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
constexpr int kTop = 1;  // the +z face

std::vector<Vec3> box_corners(const Vec3& lo, const Vec3& hi) {
  std::vector<Vec3> v;
  for (int i = 0; i < 8; ++i)
    v.emplace_back(i & 1 ? hi.x() : lo.x(), i & 2 ? hi.y() : lo.y(), i & 4 ? hi.z() : lo.z());
  return v;
}

// The box as a mesh, without face `skip` (-1: all six).
Mesh box_mesh(const Vec3& lo, const Vec3& hi, int skip = -1) {
  Mesh m;
  for (const Vec3& c : box_corners(lo, hi)) m.vertices.push_back(c.cast<float>());
  for (int f = 0; f < 6; ++f) {
    if (f == skip) continue;
    const Quad& q = kBoxFaces[f];
    const auto u = [&](int k) { return static_cast<std::uint32_t>(q[k]); };
    m.triangles.push_back({u(0), u(1), u(2)});
    m.triangles.push_back({u(0), u(2), u(3)});
  }
  return m;
}

std::string fmt(float v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.9g", v);
  return buf;
}

std::string ascii_stl(const Mesh& m) {
  std::string s = "solid box\n";
  for (const auto& t : m.triangles) {
    s += "  facet normal 0 0 0\n    outer loop\n";
    for (const auto i : t) {
      const auto& v = m.vertices[i];
      s += "      vertex " + fmt(v.x()) + " " + fmt(v.y()) + " " + fmt(v.z()) + "\n";
    }
    s += "    endloop\n  endfacet\n";
  }
  return s + "endsolid box\n";
}

void put_u32(std::string& s, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) s += static_cast<char>((v >> (8 * i)) & 0xff);
}
void put_f32(std::string& s, float v) { put_u32(s, std::bit_cast<std::uint32_t>(v)); }

std::string binary_stl(const Mesh& m, std::string header) {
  header.resize(80, ' ');
  std::string s = header;
  put_u32(s, static_cast<std::uint32_t>(m.triangles.size()));
  for (const auto& t : m.triangles) {
    for (int i = 0; i < 3; ++i) put_f32(s, 0.0f);
    for (const auto i : t)
      for (int k = 0; k < 3; ++k) put_f32(s, m.vertices[i][k]);
    s += std::string(2, '\0');
  }
  return s;
}

// OBJ with quad faces (assimp triangulates them), optionally with extra lines.
std::string obj_box(const Vec3& lo, const Vec3& hi, const std::string& extra = "") {
  std::string s = "# box\no box\n";
  for (const Vec3& c : box_corners(lo, hi))
    s += "v " + fmt(float(c.x())) + " " + fmt(float(c.y())) + " " + fmt(float(c.z())) + "\n";
  for (const Quad& q : kBoxFaces)
    s += "f " + std::to_string(q[0] + 1) + " " + std::to_string(q[1] + 1) + " " + std::to_string(q[2] + 1) +
         " " + std::to_string(q[3] + 1) + "\n";
  return s + extra;
}

// ASCII PLY with quad faces, optionally with extra faces ("3 0 0 1").
std::string ascii_ply_box(const Vec3& lo, const Vec3& hi, const std::vector<std::string>& extra = {}) {
  std::string s = "ply\nformat ascii 1.0\nelement vertex 8\nproperty float x\nproperty float y\n"
                  "property float z\nelement face " + std::to_string(6 + extra.size()) +
                  "\nproperty list uchar int vertex_indices\nend_header\n";
  for (const Vec3& c : box_corners(lo, hi))
    s += fmt(float(c.x())) + " " + fmt(float(c.y())) + " " + fmt(float(c.z())) + "\n";
  for (const Quad& q : kBoxFaces)
    s += "4 " + std::to_string(q[0]) + " " + std::to_string(q[1]) + " " + std::to_string(q[2]) + " " +
         std::to_string(q[3]) + "\n";
  for (const auto& e : extra) s += e + "\n";
  return s;
}

// Binary little-endian PLY of a mesh, written here (not by write_mesh_file),
// with the other common spelling of the index list.
std::string binary_ply(const Mesh& m) {
  std::string s = "ply\nformat binary_little_endian 1.0\nelement vertex " + std::to_string(m.vertices.size()) +
                  "\nproperty float x\nproperty float y\nproperty float z\nelement face " +
                  std::to_string(m.triangles.size()) + "\nproperty list uchar int vertex_index\nend_header\n";
  for (const auto& v : m.vertices)
    for (int k = 0; k < 3; ++k) put_f32(s, v[k]);
  for (const auto& t : m.triangles) {
    s += static_cast<char>(3);
    for (const auto i : t) put_u32(s, i);
  }
  return s;
}

// The box's eight corners (after scale and pose) are exactly the mesh's
// vertices, and the box is closed with 12 triangles.
void check_box(const Mesh& m, const MeshLoadStats& stats, const Vec3& lo, const Vec3& hi) {
  CHECK(stats.triangles_read == 12);
  CHECK(stats.triangles_kept == 12);
  CHECK(stats.skipped_degenerate == 0);
  CHECK(stats.open_edges == 0);
  CHECK(stats.nonmanifold_edges == 0);
  CHECK(stats.closed());
  REQUIRE(m.triangle_count() == 12);
  REQUIRE(m.vertices.size() == 8);
  for (const Vec3& c : box_corners(lo, hi)) {
    const Eigen::Vector3f cf = c.cast<float>();
    int found = 0;
    for (const auto& v : m.vertices) found += v == cf;
    INFO("corner " << c.transpose());
    CHECK(found == 1);
  }
  // Outward winding survives: the signed volume is the box's.
  double volume = 0.0;
  for (const auto& t : m.triangles) {
    const Vec3 a = m.vertices[t[0]].cast<double>(), b = m.vertices[t[1]].cast<double>(),
               c = m.vertices[t[2]].cast<double>();
    volume += a.dot(b.cross(c)) / 6.0;
  }
  CHECK(volume == Approx((hi - lo).prod()));
}

std::string error_of(const fs::path& path, double scale = 1.0) {
  try {
    vts::load_mesh_file(path, scale);
  } catch (const MeshFileError& e) {
    return e.what();
  }
  return "(no error)";
}

const Vec3 kLo(-10, -5, 0), kHi(30, 5, 12);

}  // namespace

TEST_CASE("mesh files: a box from ASCII STL", "[mesh]") {
  TempDir dir;
  MeshLoadStats stats;
  const Mesh m = vts::load_mesh_file(dir.write("box.stl", ascii_stl(box_mesh(kLo, kHi))), 1.0, &stats);
  check_box(m, stats, kLo, kHi);
  CHECK(stats.file == (dir.path / "box.stl").string());
}

TEST_CASE("mesh files: a box from binary STL also with a header beginning with solid", "[mesh]") {
  for (const char* header : {"binary box", "solid box, but binary", "solid"}) {
    INFO("header '" << header << "'");
    TempDir dir;
    MeshLoadStats stats;
    const Mesh m = vts::load_mesh_file(dir.write("box.STL", binary_stl(box_mesh(kLo, kHi), header)), 1.0, &stats);
    check_box(m, stats, kLo, kHi);
  }
}

TEST_CASE("mesh files: a box from OBJ with quad faces", "[mesh]") {
  TempDir dir;
  MeshLoadStats stats;
  const Mesh m = vts::load_mesh_file(dir.write("box.obj", obj_box(kLo, kHi)), 1.0, &stats);
  check_box(m, stats, kLo, kHi);
}

TEST_CASE("mesh files: a box from ASCII and binary PLY", "[mesh]") {
  TempDir dir;
  MeshLoadStats stats;
  check_box(vts::load_mesh_file(dir.write("ascii.ply", ascii_ply_box(kLo, kHi)), 1.0, &stats), stats, kLo, kHi);
  check_box(vts::load_mesh_file(dir.write("binary.ply", binary_ply(box_mesh(kLo, kHi))), 1.0, &stats), stats,
            kLo, kHi);
}

TEST_CASE("mesh files: the unit scale multiplies every coordinate", "[mesh]") {
  TempDir dir;
  const fs::path file = dir.write("box.stl", binary_stl(box_mesh(Vec3(0, 0, 0), Vec3(0.25, 0.5, 2)), "m"));
  MeshLoadStats stats;
  const Mesh m = vts::load_mesh_file(file, 1000.0, &stats);
  check_box(m, stats, Vec3(0, 0, 0), Vec3(250, 500, 2000));
  const Mesh in = vts::load_mesh_file(file, *vts::mesh_unit_mm("in"));
  float max_z = 0.0f;
  for (const auto& v : in.vertices) max_z = std::max(max_z, v.z());
  CHECK(max_z == float(2.0 * 25.4));
}

TEST_CASE("mesh files: a box with a face missing has 4 open edges", "[mesh]") {
  TempDir dir;
  MeshLoadStats stats;
  const Mesh m = vts::load_mesh_file(dir.write("open.stl", binary_stl(box_mesh(kLo, kHi, kTop), "open")), 1.0, &stats);
  CHECK(m.triangle_count() == 10);
  CHECK(stats.triangles_kept == 10);
  CHECK(stats.open_edges == 4);
  CHECK(stats.nonmanifold_edges == 0);
  CHECK_FALSE(stats.closed());
}

TEST_CASE("mesh files: degenerate triangles are skipped and counted", "[mesh]") {
  TempDir dir;
  MeshLoadStats stats;
  SECTION("OBJ: a repeated index and three collinear points") {
    // Vertices 9 and 10 lie on the edge from corner 1 (lo) to corner 2 (lo + x).
    const std::string extra = "v 0 -5 0\nv 20 -5 0\nf 1 1 2\nf 1 9 10\n";
    const Mesh m = vts::load_mesh_file(dir.write("degenerate.obj", obj_box(kLo, kHi, extra)), 1.0, &stats);
    CHECK(stats.triangles_read == 14);
    CHECK(stats.skipped_degenerate == 2);
    CHECK(stats.triangles_kept == 12);
    CHECK(stats.closed());
    CHECK(m.vertices.size() == 8);  // only the vertices of kept triangles
  }
  SECTION("PLY: a repeated index and a zero-area triangle") {
    const Mesh m =
        vts::load_mesh_file(dir.write("degenerate.ply", ascii_ply_box(kLo, kHi, {"3 0 0 1", "3 0 1 0"})), 1.0,
                            &stats);
    CHECK(stats.skipped_degenerate == 2);
    CHECK(m.triangle_count() == 12);
    CHECK(stats.closed());
  }
  SECTION("binary STL: a NaN coordinate") {
    Mesh box = box_mesh(kLo, kHi);
    box.vertices.push_back(Eigen::Vector3f(std::numeric_limits<float>::quiet_NaN(), 0, 0));
    box.triangles.push_back({0, 1, 8});
    const Mesh m = vts::load_mesh_file(dir.write("nan.stl", binary_stl(box, "nan")), 1.0, &stats);
    CHECK(stats.triangles_read == 13);
    CHECK(stats.skipped_degenerate == 1);
    CHECK(m.triangle_count() == 12);
    for (const auto& v : m.vertices) CHECK(v.allFinite());
  }
}

TEST_CASE("mesh files: lines and points are ignored", "[mesh]") {
  TempDir dir;
  MeshLoadStats stats;
  const Mesh m = vts::load_mesh_file(dir.write("lines.obj", obj_box(kLo, kHi, "l 1 2\nl 2 3\n")), 1.0, &stats);
  CHECK(m.triangle_count() == 12);
  CHECK(stats.ignored_primitives == 2);
  CHECK(stats.closed());
}

TEST_CASE("mesh files: errors name the file and the problem", "[mesh]") {
  TempDir dir;
  const std::string d = dir.path.string() + "/";
  CHECK(error_of(dir.path / "missing.stl") == d + "missing.stl: mesh file not found");
  fs::create_directories(dir.path / "folder.stl");
  CHECK(error_of(dir.path / "folder.stl") == d + "folder.stl: is a directory, not a mesh file");
  CHECK(error_of(dir.write("part.step", "ISO-10303-21;\n")) ==
        d + "part.step: unsupported mesh file type '.step' (expected .stl, .obj or .ply)");
  CHECK(error_of(dir.write("part", "x")) == d + "part: no file extension (expected .stl, .obj or .ply)");
  const std::string not_mesh = error_of(dir.write("text.stl", "solid not really\n  this is text, not a mesh\n"));
  CHECK(not_mesh.rfind(d + "text.stl: not a mesh file: ", 0) == 0);
  CHECK(not_mesh.size() > (d + "text.stl: not a mesh file: ").size());
  CHECK(error_of(dir.write("empty.ply", "")).rfind(d + "empty.ply: not a mesh file: ", 0) == 0);
  CHECK(error_of(dir.write("lines.obj", "v 0 0 0\nv 1 0 0\nl 1 2\n")) ==
        d + "lines.obj: no triangles (only 1 points and lines)");
  CHECK(error_of(dir.write("flat.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n")) ==
        d + "flat.obj: no triangles (all 1 degenerate)");
  CHECK(error_of(dir.write("box.stl", ascii_stl(box_mesh(kLo, kHi))), 0.0) ==
        d + "box.stl: unit scale must be a finite number > 0 (mm per file unit)");
}

TEST_CASE("mesh files: write_mesh_file round trip is exact", "[mesh]") {
  // Awkward floats: a tilted, displaced fillet.
  const vts::Workpiece w = vts::build_workpiece(vts::JointType::Fillet, vts::default_params(vts::JointType::Fillet),
                                                vts::pose_from_xyz_rpy(Vec3(1.0 / 3.0, -7.1, 1e3), Vec3(3, -7, 25)));
  const Mesh mesh = w.mesh();
  REQUIRE(vts::mesh_edge_stats(mesh).closed());
  for (const char* name : {"fillet.stl", "fillet.ply", "fillet.obj"}) {
    INFO(name);
    TempDir dir;
    vts::write_mesh_file(dir.path / name, mesh);
    CHECK(dir.entries() == std::vector<std::string>{name});  // no temporary file left
    MeshLoadStats stats;
    const Mesh back = vts::load_mesh_file(dir.path / name, 1.0, &stats);
    REQUIRE(back.triangle_count() == mesh.triangle_count());
    CHECK(stats.skipped_degenerate == 0);
    CHECK(stats.closed());
    int differing = 0;
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
      for (int k = 0; k < 3; ++k) {
        const Eigen::Vector3f& a = mesh.vertices[mesh.triangles[t][k]];
        const Eigen::Vector3f& b = back.vertices[back.triangles[t][k]];
        for (int c = 0; c < 3; ++c)
          differing += std::bit_cast<std::uint32_t>(a[c] + 0.0f) != std::bit_cast<std::uint32_t>(b[c] + 0.0f);
      }
    CHECK(differing == 0);
  }
}

TEST_CASE("mesh files: write_mesh_file refuses what it cannot write and leaves nothing", "[mesh]") {
  TempDir dir;
  const Mesh box = box_mesh(kLo, kHi);
  const std::string d = dir.path.string() + "/";
  try {
    vts::write_mesh_file(dir.path / "box.3mf", box);
    FAIL("no error");
  } catch (const MeshFileError& e) {
    CHECK(std::string(e.what()) == d + "box.3mf: unsupported mesh file type '.3mf' (expected .stl, .obj or .ply)");
  }
  CHECK_THROWS_AS(vts::write_mesh_file(dir.path / "no" / "such" / "dir.stl", box), MeshFileError);
  Mesh bad = box;
  bad.triangles.push_back({0, 1, 8});
  try {
    vts::write_mesh_file(dir.path / "bad.ply", bad);
    FAIL("no error");
  } catch (const MeshFileError& e) {
    CHECK(std::string(e.what()) == d + "bad.ply: triangle 12 indexes vertex 8 of 8");
  }
  CHECK(dir.entries().empty());
  // An existing file is replaced whole.
  const fs::path file = dir.write("box.stl", "old contents");
  vts::write_mesh_file(file, box);
  CHECK(fs::file_size(file) == 84 + 50 * 12);
  CHECK(vts::load_mesh_file(file).triangle_count() == 12);
}

// ---- mesh workpieces in scene files ----

namespace {

// Box 0..20 x -5..5 x -2..0 cm, i.e. 200 x 100 x 20 mm, top at z = 0.
const Vec3 kBoxLoCm(0, -5, -2), kBoxHiCm(20, 5, 0);

std::string mesh_scene(const std::string& mesh_line, const std::string& path_text =
                                                         "path:\n"
                                                         "  start:\n"
                                                         "    position_mm: [0, 100, 160]\n"
                                                         "    rpy_deg: [180, 0, 0]\n"
                                                         "  profiles: 3\n") {
  return "scanner:\n  points: 64\n  ideal: true\n"  // lines 1-3
         "workpieces:\n"                            // 4
         "  - " + mesh_line + "\n"                  // 5
         "    unit: cm\n"                           // 6
         "    pose:\n"                              // 7
         "      position_mm: [0, 0, 10]\n"          // 8
         "      rpy_deg: [0, 0, 90]\n" +            // 9
         path_text;
}

}  // namespace

TEST_CASE("scene file: mesh workpiece with unit m is scaled by 1000 and posed", "[mesh][scene]") {
  TempDir dir;
  dir.write("box.stl", binary_stl(box_mesh(Vec3(0, 0, 0), Vec3(0.2, 0.1, 0.02)), "metres"));
  const vts::Cell cell = vts::load_scene(dir.write(
      "scene.yaml",
      "workpieces:\n  - mesh: box.stl\n    unit: m\n    joint: lap\n    pose:\n      position_mm: [1, 2, 3]\n"
      "path:\n  start:\n    position_mm: [100, 50, 200]\n    rpy_deg: [180, 0, 0]\n"));
  REQUIRE(cell.workpieces.size() == 1);
  const vts::Workpiece& w = cell.workpieces[0];
  CHECK(w.is_mesh());
  CHECK(w.has_joint());
  CHECK(w.type == vts::JointType::Lap);
  CHECK(w.mesh_unit_mm == 1000.0);
  CHECK(w.mesh_file == (fs::absolute(dir.path) / "box.stl").lexically_normal().string());
  CHECK(w.mesh_stats.closed());
  CHECK(w.mesh_stats.triangles_kept == 12);
  CHECK(w.plates.empty());
  CHECK(w.face_planes().empty());
  const Mesh m = w.mesh();
  REQUIRE(m.triangle_count() == 12);
  Eigen::Vector3f lo = m.vertices[0], hi = m.vertices[0];
  for (const auto& v : m.vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
  CHECK((lo - Eigen::Vector3f(1, 2, 3)).norm() < 1e-4f);
  CHECK((hi - Eigen::Vector3f(201, 102, 23)).norm() < 1e-4f);
  // The path direction defaults to the mesh frame's x.
  CHECK((cell.path.direction - Vec3::UnitX()).norm() < 1e-12);
}

TEST_CASE("scene file: relative mesh paths start at the scene file's directory", "[mesh][scene]") {
  TempDir dir;
  dir.write("parts/box.obj", obj_box(kLo, kHi));
  const fs::path scene = dir.write("scenes/deep/scene.yaml", mesh_scene("mesh: ../../parts/box.obj"));
  const vts::Cell cell = vts::load_scene(scene);
  CHECK(cell.workpieces[0].mesh_stats.file == (dir.path / "scenes/deep/../../parts/box.obj").string());
  CHECK(cell.workpieces[0].mesh_file == (fs::absolute(dir.path) / "parts/box.obj").lexically_normal().string());
  CHECK_FALSE(cell.workpieces[0].has_joint());
  // parse_scene resolves against its file name's directory in the same way.
  std::ifstream in(scene);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  CHECK(vts::parse_scene(text, scene.string()).workpieces[0].mesh().triangle_count() == 12);
  // An absolute path is used as it is.
  const vts::Cell abs = vts::parse_scene(mesh_scene("mesh: " + (dir.path / "parts/box.obj").string()), "x.yaml");
  CHECK(abs.workpieces[0].mesh().triangle_count() == 12);
}

TEST_CASE("scene file: mesh workpiece errors name file line and field", "[mesh][scene]") {
  TempDir dir;
  const std::string d = dir.path.string() + "/";
  dir.write("box.stl", ascii_stl(box_mesh(kLo, kHi)));
  dir.write("text.stl", "solid not really\n  this is text, not a mesh\n");
  const auto error = [&](const std::string& text) -> std::string {
    try {
      vts::load_scene(dir.write("s.yaml", text));
    } catch (const vts::SceneError& e) {
      return e.what();
    }
    return "(no error)";
  };
  CHECK(error(mesh_scene("mesh: missing.stl")) == d + "s.yaml:5: workpieces[0].mesh: " + d +
                                                      "missing.stl: mesh file not found");
  CHECK(error(mesh_scene("mesh: text.stl")).rfind(d + "s.yaml:5: workpieces[0].mesh: " + d + "text.stl: not a mesh file: ", 0) == 0);
  CHECK(error(mesh_scene("mesh: box.dxf")) == d + "s.yaml:5: workpieces[0].mesh: " + d +
                                                  "box.dxf: unsupported mesh file type '.dxf' (expected .stl, .obj or .ply)");
  CHECK(error(mesh_scene("mesh: [box.stl]")) == d + "s.yaml:5: workpieces[0].mesh: expected a mesh file name, got a list of 1");
  CHECK(error(mesh_scene("mesh: box.stl\n    gap_mm: 1")) ==
        d + "s.yaml:6: workpieces[0].gap_mm: unknown key (expected one of: mesh, unit, joint, pose)");
  CHECK(error(mesh_scene("mesh: box.stl\n    joint: tjoint")) ==
        d + "s.yaml:6: workpieces[0].joint: unknown joint 'tjoint' (expected one of: fillet, corner, lap, butt, vgroove, bevel, ugroove, jgroove, plate)");
  // Without path.start the default path cannot be derived.
  CHECK(error(mesh_scene("mesh: box.stl", "")) ==
        d + "s.yaml:5: path.start: missing (required when workpieces[0] is a mesh: a mesh has no seam to derive the "
            "default path from)");
  CHECK(error(mesh_scene("mesh: box.stl", "path:\n  standoff_mm: 80\n")) ==
        d + "s.yaml:10: path.start: missing (required when workpieces[0] is a mesh: a mesh has no seam to derive "
            "the default path from)");
  // A joint first gives the default path; a mesh after it needs nothing.
  CHECK(error("workpieces:\n  - joint: plate\n  - mesh: box.stl\n") == "(no error)");
  // unit
  const auto unit_error = [&](const std::string& unit) {
    std::string text = mesh_scene("mesh: box.stl");
    text.replace(text.find("unit: cm"), 8, "unit: " + unit);
    return error(text);
  };
  CHECK(unit_error("ft") == d + "s.yaml:6: workpieces[0].unit: unknown unit 'ft' (expected mm, cm, m, in, or a number: mm per file unit)");
  CHECK(unit_error("-2") == d + "s.yaml:6: workpieces[0].unit: unit = -2: must be > 0 (mm per file unit)");
  CHECK(unit_error("0") == d + "s.yaml:6: workpieces[0].unit: unit = 0: must be > 0 (mm per file unit)");
  CHECK(unit_error(".inf") == d + "s.yaml:6: workpieces[0].unit: must be a finite number, got '.inf'");
  CHECK(unit_error("'2'") == d + "s.yaml:6: workpieces[0].unit: unknown unit '2' (expected mm, cm, m, in, or a number: mm per file unit)");
  CHECK(unit_error("25.4") == "(no error)");
}

TEST_CASE("scene file: mesh workpiece round trip through scene_to_yaml", "[mesh][scene]") {
  TempDir dir;
  dir.write("box.ply", ascii_ply_box(kBoxLoCm, kBoxHiCm));
  for (const std::string& extra : {std::string(""), std::string("\n    joint: vgroove")}) {
    std::string text = mesh_scene("mesh: box.ply" + extra);
    for (const std::string unit : {"unit: cm", "unit: 0.1"}) {
      std::string t = text;
      t.replace(t.find("unit: cm"), 8, unit);
      const vts::Cell a = vts::load_scene(dir.write("s.yaml", t));
      const std::string yaml = vts::scene_to_yaml(a);
      INFO(yaml);
      const vts::Cell b = vts::parse_scene(yaml, "elsewhere/roundtrip.yaml");
      REQUIRE(b.workpieces.size() == 1);
      const vts::Workpiece &wa = a.workpieces[0], &wb = b.workpieces[0];
      CHECK(wb.is_mesh());
      CHECK(wb.mesh_file == wa.mesh_file);
      CHECK(wb.mesh_unit_mm == wa.mesh_unit_mm);
      CHECK(wb.has_joint() == wa.has_joint());
      CHECK(wb.type == wa.type);
      CHECK((wb.world_from_joint.matrix() - wa.world_from_joint.matrix()).cwiseAbs().maxCoeff() < 1e-12);
      CHECK(wb.mesh().vertices == wa.mesh().vertices);
      CHECK((b.path.start.matrix() - a.path.start.matrix()).cwiseAbs().maxCoeff() < 1e-12);
      // The stored scene can be read without its meshes (vts track does).
      const vts::Cell c = vts::parse_scene(yaml, "r.yaml", vts::MeshFiles::Skip);
      CHECK(c.workpieces[0].is_mesh());
      CHECK(c.workpieces[0].mesh().triangle_count() == 0);
      CHECK(c.workpieces[0].type == wa.type);
      CHECK(c.workpieces[0].has_joint() == wa.has_joint());
    }
  }
}

TEST_CASE("scene file: a mesh box scanned by the reference gives the hand-computed ranges", "[mesh][scene][reference]") {
  // The box is 200 x 100 x 20 mm in the file's frame (cm); the pose turns it
  // 90 degrees about z and lifts it 10 mm: x_w = -y, y_w = x, z_w = z + 10, so
  // it covers x_w -50..50, y_w 0..200, z_w -10..10. The sensor at (0, 100, 160)
  // looks straight down: every column meets the top face (z_w = 10) at sensor
  // z = 150, along y_w 100 -+ 150 tan 20 deg = 45.4 .. 154.6, inside the box.
  // With the top face missing, the rays meet the inside of the bottom face
  // (z_w = -10) at sensor z = 170.
  for (const int skip : {-1, kTop}) {
    INFO("missing face " << skip);
    TempDir dir;
    dir.write("box.stl", binary_stl(box_mesh(kBoxLoCm, kBoxHiCm, skip), "box in cm"));
    const vts::Cell cell = vts::load_scene(dir.write("s.yaml", mesh_scene("mesh: box.stl")));
    CHECK(cell.workpieces[0].mesh_stats.open_edges == (skip < 0 ? 0 : 4));
    const auto source = vts::make_reference_source(cell.scanner, cell.mesh());
    vts::Profile p;
    source->scan(cell.path.pose_at(0), p);
    const double depth = skip < 0 ? 150.0 : 170.0;
    const double half = std::tan(20.0 * 3.14159265358979323846 / 180.0);
    REQUIRE(p.size() == 64);
    for (int i = 0; i < p.size(); ++i) {
      INFO("column " << i);
      const double t = half * (2.0 * (i + 0.5) / 64 - 1.0);
      REQUIRE(p.valid[i] == 1);
      CHECK(p.z_mm[i] == Approx(depth).margin(1e-3).epsilon(0));
      CHECK(p.range_mm[i] == Approx(depth * std::sqrt(1.0 + t * t)).margin(1e-3).epsilon(0));
    }
  }
}
