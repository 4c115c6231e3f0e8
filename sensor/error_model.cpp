#include "sensor/error_model.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <numbers>

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

// Counter-based draws for one profile: uniform(column, purpose) is a pure
// function of (seed, profile index, column, purpose).
// column_keys[column * kPurposes + p] must hold column_key(column, p) (the
// half of the hash that does not depend on the profile, cached per run).
class Draws {
 public:
  Draws(std::uint64_t seed, std::int64_t profile, const std::uint64_t* column_keys)
      : key_(mix(mix(seed) ^ static_cast<std::uint64_t>(profile))), column_keys_(column_keys) {}

  static std::uint64_t column_key(int column, std::uint64_t p) {
    return mix(static_cast<std::uint64_t>(column) * kPurposes + p);
  }
  // In [0, 1), 53 random bits.
  double uniform(int column, Purpose p) const {
    const std::uint64_t h = mix(key_ ^ column_keys_[static_cast<std::size_t>(column) * kPurposes + p]);
    return static_cast<double>(h >> 11) * 0x1.0p-53;
  }
  // Standard normal (Box-Muller).
  double normal(int column) const {
    const double u1 = 1.0 - uniform(column, kNoiseA);  // (0, 1]
    const double u2 = uniform(column, kNoiseB);
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * std::numbers::pi * u2);
  }

 private:
  std::uint64_t key_;
  const std::uint64_t* column_keys_;
};

void cache_columns(const ScannerDesc& desc, ScanState& state) {
  if (state.cached_points == desc.points && state.cached_fan_deg == desc.fan_deg &&
      static_cast<int>(state.column_tan.size()) == desc.points)
    return;
  state.column_tan.resize(desc.points);
  for (int i = 0; i < desc.points; ++i) state.column_tan[i] = column_tan(desc, i);
  state.column_keys.resize(static_cast<std::size_t>(desc.points) * kPurposes);
  for (int i = 0; i < desc.points; ++i)
    for (std::uint64_t p = 0; p < kPurposes; ++p)
      state.column_keys[static_cast<std::size_t>(i) * kPurposes + p] = Draws::column_key(i, p);
  state.cached_points = desc.points;
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

double image_row_px(const CameraModel& cam, double z_mm) { return cam.u_inf_px - cam.k_mm_px / z_mm; }

double depth_of_row_mm(const CameraModel& cam, double row_px) {
  const double den = cam.u_inf_px - row_px;
  return den > 0.0 ? cam.k_mm_px / den : 0.0;
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
  if (static_cast<int>(state.cluster_offset_mm.size()) != n) state.cluster_offset_mm.resize(n);
  ++state.profiles;

  const CameraModel cam = camera_model(desc);
  const Draws draws(state.seed, ideal.index, state.column_keys.data());
  const double cos_max_incidence = std::cos(desc.max_incidence_deg * kDeg);
  const int roi_last = std::min(desc.roi_last_column, n - 1);
  const double step = desc.subpixel_step_px;
  const double height = desc.image_height_px;

  // Reflection clusters: a cluster starts at column j with probability p and
  // covers columns j .. j + L - 1, L uniform in 1..max; a later start
  // overrides an earlier one. Every column's draws are made whether or not it
  // is lit, so both sources see the same clusters.
  std::fill(state.cluster_offset_mm.begin(), state.cluster_offset_mm.end(), 0.0f);
  if (!desc.ideal && desc.shiny_cluster_prob > 0.0) {
    const int max_len = desc.shiny_cluster_max_points;
    for (int j = 0; j < n; ++j) {
      if (!(draws.uniform(j, kShinyStart) < desc.shiny_cluster_prob)) continue;
      const int len = std::min(max_len, 1 + static_cast<int>(draws.uniform(j, kShinyLength) * max_len));
      const double mag = desc.shiny_offset_min_mm +
                         (desc.shiny_offset_max_mm - desc.shiny_offset_min_mm) *
                             draws.uniform(j, kShinyOffset);
      const double offset = draws.uniform(j, kShinySign) < 0.5 ? -mag : mag;
      for (int k = j; k < std::min(n, j + len); ++k)
        state.cluster_offset_mm[k] = static_cast<float>(offset);
    }
  }

  for (int i = 0; i < n; ++i) {
    m.true_y_mm[i] = ideal.y_mm[i];
    m.true_z_mm[i] = ideal.z_mm[i];
    m.true_valid[i] = ideal.valid[i];
    m.cos_incidence[i] = ideal.cos_incidence[i];
    m.camera_visible[i] = ideal.camera_visible[i];
    m.valid[i] = 0;
    m.y_mm[i] = m.z_mm[i] = m.range_mm[i] = 0.0f;
    m.intensity[i] = 0.0f;
    if (!ideal.valid[i]) continue;
    ++state.lit;

    const double cos_inc = ideal.cos_incidence[i];
    const double range_true = ideal.range_mm[i];
    const double intensity = std::clamp(
        desc.reflectivity * cos_inc *
            (desc.intensity_ref_range_mm / range_true) * (desc.intensity_ref_range_mm / range_true),
        0.0, 1.0);

    if (desc.ideal) {
      m.valid[i] = 1;
      m.y_mm[i] = ideal.y_mm[i];
      m.z_mm[i] = ideal.z_mm[i];
      m.range_mm[i] = ideal.range_mm[i];
      m.intensity[i] = static_cast<float>(intensity);
      ++state.measured;
      continue;
    }

    if (i < desc.roi_first_column || i > roi_last) {
      ++state.outside_roi;
      continue;
    }
    if (cos_inc < cos_max_incidence) {
      ++state.grazing;
      continue;
    }
    if (!ideal.camera_visible[i]) {
      ++state.shadowed;
      continue;
    }
    const double t = state.column_tan[i];
    if (std::abs(cam.f_px * t / cam.cos_theta) > cam.half_width_px) {
      ++state.outside_image;
      continue;
    }
    const double sin2 = 1.0 - cos_inc * cos_inc;
    const double p_drop = desc.dropout_prob_normal +
                          (desc.dropout_prob_grazing - desc.dropout_prob_normal) * sin2 * sin2;
    if (draws.uniform(i, kDropout) < p_drop) {
      ++state.dropouts;
      continue;
    }

    // The peak: the lit point, or a displaced one along the same column ray.
    double range = range_true;
    bool shiny = false, rough = false;
    if (state.cluster_offset_mm[i] != 0.0f) {
      range += state.cluster_offset_mm[i];
      shiny = true;
    } else if (desc.rough_outlier_prob > 0.0 &&
               draws.uniform(i, kRoughHit) < desc.rough_outlier_prob) {
      const double mag = desc.rough_offset_min_mm +
                         (desc.rough_offset_max_mm - desc.rough_offset_min_mm) *
                             draws.uniform(i, kRoughOffset);
      range += draws.uniform(i, kRoughSign) < 0.5 ? -mag : mag;
      rough = true;
    }
    if (!(range > 0.0)) {
      ++state.outside_image;
      continue;
    }
    const double z_peak = double(ideal.z_mm[i]) * (range / range_true);

    // Image row from the top edge, with speckle, quantized to the sub-pixel step.
    double row = image_row_px(cam, z_peak) + cam.half_height_px;
    if (desc.speckle_px > 0.0) row += desc.speckle_px * draws.normal(i);
    const double row_q = step * std::round(row / step);
    const double z = depth_of_row_mm(cam, row_q - cam.half_height_px);
    if (!(row_q >= 0.0 && row_q < height) || !(z > 0.0)) {
      ++state.outside_image;
      continue;
    }
    m.valid[i] = 1;
    m.z_mm[i] = static_cast<float>(z);
    m.y_mm[i] = static_cast<float>(t * z);
    m.range_mm[i] = static_cast<float>(z * std::sqrt(1.0 + t * t));
    m.intensity[i] = static_cast<float>(intensity);
    ++state.measured;
    state.shiny_outliers += shiny;
    state.rough_outliers += rough;
  }
}

}  // namespace vts
