#include "tracker/segmentation.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <tuple>
#include <type_traits>

namespace vts::tracker {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// p lies farther than `limit` from the line through a and b (from a if they
// coincide); no square root. In scalars: Eigen's 2-vectors need lane
// shuffles for the cross product.
[[gnu::always_inline]] inline bool beyond_chord(const Vec2& a, const Vec2& b, const Vec2& p, double limit) {
  const double dy = b.x() - a.x(), dz = b.y() - a.y();
  const double len2 = dy * dy + dz * dz;
  const double py = p.x() - a.x(), pz = p.y() - a.y();
  if (len2 < 1e-24) return py * py + pz * pz > limit * limit;
  const double c = dy * pz - dz * py;
  return c * c > limit * limit * len2;
}

// cut[j] = 1 where the profile is discontinuous between points j and j+1:
// `gap(j)` says whether invalid columns lie between them (asked only where
// their columns are not adjacent); otherwise a jump is a step longer than
// break_min_mm and break_ratio times the shorter neighbouring step.
// steps2[j] holds the squared step from j to j+1. Jumps (bit 0) and columns
// that are not adjacent (bit 1) are marked branch-free first, so that the loop
// vectorises; then the few marked 2 (not adjacent, no jump) ask gap(j).
template <class Gap>
void find_cuts(int n, const SegmentParams& sp, const int* cols, Gap gap, const Buffer<float>& steps2,
               Buffer<std::uint8_t>& cut) {
  cut.resize(std::max(0, n - 1));
  if (n < 2) return;
  const float min2 = static_cast<float>(sp.break_min_mm * sp.break_min_mm);
  const float ratio2 = static_cast<float>(sp.break_ratio * sp.break_ratio);
  const float inf = std::numeric_limits<float>::infinity();
  const float* st = steps2.data();
  std::uint8_t* c = cut.data();
  for (int j = 1; j + 2 < n; ++j) {
    const float d2 = st[j], neighbour = std::min(st[j - 1], st[j + 1]);
    c[j] = ((d2 > min2) & ((neighbour == inf) | (d2 > ratio2 * neighbour))) | ((cols[j + 1] - cols[j] != 1) << 1);
  }
  // The ends have one neighbouring step (or none).
  for (int j : {0, n - 2}) {
    const float d2 = st[j];
    const float before = j > 0 ? st[j - 1] : inf;
    const float after = j + 2 < n ? st[j + 1] : inf;
    const float neighbour = std::min(before, after);
    c[j] = ((d2 > min2) & ((neighbour == inf) | (d2 > ratio2 * neighbour))) | ((cols[j + 1] - cols[j] != 1) << 1);
  }
  const std::size_t len = static_cast<std::size_t>(n - 1);
  for (const std::uint8_t mark : {std::uint8_t{2}, std::uint8_t{3}}) {
    for (void* hit = std::memchr(c, mark, len); hit;) {
      const std::size_t j = static_cast<std::size_t>(static_cast<std::uint8_t*>(hit) - c);
      c[j] = mark == 3 || gap(static_cast<int>(j));
      hit = j + 1 < len ? std::memchr(c + j + 1, mark, len - j - 1) : nullptr;
    }
  }
}

// find_cuts for the gathered points, where invalid columns lie between
// points j and j+1 exactly when their columns are not adjacent. Written so
// that the inner loop vectorises.
void find_cuts_gathered(int n, const SegmentParams& sp, const int* cols, const Buffer<float>& steps2,
                        Buffer<std::uint8_t>& cut) {
  cut.resize(std::max(0, n - 1));
  if (n < 2) return;
  const float min2 = static_cast<float>(sp.break_min_mm * sp.break_min_mm);
  const float ratio2 = static_cast<float>(sp.break_ratio * sp.break_ratio);
  const float* st = steps2.data();
  std::uint8_t* c = cut.data();
  for (int j = 1; j + 2 < n; ++j) {
    const float d2 = st[j], nb = std::min(st[j - 1], st[j + 1]);
    c[j] = (cols[j + 1] - cols[j] != 1) | ((d2 > min2) & (d2 > ratio2 * nb));
  }
  // The ends have one neighbouring step (or none).
  for (int j : {0, n - 2}) {
    const float d2 = st[j];
    float nb = std::numeric_limits<float>::infinity();
    if (j > 0) nb = std::min(nb, st[j - 1]);
    if (j + 2 < n) nb = std::min(nb, st[j + 1]);
    c[j] = (cols[j + 1] - cols[j] != 1) | ((d2 > min2) & (std::isinf(nb) | (d2 > ratio2 * nb)));
  }
}

// Last point of the run starting at r0: the first j >= r0 with cut[j] set, or n - 1.
int run_end(const Buffer<std::uint8_t>& cut, int r0, int n) {
  if (r0 >= n - 1) return n - 1;
  const void* hit = std::memchr(cut.data() + r0, 1, static_cast<std::size_t>(n - 1 - r0));
  return hit ? static_cast<int>(static_cast<const std::uint8_t*>(hit) - cut.data()) : n - 1;
}

// A cluster of 1..max_cluster_points at one end of the run [r0, r1] (dir +1:
// its start, -1: its end) that made the jump cutting the run there itself:
// the support_points + 1 points on the other side of the cut and as many
// after the cluster inside the run lie on one line (within support_tol_mm),
// the cluster leaves that line (by more than support_tol_mm across a jump,
// threshold_mm across invalid columns), and its step back onto the line is at
// least half the jump. Returns the cluster's length, 0 if none.
int run_end_cluster(const float* ys, const float* zs, const int* cols, int n, int r0, int r1, int dir,
                    const OutlierParams& op, const Buffer<std::uint8_t>& keep) {
  auto raw = [&](int k) { return Vec2(ys[k], zs[k]); };
  const int max_cluster = std::max(1, op.max_cluster_points);
  const int support = std::clamp(op.support_points, 1, 8);
  // o: the point on the other side of the cut; it and the support points
  // beyond it must be kept when they lie in an earlier run (final by now);
  // points of a later run are taken as they are.
  const int o = dir > 0 ? r0 - 1 : r1 + 1;
  const int o_far = o - dir * support;
  if (o < 0 || o >= n || o_far < 0 || o_far >= n) return 0;
  if (dir > 0)
    for (int k = o_far; k <= o; ++k)
      if (!keep[k]) return 0;
  const int len = r1 - r0 + 1;
  // Across a jump (no invalid column at the cut) the cluster itself made the
  // step: off the line by more than its supports are is enough. Across
  // missing columns it must be off by the cluster threshold.
  const int c_cut = dir > 0 ? r0 : r1;
  const double limit = std::abs(cols[c_cut] - cols[o]) == 1 ? op.support_tol_mm : op.threshold_mm;
  for (int l = 1; l <= max_cluster && l + support + 1 <= len; ++l) {
    const int c0 = dir > 0 ? r0 : r1;          // cluster's point at the cut
    const int e = c0 + dir * l;                // first point after the cluster
    const Vec2 a = raw(o), b = raw(e);
    // The cluster leaving the line is tested first: most run ends are cut by
    // invalid columns on one line, and fail here.
    bool off = false;
    for (int k = c0; k != e && !off; k += dir) off = beyond_chord(a, b, raw(k), limit);
    if (!off) continue;
    bool supported = true;
    for (int k = 1; k <= support && supported; ++k)
      supported = !beyond_chord(a, b, raw(o - dir * k), op.support_tol_mm) &&
                  !beyond_chord(a, b, raw(e + dir * k), op.support_tol_mm);
    if (!supported) continue;
    // It leaves the line and comes back: the step back onto the line is at
    // least half the jump (a wall seen in a gap joins its plate with a short
    // step and leaves the other plate with a long one).
    if ((b - raw(e - dir)).squaredNorm() < 0.25 * (raw(c0) - a).squaredNorm()) continue;
    return l;
  }
  return 0;
}

// Marks outlier clusters in keep[] (1 keep, 0 outlier). See OutlierParams.
// spike[j] != 0 where point j leaves the line through points j-2 and j-1 by
// more than the threshold (or j < 2): only there can a cluster start.
// Returns whether anything was removed.
bool eliminate_outliers(const float* ys, const float* zs, const int* cols, int n, const Buffer<std::uint8_t>& cut,
                        const Buffer<std::uint8_t>& spike, const OutlierParams& op, double island_tol_mm,
                        Buffer<std::uint8_t>& keep) {
  auto raw = [&](int k) { return Vec2(ys[k], zs[k]); };
  keep.assign(n, 1);
  if (!op.enabled || n == 0) return false;
  bool any = false;
  const int max_cluster = std::max(1, op.max_cluster_points);
  const int support = std::clamp(op.support_points, 1, 8);
  for (int r0 = 0, r1; r0 < n; r0 = r1 + 1) {
    r1 = run_end(cut, r0, n);
    const int len = r1 - r0 + 1;
    if (len <= max_cluster && len < n) {
      // An island: a few points cut off from everything on both sides, unless
      // they are a piece of a steep surface broken by a dropout: at least two
      // points on one line that the next point beyond the cut on either side
      // continues.
      bool piece = false;
      if (len >= 2) {
        const Vec2 a = raw(r0), b = raw(r1);
        bool straight = true;
        const double straight_tol = std::max(op.support_tol_mm, island_tol_mm);
        for (int k = r0 + 1; k < r1 && straight; ++k) straight = !beyond_chord(a, b, raw(k), straight_tol);
        // The point beyond continues the line: near it, and past the island's
        // end along it (not beside the island: a short chord's line passes
        // near many points).
        const bool ahead_after = !op.islands_continue_ahead || (raw(r1 + 1 < n ? r1 + 1 : r1) - b).dot(b - a) > 0.0;
        const bool ahead_before = !op.islands_continue_ahead || (raw(r0 > 0 ? r0 - 1 : r0) - a).dot(a - b) > 0.0;
        piece = straight && ((r1 + 1 < n && ahead_after && !beyond_chord(a, b, raw(r1 + 1), op.threshold_mm)) ||
                             (r0 > 0 && ahead_before && !beyond_chord(a, b, raw(r0 - 1), op.threshold_mm)));
      }
      if (piece) continue;
      for (int k = r0; k <= r1; ++k) keep[k] = 0;
      any = true;
      continue;
    }
    // At either end of the run: a cluster that made the jump itself (see
    // run_end_cluster). Removing it leaves the rest of the run to the tests below.
    int head = r0;
    if (op.run_end_clusters) {
      const int l = run_end_cluster(ys, zs, cols, n, r0, r1, +1, op, keep);
      if (l > 0) {
        for (int k = r0; k < r0 + l; ++k) keep[k] = 0;
        head = r0 + l;
        any = true;
      }
    }
    // Inside a run: a cluster whose neighbours on both sides share one line.
    // Kept points are contiguous from `clean` on; before[m] is the m-th last
    // kept point before `clean` (n_before of them).
    int clean = head, before[9], n_before = 0;
    auto back = [&](int j, int m) {  // m-th last kept point before j, or -1
      if (j - 1 - m >= clean) return j - 1 - m;
      const int b = m - (j - clean);
      return b < n_before ? before[b] : -1;
    };
    int j = head;
    while (j <= r1) {
      // Skip the points that continue the line of the two before them.
      if (j >= clean + 2) {
        const void* hit = std::memchr(spike.data() + j, 1, static_cast<std::size_t>(r1 - j + 1));
        if (!hit) break;
        j = static_cast<int>(static_cast<const std::uint8_t*>(hit) - spike.data());
      }
      const int b0 = back(j, 0), b1 = back(j, 1), bs = back(j, support);
      bool removed = false;
      if (bs >= 0 && beyond_chord(raw(b1), raw(b0), raw(j), op.threshold_mm)) {
        const Vec2 a = raw(b0);
        for (int l = 1; l <= max_cluster && !removed; ++l) {
          const int e = j + l;  // first point after the cluster
          if (e + support > r1) break;
          const Vec2 b = raw(e);
          bool supported = true;
          for (int k = 1; k <= support && supported; ++k)
            supported = !beyond_chord(a, b, raw(back(j, k)), op.support_tol_mm) &&
                        !beyond_chord(a, b, raw(e + k), op.support_tol_mm);
          if (!supported) continue;
          bool off = false;
          for (int k = j; k < e && !off; ++k) off = beyond_chord(a, b, raw(k), op.threshold_mm);
          if (!off) continue;
          for (int k = j; k < e; ++k) keep[k] = 0;
          any = true;
          int tmp[9];
          for (int m = 0; m <= support; ++m) tmp[m] = back(j, m);
          std::copy(tmp, tmp + support + 1, before);
          n_before = support + 1;
          clean = j = e;
          removed = true;
        }
      }
      if (!removed) ++j;
    }
    if (op.run_end_clusters) {
      const int l = run_end_cluster(ys, zs, cols, n, r0, r1, -1, op, keep);
      if (l > 0) {
        for (int k = r1 - l + 1; k <= r1; ++k) keep[k] = 0;
        any = true;
      }
    }
  }
  return any;
}

}  // namespace

void Segmentation::clear() {
  // points and cols keep their size: segment_profile resizes them, and
  // shrinking them here would make it construct every element again.
  cuts.clear();
  outlier_points.clear();
  outlier_cols.clear();
  segments.clear();
  column_state.clear();
  valid_points = 0;
  outliers = 0;
  error.clear();
  sums_memo_next_ = 0;
}

namespace {

// The sums of the points of [first, last] that keep(point) accepts, relative
// to ref: (sy, sz) and (syy, szz) as 2-vectors, one instruction adding both,
// each rounded as alone.
template <class Keep>
PointSums sums_of(const Vec2* points, const Vec2& ref, int first, int last, Keep keep) {
  Vec2 s1 = Vec2::Zero(), s2 = Vec2::Zero();
  double syz = 0.0;
  int n = 0;
  for (int k = first; k <= last; ++k) {
    if (!keep(points[k])) continue;
    const Vec2 d = points[k] - ref;
    s1 += d;
    s2 += d.cwiseProduct(d);
    syz += d.x() * d.y();
    ++n;
  }
  PointSums t;
  t.n = n;
  t.sy = s1.x(), t.sz = s1.y(), t.syy = s2.x(), t.szz = s2.y(), t.syz = syz;
  return t;
}

}  // namespace

PointSums Segmentation::sums(int first, int last) const {
  const PointSums t = sums_of(points.data(), ref_, first, last, [](const Vec2&) { return true; });
  sums_memo_[sums_memo_next_++ % sums_memo_.size()] = {first, last, t};
  return t;
}

PointSums Segmentation::sums_near(const Line& line, double max_distance, int first, int last) const {
  const std::size_t memos = std::min(sums_memo_next_, sums_memo_.size());
  for (std::size_t k = 0; k < memos; ++k) {
    const SumsMemo& m = sums_memo_[k];
    if (m.first != first || m.last != last) continue;
    // Every point near the line (a loop without branches): sums()' answer.
    int far = 0;
    for (int i = first; i <= last; ++i) far += !(line.distance(points[i]) <= max_distance);
    if (far == 0) return m.sums;
    break;
  }
  return sums_of(points.data(), ref_, first, last, [&](const Vec2& p) { return line.distance(p) <= max_distance; });
}

Moments Segmentation::moments(const PointSums& t) const {
  Moments m;
  m.count = std::max(0, t.n);
  if (m.count == 0) return m;
  const double k = m.count;
  m.mean = ref_ + Vec2(t.sy / k, t.sz / k);
  m.syy = std::max(0.0, t.syy - t.sy * t.sy / k);
  m.szz = std::max(0.0, t.szz - t.sz * t.sz / k);
  m.syz = t.syz - t.sy * t.sz / k;
  return m;
}

std::optional<LineFit> Segmentation::fit(const PointSums& t) const {
  auto f = fit_line(moments(t));
  if (f) f->line.orient_towards(origin_);
  return f;
}

double Segmentation::column_tan(int col) const {
  const int np = static_cast<int>(points.size());
  if (np < 2 || col < roi_lo_ || col > roi_hi_) return kNaN;
  auto tan_of = [&](int k) {
    const Vec2 d = points[k] - origin_;
    return d.x() / d.y();
  };
  // k: the last kept point at or before col.
  int k = static_cast<int>(std::upper_bound(cols.begin(), cols.end(), col) - cols.begin()) - 1;
  if (k >= 0 && cols[k] == col) return tan_of(k);
  // Interpolate between kept points k and k + 1, or extrapolate from the end pair.
  k = std::clamp(k, 0, np - 2);
  const double ta = tan_of(k), tb = tan_of(k + 1);
  return ta + (tb - ta) * (col - cols[k]) / (cols[k + 1] - cols[k]);
}

int Segmentation::invalid_columns_between(int a, int b) const {
  if (b <= a + 1) return 0;
  return static_cast<int>(std::count(column_state.begin() + a + 1, column_state.begin() + b, kColumnInvalid));
}

namespace {

// Of the points k = from, from + step, ... before `to`, the first farthest
// from the line through (ay, az) along (cy, cz), and its distance times the
// chord's length |(cy, cz) x (p - a)|; -1 and 0 if all lie on the line. Two
// maxima, of every other point, are kept: a single one is a chain of
// dependent comparisons.
std::pair<int, double> farthest_from_chord(const Vec2* pts, int from, int to, int step, double ay, double az,
                                           double cy, double cz) {
  auto dist = [&](int k) { return std::abs(cy * (pts[k].y() - az) - cz * (pts[k].x() - ay)); };
  double w0 = 0.0, w1 = 0.0;
  int i0 = -1, i1 = -1;
  int k = from;
  for (; k + step < to; k += 2 * step) {
    const double d0 = dist(k), d1 = dist(k + step);
    if (d0 > w0) w0 = d0, i0 = k;
    if (d1 > w1) w1 = d1, i1 = k + step;
  }
  if (k < to)
    if (const double d0 = dist(k); d0 > w0) w0 = d0, i0 = k;
  // The first of them on a tie (-1 only when both are -1).
  if (w1 > w0 || (w1 == w0 && i1 < i0)) return {i1, w1};
  return {i0, w0};
}

// The squared residuals about the total least-squares line of a set of
// points: the smaller eigenvalue of their scatter matrix (fit_line's l_min).
double line_sse(const Segmentation& s, const PointSums& ps) {
  if (ps.n < 2) return 0.0;
  const Moments m = s.moments(ps);
  const double h = 0.5 * (m.syy - m.szz);
  return std::max(0.0, 0.5 * (m.syy + m.szz) - std::sqrt(h * h + m.syz * m.syz));
}

// The point k of [a, b] (at least min_side points on either side: [a, k - 1]
// and [k, b]; `total` the sums of all of them) where two lines, one through
// each side, leave the least squared residuals: a step's or a corner's
// place, found by least squares (running sums: the place only, the fits
// are summed afresh).
int best_two_line_split(const Segmentation& s, int a, int b, const PointSums& total, int min_side) {
  PointSums left;
  for (int k = a; k < a + min_side; ++k) left.add(s.points[k] - s.ref_);
  int best_k = -1;
  double best = std::numeric_limits<double>::infinity();
  for (int k = a + min_side; k <= b - min_side; ++k) {
    const double sse = line_sse(s, left) + line_sse(s, total - left);
    if (sse < best) best = sse, best_k = k;
    left.add(s.points[k] - s.ref_);
  }
  return best_k;
}

// Refits a segment from f, the fit of its sums (seg.sums must match
// [first, last]; f empty for fewer than two points).
void refit(const Segmentation& s, Segment& seg, const std::optional<LineFit>& f) {
  seg.first_col = s.cols[seg.first];
  seg.last_col = s.cols[seg.last];
  seg.fitted = f.has_value();
  if (f) {
    seg.line = f->line;
    seg.rms_mm = f->rms_mm;
    seg.centroid = f->centroid;
  } else {
    seg.rms_mm = 0.0;
    seg.centroid = s.points[seg.first];
  }
}
void refit(const Segmentation& s, Segment& seg) { refit(s, seg, seg.count() >= 2 ? s.fit(seg.sums) : std::nullopt); }

}  // namespace

void segment_profile(const ProfileView& profile, const SegmentationParams& params, Segmentation& s,
                     double detach_tol_mm, double rough_tol_mm, double island_tol_mm) {
  s.clear();
  const int n = static_cast<int>(profile.y_mm.size());
  if (profile.z_mm.size() != profile.y_mm.size() ||
      (!profile.valid.empty() && profile.valid.size() != profile.y_mm.size())) {
    s.points.clear();
    s.cols.clear();
    s.error = "profile spans differ in length (y " + std::to_string(profile.y_mm.size()) + ", z " +
              std::to_string(profile.z_mm.size()) + ", valid " + std::to_string(profile.valid.size()) + ")";
    return;
  }
  const Vec2 origin = params.ray_origin_yz;
  s.origin_ = origin;
  s.column_state.assign(n, kColumnInvalid);
  const int lo = std::max(0, params.roi_first);
  const int hi = params.roi_last < 0 ? n - 1 : std::min(n - 1, params.roi_last);

  // Gather the usable points (in the region, flagged valid, finite, in front
  // of the origin) without branches, then the squared steps between them and
  // where each leaves the line of the two before it, in float (only compared
  // with thresholds) so that the loops vectorise. Buffers keep their capacity.
  const int span = std::max(0, hi - lo + 1);
  s.points.resize(span);
  s.cols.resize(span + 1);
  s.ys_.resize(span + 1);
  s.zs_.resize(span + 1);
  s.steps_.resize(span + 1);
  s.spike_.resize(span + 1);
  float* ys = s.ys_.data();
  float* zs = s.zs_.data();
  int* cols = s.cols.data();
  const bool all_valid = profile.valid.empty();
  const float z_min = static_cast<float>(origin.y());
  constexpr float kMax = std::numeric_limits<float>::max();
  // Usable flags in one vectorisable pass, then the branch-free compaction.
  // Comparisons are false for NaN, so these also reject NaN and infinity.
  s.usable_.resize(span + 1);
  std::uint8_t* __restrict usable = s.usable_.data();
  if (span > 0) {  // else lo may lie past the end (roi_first >= n): no pointer arithmetic there
    const float* __restrict py = profile.y_mm.data() + lo;
    const float* __restrict pz = profile.z_mm.data() + lo;
    for (int k = 0; k < span; ++k) {
      const float yf = py[k], zf = pz[k];
      usable[k] = (zf > z_min) & (zf <= kMax) & (yf >= -kMax) & (yf <= kMax);
    }
    if (!all_valid) {
      const std::uint8_t* __restrict pv = profile.valid.data() + lo;
      for (int k = 0; k < span; ++k) usable[k] &= pv[k] != 0;
    }
  }
  if (span > 0)  // memcpy's pointers must not be null, even for 0 bytes
    std::memcpy(s.column_state.data() + lo, usable, static_cast<std::size_t>(span));  // kColumnKept == 1
  int nv = 0;
  {
    // Blocks of 8 usable columns (dropouts are rare) are copied whole, and
    // blocks of 8 unusable ones (outside the view) skipped.
    constexpr std::uint64_t kAllUsable = 0x0101010101010101ull;
    const float* py = profile.y_mm.data();
    const float* pz = profile.z_mm.data();
    // Columns [from, to) one by one, kept where usable.
    auto gather = [&](int from, int to) {
      for (int i = from; i < to; ++i) {
        ys[nv] = py[lo + i];
        zs[nv] = pz[lo + i];
        cols[nv] = lo + i;
        nv += usable[i];
      }
    };
    int k = 0;
    for (; k + 8 <= span; k += 8) {
      std::uint64_t block;
      std::memcpy(&block, usable + k, sizeof block);
      if (block == kAllUsable) {
        std::memcpy(ys + nv, py + lo + k, 8 * sizeof(float));
        std::memcpy(zs + nv, pz + lo + k, 8 * sizeof(float));
        for (int i = 0; i < 8; ++i) cols[nv + i] = lo + k + i;
        nv += 8;
        continue;
      }
      if (block != 0) gather(k, k + 8);
    }
    gather(k, span);
  }
  s.valid_points = nv;
  const int nvc = nv;  // a local copy: stores through uint8_t* could alias nv
  float* __restrict steps2 = s.steps_.data();
  std::uint8_t* __restrict spike = s.spike_.data();
  const float* __restrict yr = ys;
  const float* __restrict zr = zs;
  for (int j = 0; j + 1 < nvc; ++j) {
    const float dy = yr[j + 1] - yr[j], dz = zr[j + 1] - zr[j];
    steps2[j] = dy * dy + dz * dz;
  }
  const float t2 = static_cast<float>(params.outliers.threshold_mm * params.outliers.threshold_mm);
  for (int j = 0; j < std::min(nvc, 2); ++j) spike[j] = 1;
  for (int j = 2; j < nvc; ++j) {
    const float ey = yr[j - 1] - yr[j - 2], ez = zr[j - 1] - zr[j - 2];
    const float dy = yr[j] - yr[j - 1], dz = zr[j] - zr[j - 1];
    const float c = ey * dz - ez * dy, l2 = ey * ey + ez * ez;
    spike[j] = (c * c > t2 * l2) | (l2 < 1e-20f);
  }

  // Step 1: outliers; then the kept points are compacted in place, with prefix
  // sums for O(1) line fits (relative to the first point, for precision).
  find_cuts_gathered(nv, params.segments, cols, s.steps_, s.cuts);
  const bool removed = eliminate_outliers(ys, zs, cols, nv, s.cuts, s.spike_, params.outliers, island_tol_mm, s.keep_);
  Vec2* pts = s.points.data();
  s.ref_ = nv > 0 ? Vec2(ys[0], zs[0]) : Vec2::Zero();
  int np = 0;
  if (removed) {
    const std::uint8_t* keep = s.keep_.data();
    for (int k = 0; k < nv;) {
      if (!keep[k]) {
        s.column_state[cols[k]] = kColumnOutlier;
        s.outlier_points.emplace_back(ys[k], zs[k]);
        s.outlier_cols.push_back(cols[k]);
        ++s.outliers;
        ++k;
        continue;
      }
      // A run of kept points, copied without tests.
      const void* hit = std::memchr(keep + k, 0, static_cast<std::size_t>(nv - k));
      const int end = hit ? static_cast<int>(static_cast<const std::uint8_t*>(hit) - keep) : nv;
      for (; k < end; ++k, ++np) {
        pts[np].x() = ys[k];
        pts[np].y() = zs[k];
        cols[np] = cols[k];
      }
    }
  } else {
    for (int k = 0; k < nv; ++k) {
      pts[k].x() = ys[k];
      pts[k].y() = zs[k];
    }
    np = nv;
  }
  s.points.resize(np);
  s.cols.resize(np);
  s.roi_lo_ = lo;
  s.roi_hi_ = hi;

  if (np == 0) return;

  // Step 2: cut at discontinuities, then split each run recursively.
  const SegmentParams& sp = params.segments;
  // Without outliers the kept points are the gathered ones: their cuts stand.
  if (s.outliers > 0) {
    for (int j = 0; j + 1 < np; ++j) {
      const double dy = pts[j + 1].x() - pts[j].x(), dz = pts[j + 1].y() - pts[j].y();
      s.steps_[j] = static_cast<float>(dy * dy + dz * dz);
    }
    auto gap = [&](int j) { return s.invalid_columns_between(s.cols[j], s.cols[j + 1]) > 0; };
    find_cuts(np, sp, s.cols.data(), gap, s.steps_, s.cuts);
  }
  const int s_min = std::max(2, sp.min_segment_points);
  const int s_int = std::max(1, sp.split_interval);
  for (int r0 = 0, r1; r0 < np; r0 = r1 + 1) {
    r1 = run_end(s.cuts, r0, np);
    s.leaves_.clear();
    s.stack_.clear();
    s.stack_.push_back(SplitRegion{r0, r1, false, {}});
    while (!s.stack_.empty()) {
      SplitRegion region = s.stack_.back();
      s.stack_.pop_back();
      const int a = region.a, b = region.b;
      SplitRegion left, right;
      int split_at = -1;
      if (b - a + 1 >= s_min) {
        const Vec2* pts = s.points.data();
        const double ay = pts[a].x(), az = pts[a].y();
        const double cy = pts[b].x() - ay, cz = pts[b].y() - az;
        const double len = std::sqrt(cy * cy + cz * cz);
        double worst = 0.0;
        if (len > 1e-12) {
          std::tie(split_at, worst) = farthest_from_chord(pts, a + s_int, b, s_int, ay, az, cy, cz);
          worst /= len;
        } else {
          for (int k = a + s_int; k < b; k += s_int) {
            const double dist = (pts[k] - pts[a]).norm();
            if (dist > worst) {
              worst = dist;
              split_at = k;
            }
          }
        }
        if (!(worst > sp.split_threshold_mm)) {
          // A corner shallower than t_split in a short run (a dropout cut the
          // profile next to it) is split too when the region is no line: its
          // fit's rms exceeds what noise gives (rough_tol_mm, see
          // segment_profile). At its farthest point from the chord over every
          // point, with at least 3 points on either side (a corner between
          // two lines; one or two deep points, as rays into a narrow gap, are
          // left to the later steps), when each side fits a line at least
          // twice as well as the whole.
          int rough_at = -1;
          // The sums are kept for the leaf or the two parts (each part's
          // rough test, and its segment, would sum it again).
          if (rough_tol_mm > 0.0 && len > 1e-12 && worst > rough_tol_mm) {
            if (!region.summed) region.head = s.sums(a, b - 1), region.summed = true;
            const PointSums whole = s.with_point(region.head, b);
            const auto f = s.fit(whole);
            if (f && f->rms_mm > rough_tol_mm) {
              double far = 0.0;
              std::tie(rough_at, far) = farthest_from_chord(pts, a + 1, b, 1, ay, az, cy, cz);
              if (rough_at - a < 3 || b - rough_at < 3 || !(far / len > rough_tol_mm)) rough_at = -1;
              // Two lines meet there: each side alone fits a line at least
              // twice as well (a displaced cluster on one line does not).
              auto two_lines_at = [&](int at, double* angle_cos) {
                left = SplitRegion{a, at, true, s.sums(a, at - 1)};
                right = SplitRegion{at, b, true, s.sums(at, b - 1)};
                const auto l = s.fit(s.with_point(left.head, at)), r = s.fit(s.with_point(right.head, b));
                const double half = 0.5 * f->rms_mm;
                bool two = l && r && l->rms_mm <= half && r->rms_mm <= half;
                // The point there is on one line only where the lines are
                // parallel, a step between them (a butt's mismatch below
                // t_split): each side is tested with it on the side it fits.
                if (!two && sp.rough_step_either_side && l && r) {
                  if (at + 1 < b) {
                    const auto r1 = s.fit(s.with_point(s.sums(at + 1, b - 1), b));
                    two = l->rms_mm <= half && r1 && r1->rms_mm <= half;
                  }
                  if (!two && at - 1 > a) {
                    const auto l1 = s.fit(left.head);
                    two = r->rms_mm <= half && l1 && l1->rms_mm <= half;
                  }
                }
                if (angle_cos && l && r) *angle_cos = std::abs(l->line.n.dot(r->line.n));
                return two;
              };
              if (rough_at >= 0 && !two_lines_at(rough_at, nullptr)) {
                // Not there: a step between parallel lines may be elsewhere,
                // waviness putting the farthest point from the chord a
                // millimetre from it. Where two lines fit the region best
                // (least squares over every place), if they are parallel.
                const int at = sp.rough_split_best_fit ? best_two_line_split(s, a, b, whole, 3) : -1;
                double angle_cos = 0.0;
                rough_at = at >= 0 && at != rough_at && two_lines_at(at, &angle_cos) &&
                                   angle_cos >= std::cos(sp.rough_step_max_angle_deg * 3.14159265358979323846 / 180.0)
                               ? at
                               : -1;
              }
            }
          }
          split_at = rough_at;
        }
      }
      if (split_at < 0) {
        s.leaves_.push_back(region);
      } else if (left.summed) {
        s.stack_.push_back(right);
        s.stack_.push_back(left);
      } else {
        s.stack_.push_back(SplitRegion{split_at, b, false, {}});
        s.stack_.push_back(SplitRegion{a, split_at, false, {}});
      }
    }
    // Leaves share their split points; each shared point starts the next segment.
    for (std::size_t k = 0; k < s.leaves_.size(); ++k) {
      const SplitRegion& leaf = s.leaves_[k];
      Segment seg;
      seg.first = leaf.a;
      seg.last = k + 1 < s.leaves_.size() ? s.leaves_[k + 1].a - 1 : r1;
      if (seg.last < seg.first) continue;
      if (leaf.summed && seg.last == leaf.b - 1) seg.sums = leaf.head;
      else if (leaf.summed && seg.last == leaf.b) seg.sums = s.with_point(leaf.head, leaf.b);
      else seg.sums = s.sums(seg.first, seg.last);
      refit(s, seg);
      s.segments.push_back(seg);
    }
  }

  // Step 3: merge neighbours that are close in columns and in angle and still
  // one line together: at the four end points (each part is straight), or, on
  // noisy profiles, with a joint rms no worse than the parts' (1.5 x) and
  // below half the split threshold. The offset test allows 3 rms of noise.
  const double cos_merge = std::cos(sp.max_merge_angle_deg * 3.14159265358979323846 / 180.0);
  // Whether a and c are one line, together with the `between_points` points
  // between them (sums `between`: a short piece, every point of which must
  // lie within t_split of the joint line): their joint fit if so (the merged
  // segment's: its sums add up in the same order), else empty.
  auto mergeable = [&](const Segment& a, const Segment& c, const PointSums& between,
                       int between_points) -> std::optional<LineFit> {
    const double offset = std::max(sp.max_merge_offset_mm, 3.0 * std::max(a.rms_mm, c.rms_mm));
    if (!a.fitted || !c.fitted || c.first_col - a.last_col - 1 - between_points >= sp.max_merge_gap_points ||
        std::abs(a.line.n.dot(c.line.n)) <= cos_merge || a.line.distance(s.points[c.first]) >= offset ||
        c.line.distance(s.points[a.last]) >= offset)
      return std::nullopt;
    PointSums all = a.sums;
    all += between;
    all += c.sums;
    const auto f = s.fit(all);
    if (!f) return std::nullopt;
    for (int k = a.last + 1; k < c.first; ++k)
      if (f->line.distance(s.points[k]) > sp.split_threshold_mm) return std::nullopt;
    bool ends = true;
    for (int k : {a.first, a.last, c.first, c.last}) ends = ends && f->line.distance(s.points[k]) <= sp.split_threshold_mm;
    if (ends || (f->rms_mm <= 1.5 * std::max(a.rms_mm, c.rms_mm) && f->rms_mm <= 0.5 * sp.split_threshold_mm))
      return f;
    return std::nullopt;
  };
  // In place: segments [0, w] are final but w itself, which the ones from r
  // on may still join.
  std::vector<Segment>& segs = s.segments;
  std::size_t w = 0;
  for (std::size_t r = 1; r < segs.size();) {
    Segment& a = segs[w];
    const Segment& b = segs[r];
    if (const auto f = mergeable(a, b, PointSums{}, 0)) {
      a.last = b.last;
      a.sums += b.sums;
      refit(s, a, f);
      ++r;
      continue;
    }
    // A piece shorter than s_min between two parts of one line (noise near
    // the split threshold cuts a plate like this) joins them.
    const auto f = b.count() < s_min && r + 1 < segs.size() ? mergeable(a, segs[r + 1], b.sums, b.count())
                                                             : std::nullopt;
    if (f) {
      const Segment& c = segs[r + 1];
      a.last = c.last;
      a.sums += b.sums;
      a.sums += c.sums;
      refit(s, a, f);
      r += 2;
      continue;
    }
    if (++w != r) segs[w] = segs[r];
    ++r;
  }
  if (!segs.empty()) segs.resize(w + 1);

  // Boundary points go to the neighbouring line they fit better (split points
  // are shared and every other point is skipped with s_int = 2, so the point
  // at a corner may sit on the wrong side).
  for (std::size_t i = 0; i + 1 < s.segments.size();) {
    Segment& a = s.segments[i];
    Segment& b = s.segments[i + 1];
    // Not across missing columns: there the two sides are separate anyway.
    const bool joined = s.invalid_columns_between(a.last_col, b.first_col) == 0;
    for (int iter = 0; joined && iter < 3 && a.count() > 0 && b.count() > 0; ++iter) {
      bool moved = false;
      if (a.fitted) {
        const Vec2& p = s.points[b.first];
        const double da = a.line.distance(p);
        const double db = b.count() >= 3 && b.fitted ? b.line.distance(p) : kInf;
        if (da <= std::max(sp.fit_tol_mm, 3.0 * a.rms_mm) && 2.0 * da + 1e-9 < db) {
          a.sums.add(p - s.ref_);
          b.sums.add(p - s.ref_, -1.0);
          ++a.last;
          ++b.first;
          moved = true;
        }
      }
      if (!moved && b.fitted) {
        const Vec2& p = s.points[a.last];
        const double db = b.line.distance(p);
        const double da = a.count() >= 3 && a.fitted ? a.line.distance(p) : kInf;
        if (db <= std::max(sp.fit_tol_mm, 3.0 * b.rms_mm) && 2.0 * db + 1e-9 < da) {
          b.sums.add(p - s.ref_);
          a.sums.add(p - s.ref_, -1.0);
          --a.last;
          --b.first;
          moved = true;
        }
      }
      if (!moved) break;
      if (a.count() > 0) refit(s, a);
      if (b.count() > 0) refit(s, b);
    }
    // A segment emptied by the moves disappears; look at the new pair again.
    if (b.count() <= 0) {
      s.segments.erase(s.segments.begin() + static_cast<std::ptrdiff_t>(i) + 1);
    } else if (a.count() <= 0) {
      s.segments.erase(s.segments.begin() + static_cast<std::ptrdiff_t>(i));
      if (i > 0) --i;
    } else {
      ++i;
    }
  }

  // End points that sit off their segment's line (a corner sample, a few
  // points of a short face) are detached as single points: the segment is
  // fitted without its last three points on that end, and from the inside out
  // the first of them farther than max(fit_tol_mm, 4 rms, detach_tol_mm)
  // from that line is detached with everything beyond it. (A bevel seen
  // nearly along the rays has range noise along its line: its rms is far
  // below the noise, and fit_tol_mm or 4 rms alone detached its last points
  // at the root; detach_tol_mm is the noise a point may show off its line.)
  for (std::size_t i = 0; i < s.segments.size(); ++i) {
    for (int end = 0; end < 2; ++end) {
      Segment& sg = s.segments[i];
      const int m = std::min(3, sg.count() - s_min);
      if (m <= 0) continue;
      PointSums core_sums = sg.sums;
      for (int k = 0; k < m; ++k) core_sums.add(s.points[end == 0 ? sg.first + k : sg.last - k] - s.ref_, -1.0);
      const auto core = s.fit(core_sums);
      if (!core) continue;
      const double tol = std::max({sp.fit_tol_mm, 4.0 * core->rms_mm, detach_tol_mm});
      int detach = 0;
      for (int k = m; k >= 1; --k) {
        const int p = end == 0 ? sg.first + k - 1 : sg.last - k + 1;
        if (core->line.distance(s.points[p]) > tol) {
          detach = k;
          break;
        }
      }
      if (detach == 0) continue;
      const int first = end == 0 ? sg.first : sg.last - detach + 1;
      for (int k = first; k < first + detach; ++k) sg.sums.add(s.points[k] - s.ref_, -1.0);
      if (end == 0) sg.first += detach;
      else sg.last -= detach;
      refit(s, sg);
      const std::ptrdiff_t at = static_cast<std::ptrdiff_t>(i) + (end == 0 ? 0 : 1);
      for (int k = detach - 1; k >= 0; --k) {
        Segment lone;
        lone.first = lone.last = first + k;
        lone.sums = s.sums(lone.first, lone.last);
        refit(s, lone);
        s.segments.insert(s.segments.begin() + at, lone);
      }
      if (end == 0) i += detach;
    }
  }
}

}  // namespace vts::tracker
