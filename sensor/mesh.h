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

// Whether a mesh bounds solids, and which way its triangles face: every edge
// is an edge of exactly two triangles that run along it in opposite
// directions (one winding throughout), and every connected part encloses a
// positive signed volume (counter-clockwise from outside: Outward) or every
// one a negative one (Inward). Anything else, a border, a non-manifold edge,
// a flipped triangle, a part enclosing no volume or parts of both signs, is
// Open. A camera outside such solids sees only triangles facing it first,
// so the others may be culled without changing which pixels see the mesh.
enum class MeshOrientation { Open, Outward, Inward };
MeshOrientation mesh_orientation(const Mesh& mesh);

}  // namespace vts
