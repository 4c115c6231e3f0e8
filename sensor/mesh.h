#pragma once
// A triangle mesh in world coordinates, mm. Triangles wind counter-clockwise
// seen from outside (outward normals), though neither source culls back faces.
#include <array>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace vts {

struct Mesh {
  std::vector<Eigen::Vector3f> vertices;
  std::vector<std::array<std::uint32_t, 3>> triangles;

  void append(const Mesh& other);
  std::size_t triangle_count() const { return triangles.size(); }
};

}  // namespace vts
