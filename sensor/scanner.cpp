#include "sensor/scanner.h"

#include <cmath>
#include <utility>

#include "sensor/field_error.h"
#include "stripe/peaks.h"

namespace vts {
namespace {
bool finite_positive(double v) { return std::isfinite(v) && v > 0.0; }
bool probability(double v) { return std::isfinite(v) && v >= 0.0 && v <= 1.0; }
}  // namespace

std::string validate(const ScannerDesc& d) {
  if (!std::isfinite(d.fan_deg) || d.fan_deg <= 0.0 || d.fan_deg >= 170.0)
    return field_error("fan_deg", d.fan_deg, "must be > 0 and < 170 degrees");
  if (d.points < kMinPoints || d.points > kMaxPoints)
    return field_error("points", d.points, "must be between 16 and 4096");
  if (!finite_positive(d.rate_hz)) return field_error("rate_hz", d.rate_hz, "must be > 0");
  if (!d.tool_from_laser.matrix().allFinite()) return "tool_from_laser: must be finite";

  if (!finite_positive(d.min_range_mm)) return field_error("min_range_mm", d.min_range_mm, "must be > 0");
  if (!std::isfinite(d.max_range_mm) || d.max_range_mm <= d.min_range_mm)
    return field_error("max_range_mm", d.max_range_mm, "must be greater than min_range_mm");
  if (!finite_positive(d.max_hit_mm)) return field_error("max_hit_mm", d.max_hit_mm, "must be > 0");
  if (d.roi_first_column < 0 || d.roi_first_column >= d.points)
    return field_error("roi_first_column", d.roi_first_column, "must be >= 0 and < points");
  if (d.roi_last_column < d.roi_first_column)
    return field_error("roi_last_column", d.roi_last_column, "must be >= roi_first_column");
  if (!std::isfinite(d.max_incidence_deg) || d.max_incidence_deg <= 0.0 ||
      d.max_incidence_deg > 90.0)
    return field_error("max_incidence_deg", d.max_incidence_deg, "must be > 0 and <= 90 degrees");

  if (!finite_positive(d.baseline_mm)) return field_error("baseline_mm", d.baseline_mm, "must be > 0");
  if (!std::isfinite(d.triangulation_deg) || d.triangulation_deg <= 0.0 ||
      d.triangulation_deg >= 80.0)
    return field_error("triangulation_deg", d.triangulation_deg, "must be > 0 and < 80 degrees");
  if (!finite_positive(d.focal_length_mm)) return field_error("focal_length_mm", d.focal_length_mm, "must be > 0");
  if (!finite_positive(d.pixel_pitch_um)) return field_error("pixel_pitch_um", d.pixel_pitch_um, "must be > 0");
  if (d.image_width_px < 1 || d.image_width_px > 65536)
    return field_error("image_width_px", d.image_width_px, "must be between 1 and 65536");
  if (d.image_height_px < 1 || d.image_height_px > 65536)
    return field_error("image_height_px", d.image_height_px, "must be between 1 and 65536");
  if (!std::isfinite(d.subpixel_step_px) || d.subpixel_step_px <= 0.0 || d.subpixel_step_px > 1.0)
    return field_error("subpixel_step_px", d.subpixel_step_px, "must be > 0 and <= 1");
  if (!finite_positive(d.intensity_ref_range_mm))
    return field_error("intensity_ref_range_mm", d.intensity_ref_range_mm, "must be > 0");

  if (!std::isfinite(d.speckle_px) || d.speckle_px < 0.0)
    return field_error("speckle_px", d.speckle_px, "must be >= 0");
  if (!std::isfinite(d.reflectivity) || d.reflectivity < 0.0 || d.reflectivity > 1.0)
    return field_error("reflectivity", d.reflectivity, "must be between 0 and 1");
  if (!probability(d.shiny_cluster_prob))
    return field_error("shiny_cluster_prob", d.shiny_cluster_prob, "must be between 0 and 1");
  if (d.shiny_cluster_max_points < 1 || d.shiny_cluster_max_points > 64)
    return field_error("shiny_cluster_max_points", d.shiny_cluster_max_points, "must be between 1 and 64");
  if (!std::isfinite(d.shiny_offset_min_mm) || d.shiny_offset_min_mm < 0.0)
    return field_error("shiny_offset_min_mm", d.shiny_offset_min_mm, "must be >= 0");
  if (!std::isfinite(d.shiny_offset_max_mm) || d.shiny_offset_max_mm < d.shiny_offset_min_mm)
    return field_error("shiny_offset_max_mm", d.shiny_offset_max_mm, "must be >= shiny_offset_min_mm");
  if (!probability(d.rough_outlier_prob))
    return field_error("rough_outlier_prob", d.rough_outlier_prob, "must be between 0 and 1");
  if (!std::isfinite(d.rough_offset_min_mm) || d.rough_offset_min_mm < 0.0)
    return field_error("rough_offset_min_mm", d.rough_offset_min_mm, "must be >= 0");
  if (!std::isfinite(d.rough_offset_max_mm) || d.rough_offset_max_mm < d.rough_offset_min_mm)
    return field_error("rough_offset_max_mm", d.rough_offset_max_mm, "must be >= rough_offset_min_mm");
  if (!probability(d.dropout_prob_normal))
    return field_error("dropout_prob_normal", d.dropout_prob_normal, "must be between 0 and 1");
  if (!probability(d.dropout_prob_grazing))
    return field_error("dropout_prob_grazing", d.dropout_prob_grazing, "must be between 0 and 1");
  // The camera image's fields (sensor/camera_image.h).
  if (!std::isfinite(d.scheimpflug_deg) || std::abs(d.scheimpflug_deg) >= 45.0)
    return field_error("scheimpflug_deg", d.scheimpflug_deg, "must be between -45 and 45 degrees");
  const std::pair<const char*, double> positive[] = {
      {"f_number", d.f_number},           {"wavelength_nm", d.wavelength_nm},
      {"laser_power_mw", d.laser_power_mw}, {"sheet_waist_mm", d.sheet_waist_mm},
      {"sheet_focus_mm", d.sheet_focus_mm}, {"exposure_us", d.exposure_us},
      {"gain", d.gain},                   {"full_well_e", d.full_well_e}};
  for (const auto& [field, v] : positive)
    if (!finite_positive(v)) return field_error(field, v, "must be > 0");
  if (!std::isfinite(d.sheet_m2) || d.sheet_m2 < 1.0) return field_error("sheet_m2", d.sheet_m2, "must be >= 1");
  const std::pair<const char*, double> non_negative[] = {
      {"psf_sigma_px", d.psf_sigma_px},   {"read_noise_e", d.read_noise_e},
      {"dark_offset_dn", d.dark_offset_dn}, {"ambient_w_m2", d.ambient_w_m2},
      {"specular_lobe_deg", d.specular_lobe_deg}, {"speckle_contrast", d.speckle_contrast},
      {"peak_threshold_dn", d.peak_threshold_dn}};
  for (const auto& [field, v] : non_negative)
    if (!std::isfinite(v) || v < 0.0) return field_error(field, v, "must be >= 0");
  if (!probability(d.quantum_efficiency))
    return field_error("quantum_efficiency", d.quantum_efficiency, "must be between 0 and 1");
  if (!probability(d.specular_reflectance) || d.specular_reflectance + d.reflectivity > 1.0 + 1e-9)
    return field_error("specular_reflectance", d.specular_reflectance,
                       "must be between 0 and 1, and with reflectivity at most 1");
  if (d.specular_reflectance > 0.0 && d.specular_lobe_deg <= 0.0)
    return field_error("specular_lobe_deg", d.specular_lobe_deg, "must be > 0 when specular_reflectance > 0");
  if (d.image_bits != 8 && d.image_bits != 10 && d.image_bits != 12 && d.image_bits != 16)
    return field_error("image_bits", d.image_bits, "must be 8, 10, 12 or 16");
  if (d.image_roi_first_row < 0 || d.image_roi_first_row >= d.image_height_px)
    return field_error("image_roi_first_row", d.image_roi_first_row, "must be a row of the image");
  if (d.image_roi_rows < 0 || d.image_roi_first_row + d.image_roi_rows > d.image_height_px)
    return field_error("image_roi_rows", d.image_roi_rows, "must be >= 0 and end inside the image");
  if (d.peak_window_px < 1 || d.peak_window_px > 32)
    return field_error("peak_window_px", d.peak_window_px, "must be between 1 and 32");
  if (!stripe::parse_sub_pixel(d.peak_method))
    return "peak_method = '" + d.peak_method + "': must be one of " + stripe::sub_pixel_names();
  if (!stripe::parse_peak_policy(d.peak_policy))
    return "peak_policy = '" + d.peak_policy + "': must be one of " + stripe::peak_policy_names();
  return {};
}

}  // namespace vts
