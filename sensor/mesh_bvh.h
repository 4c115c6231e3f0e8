#pragma once
// A bounding-volume hierarchy over a mesh's triangles, for the queries the
// raster emulator makes before it draws (render/raster_source.cpp): which
// triangles cross a laser plane inside the fan, and which lie inside a convex
// region (the camera-shadow frustum). Both queries are conservative at the
// node level and exact per triangle, in double, with a small tolerance on the
// inclusive side, so culling never drops a triangle the rasterizer would hit.
//
// Built once (O(T log T)); queries touch only the nodes near the region, so
// their cost grows with the triangles found, not with the mesh.
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include <Eigen/Core>

namespace vts {

class MeshBvh {
 public:
  MeshBvh() = default;
  // positions: xyz per vertex; triangles: 3 vertex indices each. Every index
  // must be < positions.size() / 3 (the caller checks).
  MeshBvh(std::span<const float> positions, std::span<const std::uint32_t> triangles);

  std::size_t triangle_count() const { return tri_count_; }

  // Queries append entries: positions in the hierarchy's own triangle order,
  // where a leaf's triangles lie together in memory. triangle(e) gives the
  // triangle number (index into `triangles` / 3), corners(e) its corners
  // (x, y, z of each, as given).
  std::uint32_t triangle(std::uint32_t entry) const { return order_[entry]; }
  const std::array<float, 9>& corners(std::uint32_t entry) const { return corners_[entry]; }

  // For each offset d[k], the triangles with vertices on both sides of (or
  // on) the plane dot(n, p) = d[k] (within tol_mm) whose bounding box meets
  // the box [box_lo, box_hi]: their entries are appended to out[k], each
  // once, in no particular order. Parallel planes (the laser planes of a
  // straight path) share one traversal, over the slab between the extreme
  // offsets. out.size() must be at least d.size().
  //
  // With `facing`, only triangles whose front side faces some point of that
  // box are kept: a triangle with corners a, b, c (in the order given) is
  // dropped when every point p of the box lies behind its plane, that is
  // ((b - a) x (c - a)) . (p - a) < 0, by more than a bound on the rounding
  // of the corners (so nothing that faces a point of the box, exactly or
  // within rounding, is dropped). For closed meshes, whose back faces are
  // always hidden behind front faces.
  //
  // With `keep` (half-spaces dot(plane.xyz, p) + plane.w >= 0, such as the
  // sides of a laser fan), triangles with every corner outside one of
  // them are dropped too, and so is every node whose box is. Tested in
  // double on the corners as given: the caller moves the planes outwards by
  // whatever margin it needs.
  struct Box3 {
    Eigen::Vector3d lo, hi;
  };
  void crossing_planes(const Eigen::Vector3d& n, std::span<const double> d,
                       const Eigen::Vector3d& box_lo, const Eigen::Vector3d& box_hi,
                       double tol_mm, std::span<std::vector<std::uint32_t>> out,
                       const Box3* facing = nullptr, std::span<const Eigen::Vector4d> keep = {}) const;

  // Entries of the triangles not entirely outside any one of the half-spaces
  // dot(plane.xyz, p) + plane.w >= 0 (a convex region; up to 8 planes).
  // Conservative: a triangle outside the region but not outside a single
  // plane is kept. Tested in float, all planes at once, with each plane
  // moved outwards by a bound on the rounding (so nothing the exact test
  // would keep is dropped).
  // With `facing`, as in crossing_planes.
  void inside_planes(std::span<const Eigen::Vector4d> planes, std::vector<std::uint32_t>& out,
                     const Box3* facing = nullptr) const;

 private:
  struct Node {
    float lo[3], hi[3];
    std::uint32_t first;  // leaf: first entry in order_; inner: right child (left = this + 1)
    std::uint32_t count;  // leaf: triangle count; inner: 0
  };
  using Box = std::array<float, 6>;  // lo xyz, hi xyz
  void build(std::uint32_t node, std::uint32_t begin, std::uint32_t end,
             const std::vector<Box>& boxes, const std::vector<Eigen::Vector3f>& centroids);
  // Depth-first walk: descends into the nodes `visible` accepts and hands
  // every entry of a visible leaf to `leaf`.
  template <class Visible, class Leaf>
  void walk(Visible visible, Leaf leaf) const;
  // A facing box as may_face uses it, set up once per query: its centre and
  // half extent, and r, a bound on every coordinate the test meets.
  struct Facing {
    Eigen::Vector3d centre, half;
    double r = 0.0;
  };
  Facing facing_of(const Box3& box) const;
  // What the facing tests need of the triangle at entry i: its first corner
  // a, edges e1 = b - a and e2 = c - a, normal e1 x e2, and may_face's two
  // margin coefficients |n|_1 and 7 (|e1|_1 + |e2|_1). One function, so that
  // node_may_face's bounds are built from exactly what may_face tests.
  struct FaceTerms {
    Eigen::Vector3d a, e1, e2, nrm;
    double per_n = 0.0, per_edges = 0.0;
  };
  FaceTerms face_terms(std::uint32_t i) const;
  // Whether the triangle at entry i may face a point of the box (see
  // crossing_planes).
  bool may_face(std::uint32_t i, const Facing& f) const;
  // Whether some triangle under the node may face a point of the box: false
  // only where may_face is false for every one of them.
  bool node_may_face(std::uint32_t node, const Facing& f) const;

  std::vector<Node> nodes_;
  // Per node, what node_may_face needs of its triangles: a box around their
  // unit normals, and the largest of may_face's two margin coefficients
  // (|n|_1 and 7 (|e1|_1 + |e2|_1)) over |n|, each rounded up.
  struct NodeFacing {
    float lo[3], hi[3];
    float per_n, per_edges;
  };
  std::vector<NodeFacing> node_facing_;
  std::vector<std::uint32_t> order_;            // triangle numbers in leaf order
  std::vector<std::array<float, 9>> corners_;   // per triangle, in leaf order
  std::size_t tri_count_ = 0;
  double max_abs_coord_ = 0.0;  // largest |coordinate| of a corner (bounds float rounding)
};

}  // namespace vts
