#pragma once
// Closed box meshes with a known winding, for the tests of mesh_orientation
// (tests/sensor/mesh_test.cpp) and of the camera renderer's culling
// (tests/render/camera_image_test.cpp).
#include <cstdint>
#include <utility>

#include <Eigen/Core>

#include "sensor/mesh.h"

namespace vts::test {

// An axis-aligned box, counter-clockwise seen from outside: each face's
// corners in the order that makes (b - a) x (c - a) point out of the box
// (mesh_test.cpp checks one face by hand).
inline Mesh box(const Eigen::Vector3f& lo, const Eigen::Vector3f& hi) {
  Mesh m;
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

// The same mesh wound the other way.
inline Mesh flipped(Mesh m) {
  for (auto& t : m.triangles) std::swap(t[1], t[2]);
  return m;
}

}  // namespace vts::test
