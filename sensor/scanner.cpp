#include "sensor/scanner.h"

#include <cmath>
#include <sstream>

namespace vts {
namespace {
std::string bad(const char* field, double value, const char* why) {
  std::ostringstream s;
  s << field << " = " << value << ": " << why;
  return s.str();
}

bool finite_positive(double v) { return std::isfinite(v) && v > 0.0; }
bool probability(double v) { return std::isfinite(v) && v >= 0.0 && v <= 1.0; }
}  // namespace

std::string validate(const ScannerDesc& d) {
  if (!std::isfinite(d.fan_deg) || d.fan_deg <= 0.0 || d.fan_deg >= 170.0)
    return bad("fan_deg", d.fan_deg, "must be > 0 and < 170 degrees");
  if (d.points < kMinPoints || d.points > kMaxPoints)
    return bad("points", d.points, "must be between 16 and 4096");
  if (!finite_positive(d.rate_hz)) return bad("rate_hz", d.rate_hz, "must be > 0");
  if (!d.tool_from_laser.matrix().allFinite()) return "tool_from_laser: must be finite";

  if (!finite_positive(d.min_range_mm))
    return bad("min_range_mm", d.min_range_mm, "must be > 0");
  if (!std::isfinite(d.max_range_mm) || d.max_range_mm <= d.min_range_mm)
    return bad("max_range_mm", d.max_range_mm, "must be greater than min_range_mm");
  if (!finite_positive(d.max_hit_mm)) return bad("max_hit_mm", d.max_hit_mm, "must be > 0");
  if (d.roi_first_column < 0 || d.roi_first_column >= d.points)
    return bad("roi_first_column", d.roi_first_column, "must be >= 0 and < points");
  if (d.roi_last_column < d.roi_first_column)
    return bad("roi_last_column", d.roi_last_column, "must be >= roi_first_column");
  if (!std::isfinite(d.max_incidence_deg) || d.max_incidence_deg <= 0.0 ||
      d.max_incidence_deg > 90.0)
    return bad("max_incidence_deg", d.max_incidence_deg, "must be > 0 and <= 90 degrees");

  if (!finite_positive(d.baseline_mm)) return bad("baseline_mm", d.baseline_mm, "must be > 0");
  if (!std::isfinite(d.triangulation_deg) || d.triangulation_deg <= 0.0 ||
      d.triangulation_deg >= 80.0)
    return bad("triangulation_deg", d.triangulation_deg, "must be > 0 and < 80 degrees");
  if (!finite_positive(d.focal_length_mm))
    return bad("focal_length_mm", d.focal_length_mm, "must be > 0");
  if (!finite_positive(d.pixel_pitch_um))
    return bad("pixel_pitch_um", d.pixel_pitch_um, "must be > 0");
  if (d.image_width_px < 1 || d.image_width_px > 65536)
    return bad("image_width_px", d.image_width_px, "must be between 1 and 65536");
  if (d.image_height_px < 1 || d.image_height_px > 65536)
    return bad("image_height_px", d.image_height_px, "must be between 1 and 65536");
  if (!std::isfinite(d.subpixel_step_px) || d.subpixel_step_px <= 0.0 || d.subpixel_step_px > 1.0)
    return bad("subpixel_step_px", d.subpixel_step_px, "must be > 0 and <= 1");
  if (!finite_positive(d.intensity_ref_range_mm))
    return bad("intensity_ref_range_mm", d.intensity_ref_range_mm, "must be > 0");

  if (!std::isfinite(d.speckle_px) || d.speckle_px < 0.0)
    return bad("speckle_px", d.speckle_px, "must be >= 0");
  if (!std::isfinite(d.reflectivity) || d.reflectivity < 0.0 || d.reflectivity > 1.0)
    return bad("reflectivity", d.reflectivity, "must be between 0 and 1");
  if (!probability(d.shiny_cluster_prob))
    return bad("shiny_cluster_prob", d.shiny_cluster_prob, "must be between 0 and 1");
  if (d.shiny_cluster_max_points < 1 || d.shiny_cluster_max_points > 64)
    return bad("shiny_cluster_max_points", d.shiny_cluster_max_points, "must be between 1 and 64");
  if (!std::isfinite(d.shiny_offset_min_mm) || d.shiny_offset_min_mm < 0.0)
    return bad("shiny_offset_min_mm", d.shiny_offset_min_mm, "must be >= 0");
  if (!std::isfinite(d.shiny_offset_max_mm) || d.shiny_offset_max_mm < d.shiny_offset_min_mm)
    return bad("shiny_offset_max_mm", d.shiny_offset_max_mm, "must be >= shiny_offset_min_mm");
  if (!probability(d.rough_outlier_prob))
    return bad("rough_outlier_prob", d.rough_outlier_prob, "must be between 0 and 1");
  if (!std::isfinite(d.rough_offset_min_mm) || d.rough_offset_min_mm < 0.0)
    return bad("rough_offset_min_mm", d.rough_offset_min_mm, "must be >= 0");
  if (!std::isfinite(d.rough_offset_max_mm) || d.rough_offset_max_mm < d.rough_offset_min_mm)
    return bad("rough_offset_max_mm", d.rough_offset_max_mm, "must be >= rough_offset_min_mm");
  if (!probability(d.dropout_prob_normal))
    return bad("dropout_prob_normal", d.dropout_prob_normal, "must be between 0 and 1");
  if (!probability(d.dropout_prob_grazing))
    return bad("dropout_prob_grazing", d.dropout_prob_grazing, "must be between 0 and 1");
  return {};
}

}  // namespace vts
