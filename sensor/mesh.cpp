#include "sensor/mesh.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include <Eigen/Geometry>

namespace vts {

void Mesh::append(const Mesh& other) {
  const auto base = static_cast<std::uint32_t>(vertices.size());
  vertices.insert(vertices.end(), other.vertices.begin(), other.vertices.end());
  triangles.reserve(triangles.size() + other.triangles.size());
  for (const auto& t : other.triangles)
    triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
}

MeshOrientation mesh_orientation(const Mesh& mesh) {
  const std::size_t nv = mesh.vertices.size();
  if (mesh.triangles.empty()) return MeshOrientation::Open;
  // Each directed edge once, and its reverse there too.
  std::vector<std::uint64_t> edges;
  edges.reserve(3 * mesh.triangles.size());
  for (const auto& t : mesh.triangles)
    for (int i = 0; i < 3; ++i) {
      if (t[i] >= nv) return MeshOrientation::Open;
      edges.push_back(std::uint64_t{t[i]} << 32 | t[(i + 1) % 3]);
    }
  std::sort(edges.begin(), edges.end());
  if (std::adjacent_find(edges.begin(), edges.end()) != edges.end()) return MeshOrientation::Open;
  for (const std::uint64_t e : edges)
    if (!std::binary_search(edges.begin(), edges.end(), (e << 32) | (e >> 32))) return MeshOrientation::Open;
  // The parts (vertices joined by triangles) and their signed volumes,
  // sum of p0 . (p1 x p2) / 6 about a point of the mesh.
  std::vector<std::uint32_t> root(nv);
  std::iota(root.begin(), root.end(), 0u);
  const auto find = [&](std::uint32_t v) {
    while (root[v] != v) v = root[v] = root[root[v]];
    return v;
  };
  for (const auto& t : mesh.triangles) {
    root[find(t[1])] = find(t[0]);
    root[find(t[2])] = find(t[0]);
  }
  const Eigen::Vector3d o = mesh.vertices[mesh.triangles[0][0]].cast<double>();
  double extent = 0.0;
  for (const auto& v : mesh.vertices) extent = std::max(extent, (v.cast<double>() - o).cwiseAbs().maxCoeff());
  std::vector<double> volume(nv, 0.0);
  std::vector<char> used(nv, 0);
  for (const auto& t : mesh.triangles) {
    used[t[0]] = used[t[1]] = used[t[2]] = 1;
    const Eigen::Vector3d a = mesh.vertices[t[0]].cast<double>() - o, b = mesh.vertices[t[1]].cast<double>() - o,
                          c = mesh.vertices[t[2]].cast<double>() - o;
    volume[find(t[0])] += a.dot(b.cross(c)) / 6.0;
  }
  // A part enclosing less than this is taken as enclosing none (a flat one).
  const double tiny = 1e-9 * extent * extent * extent;
  int outward = 0, inward = 0;
  for (std::uint32_t v = 0; v < nv; ++v) {
    if (find(v) != v || !used[v]) continue;
    if (volume[v] > tiny) ++outward;
    else if (volume[v] < -tiny) ++inward;
    else return MeshOrientation::Open;
  }
  if (outward > 0 && inward == 0) return MeshOrientation::Outward;
  if (inward > 0 && outward == 0) return MeshOrientation::Inward;
  return MeshOrientation::Open;
}

}  // namespace vts
