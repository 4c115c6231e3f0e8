#include "stripe/peaks.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace vts::stripe {

namespace {

constexpr std::string_view kSubPixelNames[] = {"cog", "gaussian", "parabolic"};
constexpr std::string_view kPolicyNames[] = {"strongest", "first", "last", "widest", "continuous"};
constexpr int kMaxWindowPx = 32;
// Columns transposed together: the strip of a 1024-row frame (32 KiB) stays
// in L1 while it is written (measured: 16 is 2.5x faster than 32, as fast as 8).
constexpr int kStripColumns = 16;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::string number(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

[[noreturn]] void bad(const char* field, double value, const std::string& why) {
  throw std::invalid_argument(std::string(field) + " = " + number(value) + ": " + why);
}

// What one frame's columns share.
struct Setup {
  double threshold_dn;  // the absolute part of the threshold
  double threshold_rel;
  double saturation_dn;
  int window_px;
  SubPixel method;
  int min_width_px;
  double min_separation_px;
  int row_first;
};

// Centre of gravity of (min(value, saturation) - threshold), the positive
// part, over rows [lo, hi] of the column; NaN when nothing is above.
double centre_of_gravity(const std::uint16_t* v, int lo, int hi, double t, double sat) {
  double s = 0.0, sr = 0.0;
  for (int i = lo; i <= hi; ++i) {
    const double x = std::min<double>(v[i], sat) - t;
    if (x > 0.0) {
      s += x;
      sr += x * i;
    }
  }
  return s > 0.0 ? sr / s : kNaN;
}

// Vertex of the parabola a + b x + c x^2 least-squares fitted (weights w) to
// y at x = i - m over rows [lo, hi]; `log_values`: y = ln(value), w = value^2
// (the Gaussian fit: ln of a Gaussian is a parabola, and the weights undo
// the log's stretching of the noise on dim pixels); otherwise y = value,
// w = 1. Returns m + the vertex, or NaN when the fit has no maximum within
// the window (fewer than 3 usable rows, c >= 0, vertex beyond the window).
double parabola_vertex(const std::uint16_t* v, int m, int lo, int hi, bool log_values) {
  double s0 = 0, s1 = 0, s2 = 0, s3 = 0, s4 = 0, t0 = 0, t1 = 0, t2 = 0;
  int used = 0;
  const double peak = v[m];
  for (int i = lo; i <= hi; ++i) {
    if (log_values && v[i] == 0) continue;
    const double x = i - m;
    const double y = log_values ? std::log(static_cast<double>(v[i])) : v[i] / peak;
    const double w = log_values ? (v[i] / peak) * (v[i] / peak) : 1.0;
    const double x2 = x * x;
    s0 += w, s1 += w * x, s2 += w * x2, s3 += w * x2 * x, s4 += w * x2 * x2;
    t0 += w * y, t1 += w * x * y, t2 += w * x2 * y;
    ++used;
  }
  if (used < 3) return kNaN;
  // Normal equations [s0 s1 s2; s1 s2 s3; s2 s3 s4] [a b c] = [t0 t1 t2], Cramer's rule for b and c.
  const double det = s0 * (s2 * s4 - s3 * s3) - s1 * (s1 * s4 - s3 * s2) + s2 * (s1 * s3 - s2 * s2);
  if (!(std::abs(det) > 1e-12)) return kNaN;
  const double det_b = s0 * (t1 * s4 - s3 * t2) - t0 * (s1 * s4 - s3 * s2) + s2 * (s1 * t2 - t1 * s2);
  const double det_c = s0 * (s2 * t2 - t1 * s3) - s1 * (s1 * t2 - t1 * s2) + t0 * (s1 * s3 - s2 * s2);
  const double b = det_b / det, c = det_c / det;
  if (!(c < 0.0)) return kNaN;
  const double row = m - b / (2.0 * c);
  if (!(row >= lo - 0.5 && row <= hi + 0.5)) return kNaN;
  return row;
}

// Full width at half maximum around row m: from m outwards to the first row
// at or below half on each side, crossing interpolated linearly; the ends of
// the rows searched count as crossings at their outer edges. The maximum is
// the vertex of the parabola through rows m - 1, m, m + 1 (a peak between
// two rows is brighter than either), or `top` when given (saturated).
double width_at_half(const std::uint16_t* v, int n, int m, double top) {
  if (top <= 0.0) {
    top = v[m];
    if (m > 0 && m < n - 1) {
      const double a = v[m - 1], b = v[m], c = v[m + 1], curv = a - 2.0 * b + c;
      if (curv < 0.0) top = b - (a - c) * (a - c) / (8.0 * curv);
    }
  }
  const double half = 0.5 * top;
  int j = m;
  while (j > 0 && v[j - 1] > half) --j;
  const double left = j == 0 ? -0.5 : (j - 1) + (half - v[j - 1]) / (double(v[j]) - v[j - 1]);
  int k = m;
  while (k < n - 1 && v[k + 1] > half) ++k;
  const double right = k == n - 1 ? n - 0.5 : k + (v[k] - half) / (double(v[k]) - v[k + 1]);
  return right - left;
}

// The peaks of one column: v holds its n rows searched (the first is image
// row s.row_first). Appends to `peaks`; returns the threshold applied.
float column_peaks(const std::uint16_t* v, int n, const Setup& s, std::vector<Peak>& peaks) {
  std::uint16_t column_max = 0;
  for (int i = 0; i < n; ++i) column_max = std::max(column_max, v[i]);
  const double t = std::max(s.threshold_dn, s.threshold_rel * column_max);
  // Values are integers: v > t exactly when v > floor(t).
  const int lit_above = static_cast<int>(std::floor(t));
  if (column_max <= lit_above) return static_cast<float>(t);

  // Runs of lit rows; a run whose maximum is closer than min_separation_px
  // to the previous peak's maximum joins it. While runs are gathered,
  // Peak::row holds the maximum's index (rows from row_first).
  const std::size_t begin = peaks.size();
  for (int i = 0; i < n;) {
    if (v[i] <= lit_above) {
      ++i;
      continue;
    }
    const int first = i;
    int m = i;
    std::int64_t sum = 0;
    for (; i < n && v[i] > lit_above; ++i) {
      if (v[i] > v[m]) m = i;
      sum += v[i];
    }
    const double strength = sum - t * (i - first);
    if (peaks.size() > begin && m - peaks.back().row < s.min_separation_px) {
      Peak& p = peaks.back();
      p.last_row = i - 1;
      p.strength += static_cast<float>(strength);
      if (v[m] > p.peak_dn) p.peak_dn = v[m], p.row = static_cast<float>(m);
      continue;
    }
    Peak p;
    p.row = static_cast<float>(m);
    p.peak_dn = v[m];
    p.strength = static_cast<float>(strength);
    p.first_row = first;
    p.last_row = i - 1;
    peaks.push_back(p);
  }

  // Position, width and saturation of each run long enough; the rest
  // dropped. A run's rows end at the darkest row between it and each
  // neighbouring run (the valley, excluded), so that a close second peak
  // does not pull the fit.
  std::size_t kept = begin;
  const int w = s.window_px;
  int lo_bound = 0;
  for (std::size_t k = begin; k < peaks.size(); ++k) {
    Peak p = peaks[k];
    int hi_bound = n - 1, next_lo = n;
    if (k + 1 < peaks.size()) {
      int valley = p.last_row + 1;
      for (int i = valley + 1; i < peaks[k + 1].first_row; ++i)
        if (v[i] < v[valley]) valley = i;
      hi_bound = valley - 1;
      next_lo = valley + 1;
    }
    const int lo = lo_bound, hi = hi_bound;
    lo_bound = next_lo;
    if (p.last_row - p.first_row + 1 < s.min_width_px) continue;
    const int m = static_cast<int>(p.row);
    double row = kNaN;
    p.saturated = v[m] >= s.saturation_dn;
    if (p.saturated) {
      // Plateau rule: the saturated rows around m and both flanks, each
      // down to the threshold or to a rise (another peak's edge): centre of
      // gravity of (value clipped at saturation - threshold).
      int a = m, b = m;
      while (a > lo && v[a - 1] >= s.saturation_dn) --a;
      while (b < hi && v[b + 1] >= s.saturation_dn) ++b;
      while (a > lo && v[a - 1] > t && v[a - 1] <= v[a]) --a;
      while (b < hi && v[b + 1] > t && v[b + 1] <= v[b]) ++b;
      row = centre_of_gravity(v, a, b, t, s.saturation_dn);
    } else {
      const int a = std::max(lo, m - w), b = std::min(hi, m + w);
      if (s.method != SubPixel::centre_of_gravity)
        row = parabola_vertex(v, m, a, b, s.method == SubPixel::gaussian);
      if (std::isnan(row)) row = centre_of_gravity(v, a, b, t, s.saturation_dn);
    }
    if (std::isnan(row)) row = m;
    p.row = static_cast<float>(row + s.row_first);
    p.width_px = static_cast<float>(width_at_half(v, n, m, p.saturated ? s.saturation_dn : 0.0));
    p.first_row += s.row_first;
    p.last_row += s.row_first;
    peaks[kept++] = p;
  }
  peaks.resize(kept);
  return static_cast<float>(t);
}

// Index of the best peak of [b, e) by `better(a, b)` (a strictly better than b); -1 when empty.
template <class Better>
int pick(const std::vector<Peak>& peaks, int b, int e, Better better) {
  int best = b < e ? b : -1;
  for (int i = b + 1; i < e; ++i)
    if (better(peaks[i], peaks[best])) best = i;
  return best;
}

// The `continuous` policy (docs/PEAKS.md): Viterbi over the columns, the
// states of column c being its peaks and "none".
void choose_continuous(const PeakParams& params, double full_scale, PeakResult& out) {
  const int width = out.width();
  const std::size_t n = out.peaks.size();
  out.score_.resize(n);
  out.back_.resize(n);
  out.none_score_.resize(width);
  out.none_back_.resize(width);
  out.none_row_.resize(width);
  const double jump = params.jump_cost, free_px = params.max_jump_px;
  const double bright = params.brightness_weight / full_scale;
  const float no_row = std::numeric_limits<float>::quiet_NaN();
  // The cost of moving from a peak at row `from` (NaN: no peak before) to `to`.
  auto jump_cost = [&](float from, float to) {
    return std::isnan(from) ? 0.0 : jump * std::max(0.0, std::abs(double(to) - from) - free_px);
  };
  for (int c = 0; c < width; ++c) {
    const int b = out.column_offset[c], e = out.column_offset[c + 1];
    const double miss = e > b ? params.miss_cost : 0.0;
    if (c == 0) {
      for (int p = b; p < e; ++p) out.score_[p] = 1.0 + bright * out.peaks[p].peak_dn, out.back_[p] = -1;
      out.none_score_[0] = -miss;
      out.none_back_[0] = -1;
      out.none_row_[0] = no_row;
      continue;
    }
    const int pb = out.column_offset[c - 1], pe = b;
    // "none" here: the best state of column c - 1 ("none" first on ties),
    // remembering the row its path last chose.
    double any = out.none_score_[c - 1];
    int any_back = -1;
    float any_row = out.none_row_[c - 1];
    for (int q = pb; q < pe; ++q)
      if (out.score_[q] > any) any = out.score_[q], any_back = q, any_row = out.peaks[q].row;
    out.none_score_[c] = any - miss;
    out.none_back_[c] = any_back;
    out.none_row_[c] = any_row;
    for (int p = b; p < e; ++p) {
      const float row = out.peaks[p].row;
      double best = out.none_score_[c - 1] - jump_cost(out.none_row_[c - 1], row);
      int back = -1;
      for (int q = pb; q < pe; ++q) {
        const double v = out.score_[q] - jump_cost(out.peaks[q].row, row);
        if (v > best) best = v, back = q;
      }
      out.score_[p] = best + 1.0 + bright * out.peaks[p].peak_dn;
      out.back_[p] = back;
    }
  }
  // The best final state, then back along the chain.
  const int b = out.column_offset[width - 1], e = out.column_offset[width];
  double best = out.none_score_[width - 1];
  int state = -1;
  for (int p = b; p < e; ++p)
    if (out.score_[p] > best) best = out.score_[p], state = p;
  for (int c = width - 1; c >= 0; --c) {
    out.chosen[c] = state;
    state = state >= 0 ? out.back_[state] : out.none_back_[c];
  }
}

}  // namespace

std::string_view to_string(SubPixel m) { return kSubPixelNames[static_cast<int>(m)]; }
std::string_view to_string(PeakPolicy p) { return kPolicyNames[static_cast<int>(p)]; }

std::optional<SubPixel> parse_sub_pixel(std::string_view name) {
  for (int i = 0; i < 3; ++i)
    if (kSubPixelNames[i] == name) return static_cast<SubPixel>(i);
  return std::nullopt;
}

std::optional<PeakPolicy> parse_peak_policy(std::string_view name) {
  for (int i = 0; i < 5; ++i)
    if (kPolicyNames[i] == name) return static_cast<PeakPolicy>(i);
  return std::nullopt;
}

std::string sub_pixel_names() { return "cog, gaussian, parabolic"; }
std::string peak_policy_names() { return "strongest, first, last, widest, continuous"; }

void validate(const PeakParams& p, int bits, int height) {
  if (bits != 8 && bits != 10 && bits != 12 && bits != 16) bad("bits", bits, "must be 8, 10, 12 or 16");
  const double fs = full_scale_dn(bits);
  const std::string depth = (bits == 8 ? " of an " : " of a ") + std::to_string(bits) + "-bit image";
  if (!(p.threshold_dn >= 0.0 && p.threshold_dn < fs))
    bad("threshold_dn", p.threshold_dn, "must be >= 0 (0: full scale / 16) and below the full scale " + number(fs) + depth);
  if (!(p.threshold_rel >= 0.0 && p.threshold_rel < 1.0))
    bad("threshold_rel", p.threshold_rel, "must be in [0, 1): a fraction of the column's maximum");
  if (p.window_px < 1 || p.window_px > kMaxWindowPx)
    bad("window_px", p.window_px, "must be 1.." + std::to_string(kMaxWindowPx) + " rows");
  if (static_cast<unsigned>(p.method) > 2u) bad("method", static_cast<int>(p.method), "unknown sub-pixel method");
  if (static_cast<unsigned>(p.policy) > 4u) bad("policy", static_cast<int>(p.policy), "unknown peak policy");
  if (p.min_width_px < 1 || p.min_width_px > height)
    bad("min_width_px", p.min_width_px, "must be 1.." + std::to_string(height) + " (the image's rows)");
  const double threshold = p.threshold_dn > 0.0 ? p.threshold_dn : fs / 16.0;
  if (p.saturation_dn != 0.0 && !(p.saturation_dn > threshold && p.saturation_dn <= fs))
    bad("saturation_dn", p.saturation_dn,
        "must be 0 (full scale) or above the threshold " + number(threshold) + " and at most the full scale " +
            number(fs) + depth);
  if (!(p.min_separation_px >= 0.0 && std::isfinite(p.min_separation_px)))
    bad("min_separation_px", p.min_separation_px, "must be >= 0 rows");
  if (p.row_first < 0 || p.row_first >= height)
    bad("row_first", p.row_first, "must be 0.." + std::to_string(height - 1) + " (the image's rows)");
  if (p.row_last != -1 && (p.row_last < p.row_first || p.row_last >= height))
    bad("row_last", p.row_last,
        "must be -1 (the last row) or " + std::to_string(p.row_first) + ".." + std::to_string(height - 1));
  if (!(p.max_jump_px >= 0.0 && std::isfinite(p.max_jump_px))) bad("max_jump_px", p.max_jump_px, "must be >= 0 rows");
  if (!(p.jump_cost >= 0.0 && std::isfinite(p.jump_cost))) bad("jump_cost", p.jump_cost, "must be >= 0");
  if (!(p.miss_cost >= 0.0 && std::isfinite(p.miss_cost))) bad("miss_cost", p.miss_cost, "must be >= 0");
  if (!(p.brightness_weight >= 0.0 && std::isfinite(p.brightness_weight)))
    bad("brightness_weight", p.brightness_weight, "must be >= 0");
}

void detect_peaks(const ImageView& image, const PeakParams& params, PeakResult& out) {
  if (image.data == nullptr) throw std::invalid_argument("ImageView.data is null");
  if (image.width < 1) bad("ImageView.width", image.width, "must be >= 1");
  if (image.height < 1) bad("ImageView.height", image.height, "must be >= 1");
  if (image.stride < image.width)
    bad("ImageView.stride", static_cast<double>(image.stride), "must be >= the width " + std::to_string(image.width));
  validate(params, image.bits, image.height);

  const double fs = full_scale_dn(image.bits);
  Setup s;
  s.threshold_dn = params.threshold_dn > 0.0 ? params.threshold_dn : fs / 16.0;
  s.threshold_rel = params.threshold_rel;
  s.saturation_dn = params.saturation_dn > 0.0 ? params.saturation_dn : fs;
  s.window_px = params.window_px;
  s.method = params.method;
  s.min_width_px = params.min_width_px;
  s.min_separation_px = params.min_separation_px;
  s.row_first = params.row_first;
  const int row_last = params.row_last < 0 ? image.height - 1 : params.row_last;
  const int n = row_last - s.row_first + 1;

  const int width = image.width;
  out.peaks.clear();
  out.column_offset.assign(width + 1, 0);
  out.chosen.assign(width, -1);
  out.threshold_dn.assign(width, 0.0f);
  out.strip_.resize(static_cast<std::size_t>(kStripColumns) * n);

  // A strip of columns at a time, transposed so that each column's rows are
  // contiguous: the image is read row by row, a cache line at a time.
  for (int c0 = 0; c0 < width; c0 += kStripColumns) {
    const int cols = std::min(kStripColumns, width - c0);
    for (int r = 0; r < n; ++r) {
      const std::uint16_t* src = image.data + (s.row_first + r) * image.stride + c0;
      std::uint16_t* dst = out.strip_.data() + r;
      for (int j = 0; j < cols; ++j) dst[static_cast<std::ptrdiff_t>(j) * n] = src[j];
    }
    for (int j = 0; j < cols; ++j) {
      const int c = c0 + j;
      out.threshold_dn[c] = column_peaks(out.strip_.data() + static_cast<std::ptrdiff_t>(j) * n, n, s, out.peaks);
      out.column_offset[c + 1] = static_cast<int>(out.peaks.size());
    }
  }

  const auto stronger = [](const Peak& a, const Peak& b) {
    return a.peak_dn > b.peak_dn || (a.peak_dn == b.peak_dn && a.strength > b.strength);
  };
  switch (params.policy) {
    case PeakPolicy::continuous:
      choose_continuous(params, fs, out);
      return;
    case PeakPolicy::strongest:
      for (int c = 0; c < width; ++c) out.chosen[c] = pick(out.peaks, out.column_offset[c], out.column_offset[c + 1], stronger);
      return;
    case PeakPolicy::first:
      for (int c = 0; c < width; ++c)
        out.chosen[c] = out.column_offset[c] < out.column_offset[c + 1] ? out.column_offset[c] : -1;
      return;
    case PeakPolicy::last:
      for (int c = 0; c < width; ++c)
        out.chosen[c] = out.column_offset[c] < out.column_offset[c + 1] ? out.column_offset[c + 1] - 1 : -1;
      return;
    case PeakPolicy::widest:
      for (int c = 0; c < width; ++c)
        out.chosen[c] = pick(out.peaks, out.column_offset[c], out.column_offset[c + 1], [&](const Peak& a, const Peak& b) {
          return a.width_px > b.width_px || (a.width_px == b.width_px && stronger(a, b));
        });
      return;
  }
}

}  // namespace vts::stripe
