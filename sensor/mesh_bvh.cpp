#include "sensor/mesh_bvh.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace vts {
namespace {

// Larger leaves mean fewer nodes to visit (each a likely cache miss on big
// meshes); their triangles are tested from contiguous memory.
constexpr std::uint32_t kLeafSize = 16;

}  // namespace

MeshBvh::MeshBvh(std::span<const float> positions, std::span<const std::uint32_t> triangles) {
  tri_count_ = triangles.size() / 3;
  if (tri_count_ == 0) return;
  std::vector<Eigen::Vector3f> centroids(tri_count_);
  tri_boxes_.resize(tri_count_);
  corners_.resize(tri_count_);
  for (std::size_t t = 0; t < tri_count_; ++t) {
    std::array<float, 9>& c = corners_[t];
    for (int v = 0; v < 3; ++v)
      for (int k = 0; k < 3; ++k) c[3 * v + k] = positions[3 * std::size_t(triangles[3 * t + v]) + k];
    std::array<float, 6>& b = tri_boxes_[t];
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
  build(0, 0, static_cast<std::uint32_t>(tri_count_), centroids);
  // Corners in leaf order, so a leaf's triangles are contiguous in memory.
  std::vector<std::array<float, 9>> ordered(tri_count_);
  for (std::size_t i = 0; i < tri_count_; ++i) ordered[i] = corners_[order_[i]];
  corners_ = std::move(ordered);
  tri_boxes_.clear();
  tri_boxes_.shrink_to_fit();
}

void MeshBvh::build(std::uint32_t node, std::uint32_t begin, std::uint32_t end,
                    std::vector<Eigen::Vector3f>& centroids) {
  float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  float clo[3] = {INFINITY, INFINITY, INFINITY}, chi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (std::uint32_t i = begin; i < end; ++i) {
    const auto& b = tri_boxes_[order_[i]];
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
  build(left, begin, mid, centroids);
  const auto right = static_cast<std::uint32_t>(nodes_.size());
  nodes_[node].first = right;  // `n` may dangle after the push_backs
  nodes_.push_back({});
  build(right, mid, end, centroids);
}

void MeshBvh::crossing_plane(const Eigen::Vector3d& n, double d, const Eigen::Vector3d& box_lo,
                             const Eigen::Vector3d& box_hi, double tol_mm,
                             std::vector<std::uint32_t>& out) const {
  if (nodes_.empty()) return;
  const Eigen::Vector3d an = n.cwiseAbs();
  std::uint32_t stack[64];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& node = nodes_[stack[--top]];
    bool outside = false;
    double centre = 0.0, extent = 0.0;
    for (int k = 0; k < 3; ++k) {
      if (node.lo[k] > box_hi[k] || node.hi[k] < box_lo[k]) outside = true;
      centre += n[k] * 0.5 * (double(node.lo[k]) + node.hi[k]);
      extent += an[k] * 0.5 * (double(node.hi[k]) - node.lo[k]);
    }
    if (outside || std::abs(centre - d) > extent + tol_mm) continue;
    if (node.count == 0) {
      // Depth stays below 64: median splits halve the count at every level.
      stack[top++] = node.first;
      stack[top++] = static_cast<std::uint32_t>(&node - nodes_.data()) + 1;
      continue;
    }
    for (std::uint32_t i = node.first; i < node.first + node.count; ++i) {
      const auto& c = corners_[i];
      double lo = INFINITY, hi = -INFINITY;
      for (int v = 0; v < 3; ++v) {
        const double s = n[0] * c[3 * v] + n[1] * c[3 * v + 1] + n[2] * c[3 * v + 2] - d;
        lo = std::min(lo, s);
        hi = std::max(hi, s);
      }
      if (lo <= tol_mm && hi >= -tol_mm) out.push_back(i);
    }
  }
}

void MeshBvh::inside_planes(std::span<const Eigen::Vector4d> planes,
                            std::vector<std::uint32_t>& out) const {
  if (nodes_.empty()) return;
  std::uint32_t stack[64];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& node = nodes_[stack[--top]];
    bool outside = false;
    for (const Eigen::Vector4d& p : planes) {
      // The box corner farthest along the plane normal.
      double best = p[3];
      for (int k = 0; k < 3; ++k) best += p[k] * (p[k] >= 0.0 ? node.hi[k] : node.lo[k]);
      if (best < 0.0) {
        outside = true;
        break;
      }
    }
    if (outside) continue;
    if (node.count == 0) {
      stack[top++] = node.first;
      stack[top++] = static_cast<std::uint32_t>(&node - nodes_.data()) + 1;
      continue;
    }
    for (std::uint32_t i = node.first; i < node.first + node.count; ++i) {
      const auto& c = corners_[i];
      bool tri_outside = false;
      for (const Eigen::Vector4d& p : planes) {
        bool all_out = true;
        for (int v = 0; v < 3 && all_out; ++v)
          all_out = p[0] * c[3 * v] + p[1] * c[3 * v + 1] + p[2] * c[3 * v + 2] + p[3] < 0.0;
        if (all_out) {
          tri_outside = true;
          break;
        }
      }
      if (!tri_outside) out.push_back(i);
    }
  }
}

}  // namespace vts
