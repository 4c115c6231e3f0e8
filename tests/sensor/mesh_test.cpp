// mesh_orientation (sensor/mesh.h) on solids built here with known windings.
#include <catch2/catch.hpp>

#include <string>
#include <utility>

#include "sensor/cell.h"
#include "sensor/mesh.h"

namespace {

// An axis-aligned box, counter-clockwise seen from outside: each face's
// corners in the order that makes (b - a) x (c - a) point out of the box.
vts::Mesh box(const Eigen::Vector3f& lo, const Eigen::Vector3f& hi) {
  vts::Mesh m;
  for (int k = 0; k < 8; ++k)
    m.vertices.push_back({(k & 1) ? hi.x() : lo.x(), (k & 2) ? hi.y() : lo.y(), (k & 4) ? hi.z() : lo.z()});
  const auto quad = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t d) {
    m.triangles.push_back({a, b, c});
    m.triangles.push_back({a, c, d});
  };
  quad(0, 2, 3, 1);  // z = lo, normal -z
  quad(4, 5, 7, 6);  // z = hi, normal +z
  quad(0, 1, 5, 4);  // y = lo, normal -y
  quad(2, 6, 7, 3);  // y = hi, normal +y
  quad(0, 4, 6, 2);  // x = lo, normal -x
  quad(1, 3, 7, 5);  // x = hi, normal +x
  return m;
}

vts::Mesh flipped(vts::Mesh m) {
  for (auto& t : m.triangles) std::swap(t[1], t[2]);
  return m;
}

}  // namespace

TEST_CASE("mesh_orientation tells closed outward, closed inward and open meshes apart", "[mesh]") {
  const vts::Mesh cube = box({0, 0, 0}, {10, 20, 30});
  // The winding checked by hand: the first triangle's normal is -z.
  const Eigen::Vector3f n = (cube.vertices[2] - cube.vertices[0]).cross(cube.vertices[3] - cube.vertices[0]);
  REQUIRE(n.z() < 0.0f);
  CHECK(vts::mesh_orientation(cube) == vts::MeshOrientation::Outward);
  CHECK(vts::mesh_orientation(flipped(cube)) == vts::MeshOrientation::Inward);

  vts::Mesh holed = cube;
  holed.triangles.pop_back();
  CHECK(vts::mesh_orientation(holed) == vts::MeshOrientation::Open);

  vts::Mesh one_flipped = cube;
  std::swap(one_flipped.triangles[3][1], one_flipped.triangles[3][2]);
  CHECK(vts::mesh_orientation(one_flipped) == vts::MeshOrientation::Open);

  // Two parts: both outward, both inward, or one of each.
  vts::Mesh two = cube;
  two.append(box({50, 0, 0}, {60, 5, 5}));
  CHECK(vts::mesh_orientation(two) == vts::MeshOrientation::Outward);
  CHECK(vts::mesh_orientation(flipped(two)) == vts::MeshOrientation::Inward);
  vts::Mesh mixed = cube;
  mixed.append(flipped(box({50, 0, 0}, {60, 5, 5})));
  CHECK(vts::mesh_orientation(mixed) == vts::MeshOrientation::Open);

  // A non-manifold edge: a third triangle on one of the cube's edges.
  vts::Mesh fin = cube;
  fin.vertices.push_back({-5, -5, 0});
  fin.triangles.push_back({0, 1, static_cast<std::uint32_t>(fin.vertices.size() - 1)});
  CHECK(vts::mesh_orientation(fin) == vts::MeshOrientation::Open);

  // A flat closed surface (two triangles back to back) encloses nothing.
  vts::Mesh sheet;
  sheet.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  sheet.triangles = {{0, 1, 2}, {0, 2, 1}};
  CHECK(vts::mesh_orientation(sheet) == vts::MeshOrientation::Open);

  // Vertices no triangle uses change nothing; an index past the vertices is open.
  vts::Mesh spare = cube;
  spare.vertices.push_back({100, 100, 100});
  CHECK(vts::mesh_orientation(spare) == vts::MeshOrientation::Outward);
  vts::Mesh bad = cube;
  bad.triangles.push_back({0, 1, 99});
  CHECK(vts::mesh_orientation(bad) == vts::MeshOrientation::Open);
  CHECK(vts::mesh_orientation(vts::Mesh{}) == vts::MeshOrientation::Open);
}

TEST_CASE("the built-in v-groove cell's workpieces are closed solids wound outward", "[mesh]") {
  auto cell = vts::builtin_cell("vgroove");
  REQUIRE(cell);
  CHECK(vts::mesh_orientation(cell->mesh()) == vts::MeshOrientation::Outward);
}
