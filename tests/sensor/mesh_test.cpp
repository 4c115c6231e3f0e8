// mesh_orientation (sensor/mesh.h) on solids built here with known windings.
#include <catch2/catch.hpp>

#include <string>
#include <utility>

#include "sensor/cell.h"
#include "sensor/mesh.h"
#include "tests/sensor/box_mesh.h"

using vts::test::box;
using vts::test::flipped;

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
