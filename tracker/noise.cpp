#include "tracker/noise.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>

namespace vts::tracker {

double estimate_noise_mm(const ProfileView& p, int roi_first, int roi_last) {
  const int n = static_cast<int>(p.y_mm.size());
  if (static_cast<int>(p.z_mm.size()) != n || (!p.valid.empty() && static_cast<int>(p.valid.size()) != n)) return 0.0;
  const int lo = std::max(0, roi_first);
  const int hi = roi_last < 0 ? n - 1 : std::min(n - 1, roi_last);
  if (hi - lo < 4) return 0.0;
  // Without branches: the five columns of a run are tested together.
  const bool all_valid = p.valid.empty();
  const float* py = p.y_mm.data();
  const float* pz = p.z_mm.data();
  const std::uint8_t* pv = p.valid.data();
  auto usable = [&](int i) {
    // Comparisons are false for NaN: finite and flagged valid.
    return (all_valid | (!all_valid && pv[i] != 0)) & (std::abs(py[i]) <= 1e30f) & (std::abs(pz[i]) <= 1e30f);
  };
  // Runs of five columns centred on i = lo + 2 + k * stride; squared
  // distances (the median of their roots is the root of their median).
  const int centres = hi - lo - 3;
  const int stride = std::max(1, (centres + kNoiseSamples - 1) / kNoiseSamples);
  // Where the runs lie close together (most columns looked at) the usable
  // flags come a block of columns at a time, in a pass that vectorises.
  constexpr int kBlock = 256;
  std::array<std::uint8_t, kBlock> flags;
  int f0 = 0, f1 = 0;  // flags[k]: usable(f0 + k), for columns f0 <= f0 + k < f1
  const bool blocks = stride <= 8;
  auto run_usable = [&](int i) -> bool {
    if (!blocks) return usable(i - 2) & usable(i - 1) & usable(i) & usable(i + 1) & usable(i + 2);
    if (i + 2 >= f1) {
      f0 = i - 2, f1 = std::min(hi + 1, f0 + kBlock);
      const int len = f1 - f0;
      for (int k = 0; k < len; ++k) flags[k] = (std::abs(py[f0 + k]) <= 1e30f) & (std::abs(pz[f0 + k]) <= 1e30f);
      if (!all_valid)
        for (int k = 0; k < len; ++k) flags[k] &= pv[f0 + k] != 0;
    }
    const std::uint8_t* f = flags.data() + (i - 2 - f0);
    return (f[0] & f[1] & f[2] & f[3] & f[4]) != 0;
  };
  std::array<float, kNoiseSamples + 1> d2;
  int m = 0;
  for (int i = lo + 2; i <= hi - 2 && m <= kNoiseSamples; i += stride) {
    if (!run_usable(i)) continue;
    const float ay = p.y_mm[i - 2], az = p.z_mm[i - 2];
    const float cy = p.y_mm[i + 2] - ay, cz = p.z_mm[i + 2] - az;
    const float len2 = cy * cy + cz * cz;
    if (!(len2 > 1e-18f)) continue;
    const float c = cy * (p.z_mm[i] - az) - cz * (p.y_mm[i] - ay);
    d2[m++] = c * c / len2;
  }
  if (m < 8) return 0.0;
  auto mid = d2.begin() + m / 2;
  std::nth_element(d2.begin(), mid, d2.begin() + m);
  // |N(0, 1.5 sigma^2)| has its median at 0.6745 sqrt(1.5) sigma.
  return std::sqrt(static_cast<double>(*mid)) / (0.6744897501960817 * std::sqrt(1.5));
}

TrackerParams scaled_for_noise(const TrackerParams& params, double sigma_mm) {
  TrackerParams t = params;
  const NoiseParams& np = params.noise;
  if (!np.adapt || !(sigma_mm > 0.0) || !std::isfinite(sigma_mm)) return t;
  auto raise = [&](double& v, double k) { v = std::max(v, k * sigma_mm); };
  raise(t.surface_tol_mm, np.surface_k);
  OutlierParams& op = t.segmentation.outliers;
  raise(op.threshold_mm, np.outlier_k);
  raise(op.support_tol_mm, np.support_k);
  SegmentParams& sp = t.segmentation.segments;
  raise(sp.split_threshold_mm, np.split_k);
  raise(sp.break_min_mm, np.break_k);
  raise(sp.max_merge_offset_mm, np.merge_offset_k);
  raise(sp.fit_tol_mm, np.fit_k);
  return t;
}

}  // namespace vts::tracker
