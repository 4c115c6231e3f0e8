#pragma once
// The triangulation error model: turns an ideal geometric profile (what either
// profile source produces) into what the sensor would measure, from the
// scanner's camera geometry, measuring window and surface parameters.
// Equations and parameters: docs/SENSOR_MODEL.md.
//
// Camera geometry (sensor frame; ScannerDesc's camera fields). With b the
// baseline and theta the triangulation angle, the camera centre is
// c = (b, 0, b tan(theta)) and its axis w = (-sin(theta), 0, cos(theta)), so
// the laser origin lies in the camera's principal plane (c . w = 0). A lit point
// (0, y, z) of the laser plane then has camera depth z cos(theta) and projects
// to image row and column (pixels, from the principal point at the centre)
//   u = F tan(theta) - K / z,   v = F (y / z) / cos(theta),
// with F = focal_length / pixel_pitch (px) and K = F b / cos^2(theta) (mm px).
// Rows depend on z only, columns on the column ray's t = y / z only, so image
// column v is profile column t and a row step ds gives the depth step
//   dz = z^2 ds / K        (exactly quadratic in range).
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "sensor/profile.h"
#include "sensor/scanner.h"

namespace vts {

// The changing part of a run (MuJoCo's mjData to ScannerDesc's mjModel): the
// seed of every random draw, counters and scratch space. Draws are not taken
// from a stream: each is a hash of (seed, profile index, column, purpose), so
// the result does not depend on batching, threads or which source ran, and the
// same seed gives the same profile bit for bit.
struct ScanState {
  std::uint64_t seed = 0;

  // Counters over every profile passed through apply_error_model.
  std::int64_t profiles = 0;
  std::int64_t lit = 0;            // ideal valid columns (laser hit inside the depth of field)
  std::int64_t measured = 0;       // valid measured columns
  std::int64_t outside_roi = 0;    // lit but outside the image-processing region
  std::int64_t grazing = 0;        // lit beyond max_incidence_deg
  std::int64_t shadowed = 0;       // lit but hidden from the camera
  std::int64_t outside_image = 0;  // peak outside the camera image
  std::int64_t dropouts = 0;       // random dropouts
  std::int64_t shiny_outliers = 0; // measured points displaced by a reflection cluster
  std::int64_t rough_outliers = 0; // measured points displaced by a rough-surface outlier

  // Scratch, sized on first use (no allocation per profile afterwards).
  std::vector<float> cluster_offset_mm;  // per column, 0 = not in a cluster
  std::vector<double> column_tan;        // t_i of sensor/rays.h
  std::vector<double> column_secant;     // sqrt(1 + t_i^2)
  std::vector<std::uint64_t> column_keys;  // per purpose and column: the draws' column hash
  // One profile's draws per column: the dropout draw (first the reflection
  // clusters' start draw), the speckle noise in px, the rough outlier's hit,
  // size and sign draws; and the conditions found (error_model.cpp).
  std::vector<double> u_drop, noise_px, u_rough_hit, u_rough_size, u_rough_sign;
  std::vector<std::int32_t> flags;
  int cached_points = 0;
  double cached_fan_deg = 0.0;
};

// Adds part's counters to total's (for runs split over threads, each with
// its own ScanState); seed and scratch are left alone.
void add_counts(ScanState& total, const ScanState& part);

// The camera derived from a ScannerDesc (see the header comment).
struct CameraModel {
  Eigen::Vector3d centre_mm = Eigen::Vector3d::Zero();  // sensor frame
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();      // sensor frame, unit
  double f_px = 0.0;        // F: focal length in pixels
  double k_mm_px = 0.0;     // K = F b / cos^2(theta): z = K / (u_inf - u)
  double u_inf_px = 0.0;    // F tan(theta): row of z -> infinity, from the principal point
  double cos_theta = 1.0;
  double half_height_px = 0.0;  // image_height_px / 2
  double half_width_px = 0.0;   // image_width_px / 2
};
CameraModel camera_model(const ScannerDesc& desc);

// Image row (px from the principal point, along the triangulation direction)
// of a lit point at depth z_mm, and the depth that a row maps back to (<= 0
// when the row is at or beyond the vanishing row u_inf).
// Inline: the error model's per-column loop (cloned for AVX2 and AVX-512)
// calls them, and GCC does not inline an out-of-line function built for the
// baseline into a clone, so the loop would not vectorize.
inline double image_row_px(const CameraModel& cam, double z_mm) { return cam.u_inf_px - cam.k_mm_px / z_mm; }
inline double depth_of_row_mm(const CameraModel& cam, double row_px) {
  const double den = cam.u_inf_px - row_px;
  return den > 0.0 ? cam.k_mm_px / den : 0.0;
}

// Closed-form predictions of the model from the geometry alone (used by
// `vts sensors` and held against measurement by the tests):
// depth quantization step z^2 s / K for the sub-pixel step s,
double depth_step_mm(const ScannerDesc& desc, double z_mm);
// depth noise (std dev) z^2 sigma / K from the speckle sigma in px,
double depth_noise_mm(const ScannerDesc& desc, double z_mm);
// lateral point spacing z * 2 tan(fan/2) / points at the centre of the line,
double lateral_spacing_mm(const ScannerDesc& desc, double z_mm);
// the depth range [near, far] (mm) the image rows cover (far = infinity when
// the vanishing row lies inside the image),
Eigen::Vector2d image_depth_limits_mm(const ScannerDesc& desc);
// and whether the image is wide enough for every column of the fan.
bool image_covers_fan(const ScannerDesc& desc);

// Applies the error model to one ideal profile (a source's output, with its
// index set: the draws are keyed by ideal.index). For each column, in order:
// no ideal hit -> invalid; outside the image-processing region, beyond the
// incidence limit, in camera shadow, or outside the image columns -> invalid;
// random dropout (probability rising as sin^4 of the incidence) -> invalid; a shiny
// reflection cluster or rough-surface outlier moves the peak along the column
// ray; the peak's image row gets speckle noise, is quantized to the sub-pixel
// step and must fall inside the image; the row is triangulated back to (y, z)
// on the column ray. Intensity falls with range and incidence. `measured`
// gets pose, time and index of `ideal`, the measured points, intensity, the
// ideal points in true_*, and cos_incidence and camera_visible passed through.
// With desc.ideal the measured points are the ideal ones.
// No allocation once `measured` and `state` have been used with this size.
void apply_error_model(const ScannerDesc& desc, const Profile& ideal, ScanState& state,
                       Profile& measured);

// The distance (mm) within which an occluder next to the lit point does not
// count as camera shadow, in both sources: the shadow ray starts this far
// from the point.
inline constexpr double kShadowEpsilonMm = 0.01;

}  // namespace vts
