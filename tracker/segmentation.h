#pragma once
// Steps 1 to 4 of the paper's Figure 4: outlier elimination, recursive split,
// merge, and a least-squares line per segment.
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <type_traits>
#include <vector>

#include "tracker/geometry.h"
#include "tracker/params.h"

namespace vts::tracker {

// An allocator that default-initialises instead of value-initialising, so that
// resize() on the reused buffers costs nothing per element.
template <class T, class A = std::allocator<T>>
struct DefaultInitAllocator : A {
  using A::A;
  template <class U>
  struct rebind {
    using other = DefaultInitAllocator<U, typename std::allocator_traits<A>::template rebind_alloc<U>>;
  };
  template <class U>
  void construct(U* p) noexcept(std::is_nothrow_default_constructible_v<U>) {
    ::new (static_cast<void*>(p)) U;
  }
  template <class U, class... Args>
  void construct(U* p, Args&&... args) {
    std::allocator_traits<A>::construct(static_cast<A&>(*this), p, std::forward<Args>(args)...);
  }
};
template <class T>
using Buffer = std::vector<T, DefaultInitAllocator<T>>;

// Sums over a set of points, relative to a reference point (for precision):
// adding, removing and combining sets is O(1).
struct PointSums {
  int n = 0;
  double sy = 0.0, sz = 0.0, syy = 0.0, szz = 0.0, syz = 0.0;

  void add(const Vec2& d, double sign = 1.0) {
    n += sign > 0.0 ? 1 : -1;
    sy += sign * d.x();
    sz += sign * d.y();
    syy += sign * d.x() * d.x();
    szz += sign * d.y() * d.y();
    syz += sign * d.x() * d.y();
  }
  PointSums& operator+=(const PointSums& o) {
    n += o.n;
    sy += o.sy, sz += o.sz, syy += o.syy, szz += o.szz, syz += o.syz;
    return *this;
  }
  // The sums of a run without a part of it (rounding differs from summing
  // the rest afresh).
  PointSums operator-(const PointSums& o) const {
    PointSums d = *this;
    d.n -= o.n;
    d.sy -= o.sy, d.sz -= o.sz, d.syy -= o.syy, d.szz -= o.szz, d.syz -= o.syz;
    return d;
  }
};

// A run of consecutive kept points lying on one line.
struct Segment {
  int first = 0;      // index of its first point in Segmentation::points
  int last = 0;       // index of its last point (inclusive)
  int first_col = 0;  // profile index (column) of the first point
  int last_col = 0;   // profile index of the last point
  Line line;          // total least-squares fit, normal towards the sensor
  double rms_mm = 0.0;
  Vec2 centroid = Vec2::Zero();
  bool fitted = false;  // false for a single point (no line)
  PointSums sums;       // of its points relative to Segmentation's reference point

  int count() const { return last - first + 1; }
};

// A region of step 2's recursive split, points [a, b], and once known the
// sums of its points but the last (a leaf's segment ends where the next
// region starts, at b, unless it ends the run).
struct SplitRegion {
  int a = 0, b = 0;
  bool summed = false;
  PointSums head;
};

// Column states in Segmentation::column_state.
enum : std::uint8_t { kColumnInvalid = 0, kColumnKept = 1, kColumnOutlier = 2 };

// The result of steps 1 to 4, reused between profiles (clear() keeps the
// buffers, so after the first profiles nothing is allocated).
struct Segmentation {
  // Kept points (valid and not outliers) in scan order, sensor frame (mm),
  // and the profile column each came from.
  Buffer<Vec2> points;
  Buffer<int> cols;
  // cuts[j] = 1 where the profile is discontinuous between points j and j+1
  // (invalid columns between them, or a jump: SegmentParams::break_*).
  Buffer<std::uint8_t> cuts;
  // Points removed by step 1 and their columns, in scan order.
  std::vector<Vec2> outlier_points;
  std::vector<int> outlier_cols;
  // Segments after split, merge and boundary refinement, in scan order.
  std::vector<Segment> segments;
  // Per profile column: kColumnInvalid, kColumnKept or kColumnOutlier.
  std::vector<std::uint8_t> column_state;
  // Tangent of profile column `col`'s ray about the ray origin, (y - y0) /
  // (z - z0): measured where the column has a kept point, else linear in the
  // column index between (or beyond) the nearest kept columns. NaN with fewer
  // than two kept points or outside the region of interest.
  double column_tan(int col) const;
  int valid_points = 0;  // usable points before outlier elimination
  int outliers = 0;
  std::string error;     // set when the input itself is malformed

  // Sums, moments and line fit (normal towards the sensor) of points
  // [first, last]; O(last - first). sums() keeps its answer for sums_near
  // (sums_memo_): not for calls on one Segmentation from several threads at
  // once.
  PointSums sums(int first, int last) const;
  // The sums of those points of [first, last] within max_distance of line,
  // added in the same order (with all of them, the same as sums(): then
  // sums()' own answer for that range, if it gave one this profile).
  PointSums sums_near(const Line& line, double max_distance, int first, int last) const;
  Moments moments(const PointSums& sums) const;
  Moments moments(int first, int last) const { return moments(sums(first, last)); }
  std::optional<LineFit> fit(const PointSums& sums) const;
  std::optional<LineFit> fit(int first, int last) const { return fit(sums(first, last)); }
  // The sums of [first, k - 1] with point k added: sums(first, k), the same
  // additions in the same order.
  PointSums with_point(PointSums sums, int k) const {
    sums.add(points[k] - ref_);
    return sums;
  }
  // Number of invalid columns strictly between columns a < b.
  int invalid_columns_between(int a, int b) const;

  // Resets the counts and lists; points and cols are left to segment_profile.
  void clear();

  // Scratch, kept for reuse.
  Vec2 ref_ = Vec2::Zero();
  Vec2 origin_ = Vec2::Zero();
  int roi_lo_ = 0, roi_hi_ = -1;
  Buffer<std::uint8_t> keep_, spike_, usable_;
  Buffer<float> ys_, zs_, steps_;
  std::vector<SplitRegion> stack_, leaves_;
  // sums()' last answers this profile (the segments' own ranges, mostly),
  // for sums_near.
  struct SumsMemo {
    int first = 0, last = -1;
    PointSums sums;
  };
  mutable std::array<SumsMemo, 32> sums_memo_{};
  mutable std::size_t sums_memo_next_ = 0;
};

// Runs steps 1 to 4 on one profile. `out` is overwritten; its buffers are
// reused. Malformed input (spans of different lengths) sets out.error and
// leaves no points. The tracker passes its TrackerParams::surface_tol_mm as
// - detach_tol_mm (with TrackerParams::noise_aware_detach, else 0): step 4
//   detaches no end point that lies within it of its segment's line (noise
//   alone moves a point that far; see SegmentParams::fit_tol_mm);
// - rough_tol_mm (with TrackerParams::split_rough_segments, else 0): step 2
//   also splits a region of at least s_min points whose line fit has an rms
//   above it (no line with noise alone) at its farthest point from the chord,
//   if that lies more than rough_tol_mm off and has at least 3 points on
//   either side, each fitting a line with at most half the whole's rms (a
//   corner shallower than t_split);
// - island_tol_mm (with TrackerParams::noise_aware_islands, else 0): step 1
//   keeps an island whose points lie within it of their chord (and the next
//   point beyond a cut continues that line) as a piece of a surface.
void segment_profile(const ProfileView& profile, const SegmentationParams& params, Segmentation& out,
                     double detach_tol_mm = 0.0, double rough_tol_mm = 0.0, double island_tol_mm = 0.0);

}  // namespace vts::tracker
