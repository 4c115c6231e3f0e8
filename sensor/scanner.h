#pragma once
// The scanner description: fixed for a run (MuJoCo's mjModel to ScanState's
// mjData, sensor/error_model.h). Sensor frame: origin at the laser, z along the
// optical axis (range), y along the laser line, x = y cross z (the travel
// direction). The laser plane is the sensor's y-z plane (x = 0).
//
// The defaults are the `mspot` preset (sensor/presets.h): the paper's M-Spot-like
// sensor with a matte steel surface. docs/SENSOR_MODEL.md gives every field's
// role in the equations.
#include <string>

#include "sensor/pose.h"

namespace vts {

inline constexpr int kMinPoints = 16;
inline constexpr int kMaxPoints = 4096;

struct ScannerDesc {
  std::string name = "mspot";   // preset name, informational

  // Laser and profile.
  double fan_deg = 40.0;        // full opening angle of the laser fan, in the y-z plane
  int points = 512;             // columns per profile, 16..4096
  double rate_hz = 20.0;        // profile rate
  // Where the laser (sensor frame) sits on the torch: tool_from_laser.
  Pose tool_from_laser = Pose::Identity();

  // Measuring window. The sources apply the depth of field and the maximum hit
  // distance to the ideal profile; the error model applies the rest.
  double min_range_mm = 40.0;   // depth of field: nearest measurable z
  double max_range_mm = 1000.0; // depth of field: farthest measurable z
  double max_hit_mm = 1200.0;   // longest ray distance that counts as a hit
  int roi_first_column = 0;     // image-processing region ("boundary size"): first
  int roi_last_column = kMaxPoints - 1;  // and last column kept (clamped to points - 1)
  double max_incidence_deg = 80.0;  // laser incidence (ray to surface normal) beyond
                                    // which the return is lost (grazing)

  // Camera (pinhole). Its centre is at (baseline_mm, 0, baseline_mm *
  // tan(triangulation_deg)) in the sensor frame and its optical axis
  // (-sin, 0, cos)(triangulation_deg) points back across the laser plane, so
  // the laser origin lies in the camera's principal plane. Image rows (u) run
  // along the triangulation direction (range), image columns (v) along the
  // laser line; the principal point is the image centre.
  double baseline_mm = 24.4549;         // camera centre's distance from the laser plane (x)
  double triangulation_deg = 19.7407;   // camera axis tilt from the laser's z axis
  double focal_length_mm = 8.0;
  double pixel_pitch_um = 5.3;          // square pixels
  int image_width_px = 1280;            // along the laser line (v)
  int image_height_px = 1024;           // along the triangulation direction (u)
  double subpixel_step_px = 0.0625;     // peak detector resolution (1/16 px)
  double intensity_ref_range_mm = 200.0;  // range at which a white (reflectivity 1)
                                          // surface at normal incidence gives intensity 1

  // Surface (one material for the whole scene; presets in sensor/presets.h).
  std::string material = "matte-steel";  // material preset name, informational
  double speckle_px = 0.1;              // std dev of the peak position (speckle), px
  double reflectivity = 0.5;            // diffuse reflectance, 0..1 (scales intensity)
  double shiny_cluster_prob = 0.0005;   // per column: a reflection cluster starts here
  int shiny_cluster_max_points = 4;     // cluster length uniform in 1..this, columns
  double shiny_offset_min_mm = 0.5;     // cluster displacement along the ray, |mm|,
  double shiny_offset_max_mm = 3.0;     // uniform in [min, max], either sign
  double rough_outlier_prob = 0.0002;   // per column: an isolated rough-surface outlier
  double rough_offset_min_mm = 0.1;     // its displacement along the ray, |mm|,
  double rough_offset_max_mm = 0.5;     // uniform in [min, max], either sign
  double dropout_prob_normal = 0.001;   // dropout probability at normal incidence,
  double dropout_prob_grazing = 0.05;   // rising as sin^4(incidence) to this at 90 deg

  // Camera image (the third mode, `vts scan --camera-image`; sensor/camera_image.h,
  // docs/SENSOR_MODEL.md "The camera image"): the camera's view of the part lit
  // by the laser sheet, rendered, then the stripe's peak found per image column.
  double scheimpflug_deg = 0.0;     // image plane tilt about the image's v axis (0: none)
  double f_number = 2.5;            // lens aperture N (speckle grain, image irradiance)
  double wavelength_nm = 660.0;     // laser wavelength
  double psf_sigma_px = 1.2;        // lens blur, Gaussian std dev across the stripe, px
  double laser_power_mw = 20.0;     // optical power in the fan
  double sheet_waist_mm = 0.1;      // sheet's 1/e^2 half thickness at its waist
  double sheet_focus_mm = 200.0;    // range of the waist
  double sheet_m2 = 1.3;            // beam quality M^2: divergence M^2 lambda / (pi waist)
  double exposure_us = 20.0;        // exposure time
  double gain = 4.0;                // DN per electron = gain (2^bits - 1) / full_well_e
  double quantum_efficiency = 0.5;  // electrons per photon at the laser wavelength
  double full_well_e = 10000.0;     // electrons at which the pixel saturates (gain 1)
  double read_noise_e = 20.0;       // read noise, electrons rms
  double dark_offset_dn = 1.0;      // black level, DN
  double ambient_w_m2 = 0.5;        // ambient irradiance on the part inside the filter band
  int image_bits = 8;               // 8, 10, 12 or 16
  int image_roi_first_row = 0;      // region of interest: first image row read out
  int image_roi_rows = 0;           // and how many (0: the full frame)
  bool image_noise = true;          // shot and read noise (off: each pixel's expected value)
  double specular_reflectance = 0.05;  // surface: the specular lobe's share of the light (matte-steel's)
  double specular_lobe_deg = 8.0;      // surface: the lobe's std dev around the mirror direction
  double speckle_contrast = 0.5;      // surface: std/mean of the stripe's brightness per grain
  // The peak detector (stripe/peaks.h) that turns each image into a profile.
  double peak_threshold_dn = 0.0;   // DN a stripe pixel must exceed (0: full scale / 16)
  int peak_window_px = 4;           // half width of the sub-pixel fit window
  std::string peak_method = "cog";  // sub-pixel method: cog, gaussian, parabolic
  std::string peak_policy = "continuous";  // several peaks: strongest, first, last, widest, continuous

  // Error model off: profiles are the ideal geometric ones (`vts scan --ideal`).
  bool ideal = false;
  // Profiles from the camera image instead of the error model (`--camera-image`).
  bool camera_image = false;
};

// Empty when the description is usable, else a message naming the first bad
// field and its value, e.g. "points = 8: must be between 16 and 4096".
std::string validate(const ScannerDesc& desc);

}  // namespace vts
