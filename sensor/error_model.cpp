#include "sensor/error_model.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <numbers>

#include "sensor/fast_math.h"
#include "sensor/simd_clones.h"
#include "sensor/rays.h"

namespace vts {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// What each draw of a column is for; part of the hash key, so adding a use
// never shifts the others.
enum Purpose : std::uint64_t {
  kDropout = 1,
  kNoiseA,
  kNoiseB,
  kShinyStart,
  kShinyLength,
  kShinyOffset,
  kShinySign,
  kRoughHit,
  kRoughOffset,
  kRoughSign,
  kPurposes = 16,
};

// SplitMix64's finaliser: a bijective 64-bit mix with full avalanche.
constexpr std::uint64_t mix(std::uint64_t z) {
  z += 0x9e3779b97f4a7c15ULL;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

// The half of every draw's hash that depends on the profile only.
std::uint64_t profile_key(std::uint64_t seed, std::int64_t profile) {
  return mix(mix(seed) ^ static_cast<std::uint64_t>(profile));
}
// The half that depends on (column, purpose) only, cached per run in
// ScanState::column_keys at [p * points + column].
std::uint64_t column_key(int column, std::uint64_t p) {
  return mix(static_cast<std::uint64_t>(column) * kPurposes + p);
}

// Counter-based draws for one profile: uniform(column, purpose) is a pure
// function of (seed, profile index, column, purpose): unit_from_hash of
// mix(profile_key ^ column_key).
class Draws {
 public:
  Draws(std::uint64_t key, const std::uint64_t* column_keys, int points)
      : key_(key), column_keys_(column_keys), points_(points) {}
  // In [0, 1), 53 random bits.
  double uniform(int column, Purpose p) const {
    return unit_from_hash(mix(key_ ^ column_keys_[static_cast<std::size_t>(p) * points_ + column]));
  }

 private:
  std::uint64_t key_;
  const std::uint64_t* column_keys_;
  int points_;
};

// The draws every column needs, a whole profile at a time in loops without
// branches, so that they vectorize (cloned for AVX2 and AVX-512 with GCC on
// x86-64; the clones compute the same values).

// out[i] = Draws::uniform(i, p), keys = column_keys + p * n.
VTS_SIMD_CLONES void uniforms(std::uint64_t key, const std::uint64_t* __restrict keys, int n,
                              double* __restrict out) {
  for (int i = 0; i < n; ++i) out[i] = unit_from_hash(mix(key ^ keys[i]));
}

// out[i] = scale * a standard normal (Box-Muller of the kNoiseA and kNoiseB
// draws of column i).
VTS_SIMD_CLONES void normals(std::uint64_t key, const std::uint64_t* __restrict keys_a,
                             const std::uint64_t* __restrict keys_b, int n, double scale,
                             double* __restrict out) {
  for (int i = 0; i < n; ++i) {
    const double u1 = 1.0 - unit_from_hash(mix(key ^ keys_a[i]));  // (0, 1]
    const double u2 = unit_from_hash(mix(key ^ keys_b[i]));
    out[i] = scale * (std::sqrt(-2.0 * log_unit(u1)) * cos_turns(u2));
  }
}

// Conditions measure_columns finds per column (bits of `flags`).
enum ColumnFlag : std::int32_t {
  kFlagGrazing = 1,        // beyond the incidence limit
  kFlagOutsideColumns = 2, // outside the image columns
  kFlagDropout = 4,        // a random dropout
  kFlagPeakLost = 8,       // the peak behind the laser or outside the image rows
};

// What measure_columns needs of the scanner besides its camera.
struct ColumnParams {
  double rough_prob, rough_min_mm, rough_span_mm;
  double cos_max_incidence, drop_normal, drop_span;
  double step_px, height_px;
  double reflectivity, intensity_ref_mm;
};

// The arithmetic of the model for every column of a profile at once,
// branch-free so that it vectorizes (unlit columns give meaningless values):
// flags[i] (ColumnFlag bits) and the measured y, z, range and intensity if
// the column is measured. The peak, the lit point moved along its column ray
// by the reflection cluster's offset, or else by a rough-surface outlier
// (u_hit < p, size min + span u_off, sign by u_sign), gets speckle noise on
// its image row, is quantized to the sub-pixel step and must fall inside the
// image in front of the laser; it is triangulated back on the column ray.
// Dropouts: probability rising as sin^4 of the incidence.
VTS_SIMD_CLONES void measure_columns(
    int n, const float* __restrict cos_incidence, const float* __restrict z_ideal,
    const float* __restrict range_ideal, const double* __restrict tan, const double* __restrict secant,
    const float* __restrict cluster, const double* __restrict u_drop, const double* __restrict u_hit,
    const double* __restrict u_off, const double* __restrict u_sign, const double* __restrict noise,
    const CameraModel cam, const ColumnParams p, std::int32_t* __restrict flags, float* __restrict y_out,
    float* __restrict z_out, float* __restrict range_out, float* __restrict intensity_out) {
  for (int i = 0; i < n; ++i) {
    const double cos_inc = cos_incidence[i];
    const double rt = range_ideal[i];
    const double t = tan[i];
    const double sin2 = 1.0 - cos_inc * cos_inc;
    const double p_drop = p.drop_normal + p.drop_span * sin2 * sin2;
    const double mag = p.rough_min_mm + p.rough_span_mm * u_off[i];
    const double rough = u_hit[i] < p.rough_prob ? (u_sign[i] < 0.5 ? -mag : mag) : 0.0;
    const double range = rt + (cluster[i] != 0.0f ? double(cluster[i]) : rough);
    const double z_peak = double(z_ideal[i]) * (range / rt);
    const double row = (image_row_px(cam, z_peak) + cam.half_height_px) + noise[i];
    const double row_q = p.step_px * round_half_away(row / p.step_px);
    const double z = depth_of_row_mm(cam, row_q - cam.half_height_px);
    const int peak_lost = !((range > 0.0) & (row_q >= 0.0) & (row_q < p.height_px) & (z > 0.0));
    const double a = p.intensity_ref_mm / rt;
    const double v = p.reflectivity * cos_inc * a * a;
    const double intensity = v < 0.0 ? 0.0 : (1.0 < v ? 1.0 : v);  // std::clamp(v, 0, 1)
    flags[i] = (cos_inc < p.cos_max_incidence ? kFlagGrazing : 0) |
               (std::abs(cam.f_px * t / cam.cos_theta) > cam.half_width_px ? kFlagOutsideColumns : 0) |
               (u_drop[i] < p_drop ? kFlagDropout : 0) | (peak_lost ? kFlagPeakLost : 0);
    z_out[i] = static_cast<float>(z);
    y_out[i] = static_cast<float>(t * z);
    range_out[i] = static_cast<float>(z * secant[i]);
    intensity_out[i] = static_cast<float>(intensity);
  }
}

// One profile's counts (ScanState's counters) from classify_columns.
struct ColumnCounts {
  std::int32_t lit = 0, measured = 0, outside_roi = 0, grazing = 0, shadowed = 0, outside_image = 0,
               dropouts = 0, shiny = 0, rough = 0;
};

// What becomes of each column, in the order the model decides it: unlit;
// outside the image-processing region [roi_first, roi_last]; beyond the
// incidence limit; in camera shadow; outside the image columns; a dropout;
// the peak lost. A column lost to any of them (or unlit) is written invalid
// with y, z, range and intensity 0; the rest keep measure_columns' values.
// Branch-free, so that it vectorizes like measure_columns.
VTS_SIMD_CLONES ColumnCounts classify_columns(
    int n, const std::uint8_t* __restrict lit_in, const std::uint8_t* __restrict visible, int roi_first,
    int roi_last, const std::int32_t* __restrict flags, const float* __restrict cluster,
    const double* __restrict u_hit, double rough_prob, std::uint8_t* __restrict valid_out,
    float* __restrict y, float* __restrict z, float* __restrict range, float* __restrict intensity) {
  std::int32_t lit = 0, measured = 0, roi_c = 0, grazing = 0, shadowed = 0, outside = 0, dropouts = 0,
               shiny_c = 0, rough_c = 0;
  for (int i = 0; i < n; ++i) {
    const std::int32_t on = lit_in[i] != 0;
    const std::int32_t f = flags[i];
    const std::int32_t out_roi = (i < roi_first) | (i > roi_last);
    const std::int32_t graze = (1 - out_roi) & ((f & kFlagGrazing) != 0);
    const std::int32_t shadow = (1 - out_roi) & (1 - graze) & (visible[i] == 0);
    const std::int32_t seen = (1 - out_roi) & (1 - graze) & (1 - shadow);
    const std::int32_t out_cols = seen & ((f & kFlagOutsideColumns) != 0);
    const std::int32_t drop = seen & (1 - out_cols) & ((f & kFlagDropout) != 0);
    const std::int32_t peak = seen & (1 - out_cols) & (1 - drop) & ((f & kFlagPeakLost) != 0);
    const std::int32_t meas = on & seen & (1 - out_cols) & (1 - drop) & (1 - peak);
    const std::int32_t shiny = cluster[i] != 0.0f;
    lit += on;
    roi_c += on & out_roi;
    grazing += on & graze;
    shadowed += on & shadow;
    outside += on & (out_cols | peak);
    dropouts += on & drop;
    measured += meas;
    shiny_c += meas & shiny;
    rough_c += meas & (1 - shiny) & (u_hit[i] < rough_prob);
    valid_out[i] = static_cast<std::uint8_t>(meas);
    y[i] = meas ? y[i] : 0.0f;
    z[i] = meas ? z[i] : 0.0f;
    range[i] = meas ? range[i] : 0.0f;
    intensity[i] = meas ? intensity[i] : 0.0f;
  }
  return {lit, measured, roi_c, grazing, shadowed, outside, dropouts, shiny_c, rough_c};
}

void cache_columns(const ScannerDesc& desc, ScanState& state) {
  const int n = desc.points;
  if (state.cached_points == n && state.cached_fan_deg == desc.fan_deg &&
      static_cast<int>(state.column_tan.size()) == n)
    return;
  state.column_tan.resize(n);
  for (int i = 0; i < n; ++i) state.column_tan[i] = column_tan(desc, i);
  state.column_keys.resize(static_cast<std::size_t>(n) * kPurposes);
  for (std::uint64_t p = 0; p < kPurposes; ++p)
    for (int i = 0; i < n; ++i) state.column_keys[p * n + i] = column_key(i, p);
  state.cluster_offset_mm.resize(n);
  state.column_secant.resize(n);
  for (int i = 0; i < n; ++i) state.column_secant[i] = std::sqrt(1.0 + state.column_tan[i] * state.column_tan[i]);
  for (auto* v : {&state.u_drop, &state.noise_px, &state.u_rough_hit, &state.u_rough_size, &state.u_rough_sign})
    v->resize(n);
  state.flags.resize(n);
  state.cached_points = n;
  state.cached_fan_deg = desc.fan_deg;
}

}  // namespace

void add_counts(ScanState& total, const ScanState& part) {
  total.profiles += part.profiles;
  total.lit += part.lit;
  total.measured += part.measured;
  total.outside_roi += part.outside_roi;
  total.grazing += part.grazing;
  total.shadowed += part.shadowed;
  total.outside_image += part.outside_image;
  total.dropouts += part.dropouts;
  total.shiny_outliers += part.shiny_outliers;
  total.rough_outliers += part.rough_outliers;
}

CameraModel camera_model(const ScannerDesc& d) {
  CameraModel cam;
  const double theta = d.triangulation_deg * kDeg;
  cam.cos_theta = std::cos(theta);
  cam.f_px = d.focal_length_mm / (d.pixel_pitch_um * 1e-3);
  cam.k_mm_px = cam.f_px * d.baseline_mm / (cam.cos_theta * cam.cos_theta);
  cam.u_inf_px = cam.f_px * std::tan(theta);
  cam.centre_mm = Eigen::Vector3d(d.baseline_mm, 0.0, d.baseline_mm * std::tan(theta));
  cam.axis = Eigen::Vector3d(-std::sin(theta), 0.0, cam.cos_theta);
  cam.half_height_px = 0.5 * d.image_height_px;
  cam.half_width_px = 0.5 * d.image_width_px;
  return cam;
}

double depth_step_mm(const ScannerDesc& desc, double z_mm) {
  return z_mm * z_mm * desc.subpixel_step_px / camera_model(desc).k_mm_px;
}

double depth_noise_mm(const ScannerDesc& desc, double z_mm) {
  return z_mm * z_mm * desc.speckle_px / camera_model(desc).k_mm_px;
}

double lateral_spacing_mm(const ScannerDesc& desc, double z_mm) {
  return z_mm * 2.0 * std::tan(0.5 * desc.fan_deg * kDeg) / desc.points;
}

Eigen::Vector2d image_depth_limits_mm(const ScannerDesc& desc) {
  const CameraModel cam = camera_model(desc);
  const double near = depth_of_row_mm(cam, -cam.half_height_px);
  const double far = cam.u_inf_px > cam.half_height_px ? depth_of_row_mm(cam, cam.half_height_px)
                                                       : std::numeric_limits<double>::infinity();
  return {near, far};
}

bool image_covers_fan(const ScannerDesc& desc) {
  const CameraModel cam = camera_model(desc);
  const double t = std::abs(column_tan(desc, 0));
  return cam.f_px * t / cam.cos_theta <= cam.half_width_px;
}

void apply_error_model(const ScannerDesc& desc, const Profile& ideal, ScanState& state,
                       Profile& m) {
  const int n = ideal.size();
  assert(ideal.sized(n));
  assert(n == desc.points);
  if (!m.sized(n)) m.resize(n);
  m.world_from_sensor = ideal.world_from_sensor;
  m.time_s = ideal.time_s;
  m.index = ideal.index;
  cache_columns(desc, state);
  ++state.profiles;

  const CameraModel cam = camera_model(desc);
  const std::uint64_t key = profile_key(state.seed, ideal.index);
  const std::uint64_t* keys = state.column_keys.data();
  const Draws draws(key, keys, n);
  const double cos_max_incidence = std::cos(desc.max_incidence_deg * kDeg);
  const int roi_last = std::min(desc.roi_last_column, n - 1);
  const double step = desc.subpixel_step_px;
  const double height = desc.image_height_px;

  // Reflection clusters: a cluster starts at column j with probability p and
  // covers columns j .. j + L - 1, L uniform in 1..max; a later start
  // overrides an earlier one. Every column's draws are made whether or not it
  // is lit, so both sources see the same clusters.
  std::fill(state.cluster_offset_mm.begin(), state.cluster_offset_mm.end(), 0.0f);
  double* const u_drop = state.u_drop.data();
  if (!desc.ideal && desc.shiny_cluster_prob > 0.0) {
    const int max_len = desc.shiny_cluster_max_points;
    double* const u_start = u_drop;  // the dropout draws overwrite them below
    uniforms(key, keys + kShinyStart * n, n, u_start);
    for (int j = 0; j < n; ++j) {
      if (!(u_start[j] < desc.shiny_cluster_prob)) continue;
      const int len = std::min(max_len, 1 + static_cast<int>(draws.uniform(j, kShinyLength) * max_len));
      const double mag = desc.shiny_offset_min_mm +
                         (desc.shiny_offset_max_mm - desc.shiny_offset_min_mm) *
                             draws.uniform(j, kShinyOffset);
      const double offset = draws.uniform(j, kShinySign) < 0.5 ? -mag : mag;
      for (int k = j; k < std::min(n, j + len); ++k)
        state.cluster_offset_mm[k] = static_cast<float>(offset);
    }
  }

  std::copy(ideal.y_mm.begin(), ideal.y_mm.end(), m.true_y_mm.begin());
  std::copy(ideal.z_mm.begin(), ideal.z_mm.end(), m.true_z_mm.begin());
  std::copy(ideal.valid.begin(), ideal.valid.end(), m.true_valid.begin());
  std::copy(ideal.cos_incidence.begin(), ideal.cos_incidence.end(), m.cos_incidence.begin());
  std::copy(ideal.camera_visible.begin(), ideal.camera_visible.end(), m.camera_visible.begin());
  auto intensity = [&](int i) {
    const double range_true = ideal.range_mm[i];
    return static_cast<float>(std::clamp(desc.reflectivity * double(ideal.cos_incidence[i]) *
                                             (desc.intensity_ref_range_mm / range_true) *
                                             (desc.intensity_ref_range_mm / range_true),
                                         0.0, 1.0));
  };

  if (desc.ideal) {
    std::fill(m.valid.begin(), m.valid.end(), std::uint8_t{0});
    std::fill(m.y_mm.begin(), m.y_mm.end(), 0.0f);
    std::fill(m.z_mm.begin(), m.z_mm.end(), 0.0f);
    std::fill(m.range_mm.begin(), m.range_mm.end(), 0.0f);
    std::fill(m.intensity.begin(), m.intensity.end(), 0.0f);
    for (int i = 0; i < n; ++i) {
      if (!ideal.valid[i]) continue;
      ++state.lit;
      m.valid[i] = 1;
      m.y_mm[i] = ideal.y_mm[i];
      m.z_mm[i] = ideal.z_mm[i];
      m.range_mm[i] = ideal.range_mm[i];
      m.intensity[i] = intensity(i);
      ++state.measured;
    }
    return;
  }

  // Every column's draws, then the model's arithmetic for every column, a
  // whole profile at a time (uniforms, normals and measure_columns vectorize).
  double* const noise = state.noise_px.data();
  double* const u_hit = state.u_rough_hit.data();
  double* const u_off = state.u_rough_size.data();
  double* const u_sign = state.u_rough_sign.data();
  uniforms(key, keys + kDropout * n, n, u_drop);
  if (desc.speckle_px > 0.0)
    normals(key, keys + kNoiseA * n, keys + kNoiseB * n, n, desc.speckle_px, noise);
  else
    std::fill(noise, noise + n, 0.0);
  const bool rough_on = desc.rough_outlier_prob > 0.0;
  if (rough_on) {
    uniforms(key, keys + kRoughHit * n, n, u_hit);
    uniforms(key, keys + kRoughOffset * n, n, u_off);
    uniforms(key, keys + kRoughSign * n, n, u_sign);
  } else {
    std::fill(u_hit, u_hit + n, 1.0);  // never below a probability of 0
    std::fill(u_off, u_off + n, 0.0);
    std::fill(u_sign, u_sign + n, 0.0);
  }
  const ColumnParams params{desc.rough_outlier_prob, desc.rough_offset_min_mm,
                            desc.rough_offset_max_mm - desc.rough_offset_min_mm, cos_max_incidence,
                            desc.dropout_prob_normal, desc.dropout_prob_grazing - desc.dropout_prob_normal,
                            step, height, desc.reflectivity, desc.intensity_ref_range_mm};
  std::int32_t* const flags = state.flags.data();
  measure_columns(n, ideal.cos_incidence.data(), ideal.z_mm.data(), ideal.range_mm.data(),
                  state.column_tan.data(), state.column_secant.data(), state.cluster_offset_mm.data(),
                  u_drop, u_hit, u_off, u_sign, noise, cam, params, flags, m.y_mm.data(), m.z_mm.data(),
                  m.range_mm.data(), m.intensity.data());
  const ColumnCounts k =
      classify_columns(n, ideal.valid.data(), ideal.camera_visible.data(), desc.roi_first_column, roi_last, flags,
                       state.cluster_offset_mm.data(), u_hit, desc.rough_outlier_prob, m.valid.data(), m.y_mm.data(),
                       m.z_mm.data(), m.range_mm.data(), m.intensity.data());
  state.lit += k.lit;
  state.measured += k.measured;
  state.outside_roi += k.outside_roi;
  state.grazing += k.grazing;
  state.shadowed += k.shadowed;
  state.outside_image += k.outside_image;
  state.dropouts += k.dropouts;
  state.shiny_outliers += k.shiny;
  state.rough_outliers += k.rough;
}

}  // namespace vts
