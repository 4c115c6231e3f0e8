#include "sensor/presets.h"

namespace vts {
namespace {

// Camera figures of every preset come from one design rule (SENSOR_MODEL.md,
// "Designing a preset"): given the depth of field [near, far], the image
// height H, the sub-pixel step s and the wanted depth step at one range, the
// depth gain is K = s z^2 / dz; the principal row is centred on the depth of
// field, F tan(theta) = K (1/near + 1/far) / 2, and the baseline follows as
// b = K cos^2(theta) / F. The image width must hold F tan(fan/2) / cos(theta).
// tests/sensor/error_model_test.cpp checks every preset against these rules.

struct SensorPreset {
  std::string_view name;
  std::string_view description;
  ScannerDesc desc;
};

ScannerDesc mspot() {
  // The paper's M-Spot-like sensor (Cederberg et al., section 3.1 and 3.2.2):
  // 256 or 512 points per profile, 20 Hz, depth resolution 0.015 mm at 100 mm
  // and 1.5 mm at 1000 mm. Near end 40 mm so the paper's closest static setup
  // (D, 55 mm to the root) is measured in full. Camera: 1280 x 1024 pixels of
  // 5.3 um, 8 mm lens, 1/16 px peak detector: K = 41667 mm px.
  ScannerDesc d;  // ScannerDesc's defaults are this preset
  d.name = "mspot";
  return d;
}

ScannerDesc lps_2048_short() {
  // A short-range high-resolution profile sensor, from the figures such
  // datasheets give: 2048 points per profile, 4 kHz at full measuring range,
  // clearance 60 mm, measuring range 40 mm (60..100 mm), field of view about
  // 24 mm near and 40 mm far, depth resolution 1.5 um near to 4 um far.
  // Camera: 2048 x 1088 pixels of 5.5 um, 24 mm lens, 1/16 px: K = 150000 mm px.
  ScannerDesc d;
  d.name = "lps-2048-short";
  d.fan_deg = 22.62;
  d.points = 2048;
  d.rate_hz = 4000.0;
  d.min_range_mm = 60.0;
  d.max_range_mm = 100.0;
  d.max_hit_mm = 110.0;
  d.max_incidence_deg = 80.0;
  d.baseline_mm = 28.4075;
  d.triangulation_deg = 24.6236;
  d.focal_length_mm = 24.0;
  d.pixel_pitch_um = 5.5;
  d.image_width_px = 2048;
  d.image_height_px = 1088;
  d.subpixel_step_px = 0.0625;
  d.intensity_ref_range_mm = 80.0;
  d.sheet_waist_mm = 0.03;  // a thin line focused mid-range
  d.sheet_focus_mm = 80.0;
  return d;
}

ScannerDesc lps_1280_mid() {
  // A mid-range profile sensor of the seam-tracking class: 1280 points, 2 kHz,
  // clearance 100 mm, measuring range 200 mm (100..300 mm), field of view
  // about 60 mm near and 180 mm far, depth resolution 4.5 um near to 40 um far.
  // Camera: 1280 x 1024 pixels of 5.3 um, 10 mm lens, 1/16 px: K = 140000 mm px.
  ScannerDesc d;
  d.name = "lps-1280-mid";
  d.fan_deg = 33.40;
  d.points = 1280;
  d.rate_hz = 2000.0;
  d.min_range_mm = 100.0;
  d.max_range_mm = 300.0;
  d.max_hit_mm = 330.0;
  d.max_incidence_deg = 80.0;
  d.baseline_mm = 59.6130;
  d.triangulation_deg = 26.3201;
  d.focal_length_mm = 10.0;
  d.pixel_pitch_um = 5.3;
  d.image_width_px = 1280;
  d.image_height_px = 1024;
  d.subpixel_step_px = 0.0625;
  d.intensity_ref_range_mm = 170.0;
  d.sheet_waist_mm = 0.06;
  d.sheet_focus_mm = 200.0;
  return d;
}

const std::vector<SensorPreset>& sensors() {
  static const std::vector<SensorPreset> all = {
      {"mspot", "the paper's M-Spot-like seam sensor: 512 points (256 allowed), 20 Hz (default)",
       mspot()},
      {"lps-2048-short", "short-range high-resolution profile sensor: 2048 points, 4 kHz",
       lps_2048_short()},
      {"lps-1280-mid", "mid-range seam-tracking profile sensor: 1280 points, 2 kHz",
       lps_1280_mid()},
  };
  return all;
}

struct Material {
  std::string_view name;
  std::string_view description;
  double speckle_px, reflectivity;
  double shiny_prob;
  int shiny_max_points;
  double shiny_min_mm, shiny_max_mm;
  double rough_prob, rough_min_mm, rough_max_mm;
  double drop_normal, drop_grazing;
  // The camera image's surface (sensor/camera_image.h): specular share,
  // lobe width (deg), speckle contrast.
  double specular, lobe_deg, speckle_contrast;
};

constexpr Material kMaterials[] = {
    {"matte-steel", "blasted or matte mild steel: mild speckle, rare reflections (default)",
     0.1, 0.5, 0.0005, 4, 0.5, 3.0, 0.0002, 0.1, 0.5, 0.001, 0.05, 0.05, 8.0, 0.5},
    {"shiny-steel", "ground or stainless steel: reflection clusters, weaker diffuse return",
     0.15, 0.3, 0.004, 8, 0.5, 5.0, 0.0005, 0.1, 0.5, 0.002, 0.3, 0.5, 2.0, 0.6},
    {"aluminium", "bright aluminium: frequent long reflection clusters, dropouts at grazing",
     0.2, 0.25, 0.01, 10, 0.5, 8.0, 0.001, 0.1, 0.5, 0.005, 0.5, 0.7, 1.5, 0.6},
    {"rough", "mill scale or rough cut surface: strong speckle, isolated rough-surface outliers",
     0.25, 0.4, 0.0, 4, 0.5, 3.0, 0.01, 0.1, 1.0, 0.005, 0.1, 0.0, 20.0, 0.7},
    {"lambertian", "ideal diffuse surface: no speckle, outliers or dropouts (geometry only)",
     0.0, 1.0, 0.0, 1, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 20.0, 0.0},
};

}  // namespace

std::vector<std::string> sensor_preset_names() {
  std::vector<std::string> names;
  for (const auto& p : sensors()) names.emplace_back(p.name);
  return names;
}

std::optional<ScannerDesc> sensor_preset(std::string_view name) {
  for (const auto& p : sensors())
    if (p.name == name) return p.desc;
  return std::nullopt;
}

std::string sensor_preset_description(std::string_view name) {
  for (const auto& p : sensors())
    if (p.name == name) return std::string(p.description);
  return {};
}

void set_sensor_fields(ScannerDesc& d, const ScannerDesc& p) {
  d.name = p.name;
  d.fan_deg = p.fan_deg;
  d.points = p.points;
  d.rate_hz = p.rate_hz;
  d.min_range_mm = p.min_range_mm;
  d.max_range_mm = p.max_range_mm;
  d.max_hit_mm = p.max_hit_mm;
  d.roi_first_column = p.roi_first_column;
  d.roi_last_column = p.roi_last_column;
  d.max_incidence_deg = p.max_incidence_deg;
  d.baseline_mm = p.baseline_mm;
  d.triangulation_deg = p.triangulation_deg;
  d.focal_length_mm = p.focal_length_mm;
  d.pixel_pitch_um = p.pixel_pitch_um;
  d.image_width_px = p.image_width_px;
  d.image_height_px = p.image_height_px;
  d.subpixel_step_px = p.subpixel_step_px;
  d.intensity_ref_range_mm = p.intensity_ref_range_mm;
  d.scheimpflug_deg = p.scheimpflug_deg;
  d.f_number = p.f_number;
  d.wavelength_nm = p.wavelength_nm;
  d.psf_sigma_px = p.psf_sigma_px;
  d.laser_power_mw = p.laser_power_mw;
  d.sheet_waist_mm = p.sheet_waist_mm;
  d.sheet_focus_mm = p.sheet_focus_mm;
  d.sheet_m2 = p.sheet_m2;
  d.exposure_us = p.exposure_us;
  d.gain = p.gain;
  d.quantum_efficiency = p.quantum_efficiency;
  d.full_well_e = p.full_well_e;
  d.read_noise_e = p.read_noise_e;
  d.dark_offset_dn = p.dark_offset_dn;
  d.image_bits = p.image_bits;
  d.image_roi_first_row = p.image_roi_first_row;
  d.image_roi_rows = p.image_roi_rows;
  d.peak_threshold_dn = p.peak_threshold_dn;
  d.peak_window_px = p.peak_window_px;
  d.peak_method = p.peak_method;
  d.peak_policy = p.peak_policy;
}

std::vector<std::string> material_names() {
  std::vector<std::string> names;
  for (const auto& m : kMaterials) names.emplace_back(m.name);
  return names;
}

std::string material_description(std::string_view name) {
  for (const auto& m : kMaterials)
    if (m.name == name) return std::string(m.description);
  return {};
}

bool apply_material(ScannerDesc& d, std::string_view name) {
  for (const auto& m : kMaterials) {
    if (m.name != name) continue;
    d.material = std::string(m.name);
    d.speckle_px = m.speckle_px;
    d.reflectivity = m.reflectivity;
    d.shiny_cluster_prob = m.shiny_prob;
    d.shiny_cluster_max_points = m.shiny_max_points;
    d.shiny_offset_min_mm = m.shiny_min_mm;
    d.shiny_offset_max_mm = m.shiny_max_mm;
    d.rough_outlier_prob = m.rough_prob;
    d.rough_offset_min_mm = m.rough_min_mm;
    d.rough_offset_max_mm = m.rough_max_mm;
    d.dropout_prob_normal = m.drop_normal;
    d.dropout_prob_grazing = m.drop_grazing;
    d.specular_reflectance = m.specular;
    d.specular_lobe_deg = m.lobe_deg;
    d.speckle_contrast = m.speckle_contrast;
    return true;
  }
  return false;
}

std::string join_names(const std::vector<std::string>& names) {
  std::string s;
  for (const auto& n : names) s += (s.empty() ? "" : ", ") + n;
  return s;
}

}  // namespace vts
