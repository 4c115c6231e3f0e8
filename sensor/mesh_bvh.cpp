#include "sensor/mesh_bvh.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstring>
#include <numeric>

#if defined(__SSE2__)
#include <immintrin.h>
#endif

#include <Eigen/Geometry>

#include "sensor/simd_clones.h"

namespace vts {
namespace {

// Larger leaves mean fewer nodes to visit (each a likely cache miss on big
// meshes); their triangles are tested from contiguous memory.
constexpr std::uint32_t kLeafSize = 16;

// Eight floats (GCC/Clang vector extension): one lane per plane of a query.
// AVX when the build targets it, two SSE registers otherwise. (Passed by
// reference: GCC warns that passing them by value changes with AVX.)
using Float8 = float __attribute__((vector_size(32)));
using Int8 = std::int32_t __attribute__((vector_size(32)));

// Whether some lane of a comparison's result is true.
inline bool any_lane(const Int8& m) {
#if defined(__AVX__)
  return _mm256_movemask_ps(reinterpret_cast<__m256>(m)) != 0;
#elif defined(__SSE2__)
  __m128 lo, hi;
  std::memcpy(&lo, &m, sizeof lo);
  std::memcpy(&hi, reinterpret_cast<const char*>(&m) + sizeof lo, sizeof hi);
  return (_mm_movemask_ps(lo) | _mm_movemask_ps(hi)) != 0;
#else
  std::int32_t any = 0;
  for (int l = 0; l < 8; ++l) any |= m[l];
  return any != 0;
#endif
}

// Four floats: the lanes of crossing_planes' float filter.
using Float4 = float __attribute__((vector_size(16)));
using Int4 = std::int32_t __attribute__((vector_size(16)));

inline bool any_lane4(const Int4& m) {
#if defined(__SSE2__)
  __m128 v;
  std::memcpy(&v, &m, sizeof v);
  return _mm_movemask_ps(v) != 0;
#else
  std::int32_t any = 0;
  for (int l = 0; l < 4; ++l) any |= m[l];
  return any != 0;
#endif
}

inline bool all_lanes4(const Int4& m) {
#if defined(__SSE2__)
  __m128 v;
  std::memcpy(&v, &m, sizeof v);
  return _mm_movemask_ps(v) == 0xf;
#else
  std::int32_t all = -1;
  for (int l = 0; l < 4; ++l) all &= m[l];
  return all == -1;
#endif
}

// Per lane: mask ? a : b (as bits: GCC scalarizes the vector ?: here).
inline void select(const Int8& mask, float a, float b, Float8& out) {
  const Int8 ia = reinterpret_cast<Int8>(Float8{} + a), ib = reinterpret_cast<Int8>(Float8{} + b);
  out = reinterpret_cast<Float8>((mask & ia) | (~mask & ib));
}

}  // namespace

MeshBvh::MeshBvh(std::span<const float> positions, std::span<const std::uint32_t> triangles) {
  tri_count_ = triangles.size() / 3;
  if (tri_count_ == 0) return;
  std::vector<Eigen::Vector3f> centroids(tri_count_);
  std::vector<Box> boxes(tri_count_);
  corners_.resize(tri_count_);
  for (std::size_t t = 0; t < tri_count_; ++t) {
    std::array<float, 9>& c = corners_[t];
    for (int v = 0; v < 3; ++v)
      for (int k = 0; k < 3; ++k) c[3 * v + k] = positions[3 * std::size_t(triangles[3 * t + v]) + k];
    for (float v : c)
      if (std::abs(v) > max_abs_coord_) max_abs_coord_ = std::abs(v);  // NaN compares false
    Box& b = boxes[t];
    for (int k = 0; k < 3; ++k) {
      b[k] = std::min({c[k], c[3 + k], c[6 + k]});
      b[3 + k] = std::max({c[k], c[3 + k], c[6 + k]});
      centroids[t][k] = 0.5f * (b[k] + b[3 + k]);
    }
  }
  order_.resize(tri_count_);
  std::iota(order_.begin(), order_.end(), 0u);
  nodes_.reserve(2 * (tri_count_ / kLeafSize + 1));
  nodes_.push_back({});
  build(0, 0, static_cast<std::uint32_t>(tri_count_), boxes, centroids);
  // Corners in leaf order, so a leaf's triangles are contiguous in memory.
  std::vector<std::array<float, 9>> ordered(tri_count_);
  for (std::size_t i = 0; i < tri_count_; ++i) ordered[i] = corners_[order_[i]];
  corners_ = std::move(ordered);

  // The facing bounds, children before parents (a child's index is larger
  // than its parent's). A triangle without a finite unit normal makes its
  // nodes' margins infinite: never dropped whole.
  node_facing_.resize(nodes_.size());
  for (std::size_t k = nodes_.size(); k-- > 0;) {
    const Node& node = nodes_[k];
    NodeFacing& f = node_facing_[k];
    if (node.count == 0) {
      const NodeFacing& a = node_facing_[k + 1];
      const NodeFacing& b = node_facing_[node.first];
      for (int j = 0; j < 3; ++j) {
        f.lo[j] = std::min(a.lo[j], b.lo[j]);
        f.hi[j] = std::max(a.hi[j], b.hi[j]);
      }
      f.per_n = std::max(a.per_n, b.per_n);
      f.per_edges = std::max(a.per_edges, b.per_edges);
      continue;
    }
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    double per_n = 0.0, per_edges = 0.0;
    for (std::uint32_t i = node.first; i < node.first + node.count; ++i) {
      const FaceTerms t = face_terms(i);
      const double len = t.nrm.norm();
      if (!(len > 0.0) || !std::isfinite(len)) {
        per_n = INFINITY;
        continue;
      }
      for (int j = 0; j < 3; ++j) {
        lo[j] = std::min(lo[j], t.nrm[j] / len);
        hi[j] = std::max(hi[j], t.nrm[j] / len);
      }
      per_n = std::max(per_n, t.per_n / len);
      per_edges = std::max(per_edges, t.per_edges / len);
    }
    // Widened far beyond the rounding of the unit normals and of the floats.
    for (int j = 0; j < 3; ++j) {
      f.lo[j] = static_cast<float>(lo[j] - 1e-6);
      f.hi[j] = static_cast<float>(hi[j] + 1e-6);
    }
    f.per_n = static_cast<float>(per_n * (1.0 + 1e-6));
    f.per_edges = static_cast<float>(per_edges * (1.0 + 1e-6));
  }
}

void MeshBvh::build(std::uint32_t node, std::uint32_t begin, std::uint32_t end,
                    const std::vector<Box>& boxes, const std::vector<Eigen::Vector3f>& centroids) {
  float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  float clo[3] = {INFINITY, INFINITY, INFINITY}, chi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (std::uint32_t i = begin; i < end; ++i) {
    const Box& b = boxes[order_[i]];
    const auto& c = centroids[order_[i]];
    for (int k = 0; k < 3; ++k) {
      // NaN coordinates fail both comparisons and leave the box as it is.
      lo[k] = std::min(lo[k], b[k]);
      hi[k] = std::max(hi[k], b[3 + k]);
      clo[k] = std::min(clo[k], c[k]);
      chi[k] = std::max(chi[k], c[k]);
    }
  }
  Node& n = nodes_[node];
  for (int k = 0; k < 3; ++k) {
    n.lo[k] = lo[k];
    n.hi[k] = hi[k];
  }
  int axis = 0;
  for (int k = 1; k < 3; ++k)
    if (chi[k] - clo[k] > chi[axis] - clo[axis]) axis = k;
  if (end - begin <= kLeafSize || !(chi[axis] > clo[axis])) {
    n.first = begin;
    n.count = end - begin;
    return;
  }
  const std::uint32_t mid = begin + (end - begin) / 2;
  std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end,
                   [&](std::uint32_t a, std::uint32_t b) { return centroids[a][axis] < centroids[b][axis]; });
  n.count = 0;
  const auto left = static_cast<std::uint32_t>(nodes_.size());
  nodes_.push_back({});
  build(left, begin, mid, boxes, centroids);
  const auto right = static_cast<std::uint32_t>(nodes_.size());
  nodes_[node].first = right;  // `n` may dangle after the push_backs
  nodes_.push_back({});
  build(right, mid, end, boxes, centroids);
}

template <class Visible, class Leaf>
[[gnu::always_inline]] inline void MeshBvh::walk(Visible visible, Leaf leaf) const {
  if (nodes_.empty()) return;
  // Depth stays below 64: median splits halve the count at every level.
  std::uint32_t stack[64];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& node = nodes_[stack[--top]];
    if (!visible(node)) continue;
    if (node.count == 0) {
      stack[top++] = node.first;
      stack[top++] = static_cast<std::uint32_t>(&node - nodes_.data()) + 1;
      continue;
    }
    for (std::uint32_t i = node.first; i < node.first + node.count; ++i) leaf(i);
  }
}

MeshBvh::Facing MeshBvh::facing_of(const Box3& box) const {
  Facing f;
  f.centre = 0.5 * (box.lo + box.hi);
  f.half = 0.5 * (box.hi - box.lo);
  f.r = max_abs_coord_ + f.centre.cwiseAbs().maxCoeff() + f.half.maxCoeff();
  return f;
}

[[gnu::always_inline]] inline MeshBvh::FaceTerms MeshBvh::face_terms(std::uint32_t i) const {
  const auto& c = corners_[i];
  FaceTerms t;
  t.a = Eigen::Vector3d(c[0], c[1], c[2]);
  t.e1 = Eigen::Vector3d(c[3], c[4], c[5]) - t.a;
  t.e2 = Eigen::Vector3d(c[6], c[7], c[8]) - t.a;
  t.nrm = t.e1.cross(t.e2);
  t.per_n = t.nrm.lpNorm<1>();
  t.per_edges = 7.0 * (t.e1.lpNorm<1>() + t.e2.lpNorm<1>());
  return t;
}

[[gnu::always_inline]] inline bool MeshBvh::may_face(std::uint32_t i, const Facing& f) const {
  const FaceTerms t = face_terms(i);
  // Largest n . (p - a) over the box.
  const double best = t.nrm.dot(f.centre - t.a) + t.nrm.cwiseAbs().dot(f.half);
  if (best >= 0.0) return true;
  // The corners are float roundings (at most 2^-24 r, r bounding every
  // coordinate) of the mesh the caller's exact test uses. Moving a by d
  // changes n . (p - a) by up to |n| d; moving the corners turns n by up to
  // 2 (|e1| + |e2|) d, which over |p - a| <= 2 sqrt(3) r changes it by up to
  // 7 (|e1| + |e2|) r d. The margin is 16 times the sum (and covers the double
  // arithmetic here many times over). Lengths taken as sums of |components|
  // (never shorter, and no square roots).
  const double margin = 0x1p-20 * f.r * (t.per_n + t.per_edges * f.r);
  return best >= -margin;
}

[[gnu::always_inline]] inline bool MeshBvh::node_may_face(std::uint32_t node, const Facing& f) const {
  // For a triangle under the node with unit normal u and corner a, and p in
  // the box: u . (p - a) is at most the sum over the axes of the largest
  // product of u's and (p - a)'s bounds (the box's minus the node's). When
  // that is below minus the largest margin over |n| may_face would allow,
  // every triangle under the node is turned away (with room for the
  // rounding here).
  const NodeFacing& nf = node_facing_[node];
  const Node& b = nodes_[node];
  double best = 0.0, reach = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double lo = f.centre[k] - f.half[k] - b.hi[k], hi = f.centre[k] + f.half[k] - b.lo[k];
    best += std::max(std::max(nf.lo[k] * lo, nf.lo[k] * hi), std::max(nf.hi[k] * lo, nf.hi[k] * hi));
    reach = std::max(reach, std::max(std::abs(lo), std::abs(hi)));
  }
  const double margin = 0x1p-20 * f.r * (nf.per_n + nf.per_edges * f.r) + 1e-9 * reach;
  return !(best < -margin);  // NaN: kept
}

VTS_SIMD_CLONES
void MeshBvh::crossing_planes(const Eigen::Vector3d& n, std::span<const double> d,
                              const Eigen::Vector3d& box_lo, const Eigen::Vector3d& box_hi,
                              double tol_mm, std::span<std::vector<std::uint32_t>> out,
                              const Box3* facing, std::span<const Eigen::Vector4d> keep) const {
  if (d.empty()) return;
  // The offsets in increasing order (a triangle crosses a contiguous run of
  // them: found from the mean spacing instead of testing every one), at
  // most kMaxSorted per traversal.
  constexpr std::size_t kMaxSorted = 64;
  if (d.size() > kMaxSorted) {
    crossing_planes(n, d.first(kMaxSorted), box_lo, box_hi, tol_mm, out.first(kMaxSorted), facing, keep);
    crossing_planes(n, d.subspan(kMaxSorted), box_lo, box_hi, tol_mm, out.subspan(kMaxSorted), facing, keep);
    return;
  }
  const std::size_t count = d.size();
  std::array<std::pair<double, std::uint32_t>, kMaxSorted> sorted;
  for (std::size_t k = 0; k < count; ++k) sorted[k] = {d[k], static_cast<std::uint32_t>(k)};
  std::sort(sorted.begin(), sorted.begin() + count);
  const double d_min = sorted[0].first, d_max = sorted[count - 1].first;
  const double per_spacing = d_max > d_min ? double(count - 1) / (d_max - d_min) : 0.0;  // 1 / mean spacing
  const double mid = 0.5 * (d_min + d_max), half = 0.5 * (d_max - d_min) + tol_mm;
  const Eigen::Vector3d an = n.cwiseAbs();
  const Facing face = facing ? facing_of(*facing) : Facing{};
  // A float filter before the exact leaf test, in the lanes of 4-float
  // vectors: the slab's two sides (n . p >= d_min - tol, n . p <= d_max +
  // tol) and up to two `keep` half-spaces, each made more inclusive by a
  // bound on the float rounding (as in inside_planes). A triangle with all
  // corners outside one lane's plane fails the exact test too, so dropping
  // it here changes nothing; the rest go on to the exact test. Only for a
  // thin slab (a few planes: most triangles of the leaves it reaches lie
  // outside it); a block of 16 parallel planes keeps most of them, and
  // the filter would only add its cost (callgrind, docs/PERFORMANCE.md).
  //
  // The float value of a lane differs from the exact n . p + w plus the
  // widening m by less than m / 2, so a corner scoring 3 m or more lies
  // inside that half-space by more than m: with a single plane, a triangle
  // with such a corner in every lane passes the exact slab and `keep` tests
  // (which are then skipped), only the facing test is left.
  Float4 fx{}, fy{}, fz{}, fw{}, clear{};
  for (int l = 0; l < 4; ++l) fw[l] = 1.0f;
  const bool prefilter = count <= 4 && keep.size() <= 2;
  if (prefilter) {
    auto lane = [&](int l, double x, double y, double z, double w) {
      const double bound = std::abs(w) + (std::abs(x) + std::abs(y) + std::abs(z)) * max_abs_coord_;
      fx[l] = static_cast<float>(x);
      fy[l] = static_cast<float>(y);
      fz[l] = static_cast<float>(z);
      fw[l] = static_cast<float>(w + 16.0 * 0x1p-24 * bound);
      clear[l] = static_cast<float>(3.0 * 16.0 * 0x1p-24 * bound);
    };
    lane(0, n[0], n[1], n[2], tol_mm - d_min);
    lane(1, -n[0], -n[1], -n[2], d_max + tol_mm);
    for (std::size_t l = 0; l < keep.size(); ++l) lane(2 + int(l), keep[l][0], keep[l][1], keep[l][2], keep[l][3]);
  }
  walk(
      [&](const Node& node) __attribute__((always_inline)) {
        double centre = 0.0, extent = 0.0;
        for (int k = 0; k < 3; ++k) {
          if (node.lo[k] > box_hi[k] || node.hi[k] < box_lo[k]) return false;
          centre += n[k] * 0.5 * (double(node.lo[k]) + node.hi[k]);
          extent += an[k] * 0.5 * (double(node.hi[k]) - node.lo[k]);
        }
        if (!(std::abs(centre - mid) <= extent + half)) return false;
        for (const Eigen::Vector4d& h : keep) {
          // The box's corner farthest into the half-space, summed in the leaf
          // test's order: rounding is monotonic, so no corner of a triangle
          // inside the box scores more than the box does.
          const double x = h[0] >= 0.0 ? node.hi[0] : node.lo[0], y = h[1] >= 0.0 ? node.hi[1] : node.lo[1],
                       z = h[2] >= 0.0 ? node.hi[2] : node.lo[2];
          if (h[0] * x + h[1] * y + h[2] * z + h[3] < 0.0) return false;
        }
        return !facing || node_may_face(static_cast<std::uint32_t>(&node - nodes_.data()), face);
      },
      [&](std::uint32_t i) __attribute__((always_inline)) {
        const auto& c = corners_[i];
        if (prefilter) {
          const Float4 d0 = fw + fx * c[0] + fy * c[1] + fz * c[2];
          const Float4 d1 = fw + fx * c[3] + fy * c[4] + fz * c[5];
          const Float4 d2 = fw + fx * c[6] + fy * c[7] + fz * c[8];
          if (any_lane4((d0 < 0.0f) & (d1 < 0.0f) & (d2 < 0.0f))) return;
          if (count == 1 && all_lanes4((d0 >= clear) | (d1 >= clear) | (d2 >= clear))) {
            if (facing && !may_face(i, face)) return;
            out[sorted[0].second].push_back(i);
            return;
          }
        }
        double lo = INFINITY, hi = -INFINITY;
        for (int v = 0; v < 3; ++v) {
          const double s = n[0] * c[3 * v] + n[1] * c[3 * v + 1] + n[2] * c[3 * v + 2];
          lo = std::min(lo, s);
          hi = std::max(hi, s);
        }
        // Both tests are monotonic in the offset: the first offset with
        // lo <= d + tol, then on while hi >= d - tol. The first is guessed
        // from the mean spacing (exact for a path of equal steps), then
        // stepped to.
        std::size_t k = 0;
        if (per_spacing > 0.0) {
          const double g = (lo - tol_mm - d_min) * per_spacing;
          k = g <= 0.0 ? 0 : std::min(count - 1, static_cast<std::size_t>(g));
        }
        while (k > 0 && lo <= sorted[k - 1].first + tol_mm) --k;
        while (k < count && !(lo <= sorted[k].first + tol_mm)) ++k;
        if (k == count || !(hi >= sorted[k].first - tol_mm)) return;
        for (const Eigen::Vector4d& h : keep) {
          double best = -INFINITY;
          for (int v = 0; v < 3; ++v)
            best = std::max(best, h[0] * c[3 * v] + h[1] * c[3 * v + 1] + h[2] * c[3 * v + 2] + h[3]);
          if (best < 0.0) return;
        }
        if (facing && !may_face(i, face)) return;
        for (; k < count && hi >= sorted[k].first - tol_mm; ++k) out[sorted[k].second].push_back(i);
      });
}

VTS_SIMD_CLONES
void MeshBvh::inside_planes(std::span<const Eigen::Vector4d> planes, std::vector<std::uint32_t>& out,
                            const Box3* facing) const {
  const Facing face = facing ? facing_of(*facing) : Facing{};
  // The planes in the lanes of 8-float vectors (lanes without a plane:
  // 0 . p + 1 >= 0, always inside), each made more inclusive by a bound on
  // the float rounding of n . p + w over the mesh's coordinates, so the
  // float tests keep everything the double ones would.
  assert(planes.size() <= 8);
  Float8 nx{}, ny{}, nz{}, w{};
  for (int l = 0; l < 8; ++l) w[l] = 1.0f;
  for (std::size_t l = 0; l < std::min<std::size_t>(planes.size(), 8); ++l) {
    const Eigen::Vector4d& p = planes[l];
    const double bound = std::abs(p[3]) + (std::abs(p[0]) + std::abs(p[1]) + std::abs(p[2])) * max_abs_coord_;
    nx[l] = static_cast<float>(p[0]);
    ny[l] = static_cast<float>(p[1]);
    nz[l] = static_cast<float>(p[2]);
    w[l] = static_cast<float>(p[3] + 16.0 * 0x1p-24 * bound);
  }
  const Int8 px = nx >= 0.0f, py = ny >= 0.0f, pz = nz >= 0.0f;  // which box corner is farthest
  walk(
      // always_inline: GCC inlines nothing across the clone's arch=, so a
      // lambda left out of line would run the default (SSE2) code per call.
      [&](const Node& node) __attribute__((always_inline)) {
        Float8 x, y, z;
        select(px, node.hi[0], node.lo[0], x);
        select(py, node.hi[1], node.lo[1], y);
        select(pz, node.hi[2], node.lo[2], z);
        if (any_lane(w + nx * x + ny * y + nz * z < 0.0f)) return false;
        return !facing || node_may_face(static_cast<std::uint32_t>(&node - nodes_.data()), face);
      },
      [&](std::uint32_t i) __attribute__((always_inline)) {
        const auto& c = corners_[i];
        const Float8 d0 = w + nx * c[0] + ny * c[1] + nz * c[2];
        const Float8 d1 = w + nx * c[3] + ny * c[4] + nz * c[5];
        const Float8 d2 = w + nx * c[6] + ny * c[7] + nz * c[8];
        // Kept unless some plane has all three corners outside.
        if (any_lane((d0 < 0.0f) & (d1 < 0.0f) & (d2 < 0.0f))) return;
        if (facing && !may_face(i, face)) return;
        out.push_back(i);
      });
}

}  // namespace vts
