#pragma once
// The camera image: the physics of the third mode (`vts scan --camera-image`).
// render/camera_renderer.h draws the part as the sensor's camera sees it in
// the ambient light (radiance per pixel, W/(mm^2 sr)); this file holds
// everything else, free of GL: the camera's projection with an optional
// Scheimpflug tilt and its inverse onto the laser plane, the sheet's
// thickness along its range, the stripe itself and one bounce of laser
// light off a specular surface (cast with Embree), the lens blur, speckle, the sensor's
// electrons, shot and read noise, saturation and quantization, the per-column
// truth (where the ideal point's image falls), and the profile triangulated
// from the peaks the detector finds (stripe/peaks.h). docs/SENSOR_MODEL.md,
// "The camera image", gives every formula and its source.
//
// Image coordinates: column c along the laser line (v), row r along the
// triangulation direction (u); the centre of pixel (c, r) is at (c, r), so a
// pixel covers [c - 0.5, c + 0.5] x [r - 0.5, r + 0.5] and the principal point
// is ((W - 1) / 2, (H - 1) / 2). Without tilt, u = F tan(theta) - K / z for a
// lit point at depth z (sensor/error_model.h's CameraModel).
#include <cstdint>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "sensor/pose.h"
#include "sensor/profile.h"
#include "sensor/scanner.h"
#include "stripe/peaks.h"

namespace vts {

class RayScene;

// The camera of a scanner description, with its Scheimpflug tilt: a point X
// in camera coordinates (x along u, y along v, z along the optical axis,
// from the camera centre) images at
//   u = F x / (z cos(tau) - x sin(tau)),  v = F cos(tau) y / (z cos(tau) - x sin(tau))
// (the pinhole ray meeting an image plane turned by tau about the v axis).
struct CameraGeometry {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();  // sensor frame, mm
  Eigen::Matrix3d camera_from_sensor = Eigen::Matrix3d::Identity();  // rows: e_u, e_v, axis
  double f_px = 0.0;
  double cos_tilt = 1.0, sin_tilt = 0.0;
  double cx = 0.0, cy = 0.0;  // principal point, pixel coordinates
  int width = 0, height = 0;
};
CameraGeometry camera_geometry(const ScannerDesc& desc);

// Pixel coordinates (column, row) of a point in the sensor frame; false when
// it lies behind the camera.
bool project(const CameraGeometry& cam, const Eigen::Vector3d& p_sensor, Eigen::Vector2d& col_row);
// The point of the laser plane (sensor x = 0) that images at (column, row):
// (y, z) in the sensor frame; false when the pixel's ray does not meet the
// plane in front of the camera.
bool triangulate(const CameraGeometry& cam, double column, double row, Eigen::Vector2d& yz);

// The ambient light's radiance toward the camera (W/(mm^2 sr)) in pixel
// (column, row) where that pixel sees a surface: E_amb rho_d / pi (the
// ambient irradiance in the filter band, reflected diffusely) times cos^4 of
// the pixel ray's angle off the camera's axis (the camera equation's
// fall-off, as for the laser light). The same on every surface (one
// reflectivity per scene), so render/camera_renderer.h draws only which
// pixels see a surface.
double ambient_radiance(const ScannerDesc& desc, const CameraGeometry& cam, double column, double row);

// The sheet's 1/e^2 half thickness at range r (mm): a Gaussian beam of waist
// w0 at sheet_focus_mm with quality M^2,
//   w(r) = w0 sqrt(1 + ((r - r_f) / z_R)^2),  z_R = pi w0^2 / (M^2 lambda).
double sheet_half_thickness_mm(const ScannerDesc& desc, double range_mm);
// z_R = pi w0^2 / (M^2 lambda), mm: the renderer's shader takes it as is.
double sheet_rayleigh_mm(const ScannerDesc& desc);

// Electrons per unit image radiance (W/(mm^2 sr)) in one pixel during one
// exposure: the camera equation E = L pi / (4 N^2) times the pixel area, the
// exposure, the quantum efficiency, over the photon energy h c / lambda.
double electrons_per_radiance(const ScannerDesc& desc);
// DN per electron: gain (2^bits - 1) / full_well_e.
double dn_per_electron(const ScannerDesc& desc);

// The radiance of the region of interest, rows first_row ..
// first_row + rows - 1, row-major (row k of the buffers is image row
// first_row + k): laser light (coherent: speckle applies; the renderer
// leaves it at zero, add_stripe adds a LaserPaths' stripe to it; form_image
// uses it as scratch, without reading it) and ambient light (the
// renderer's).
struct RadianceImage {
  int width = 0, rows = 0, first_row = 0;
  std::vector<float> laser, ambient;  // W/(mm^2 sr), width * rows each
  void resize(int w, int r, int first);
};

// The rows read out for a description: (first row, row count).
std::pair<int, int> image_roi(const ScannerDesc& desc);

// What the camera records, with its labels: the image in DN (bits per
// pixel as the description says, in 16-bit words), and per image column the
// true stripe centre (the row where the ideal lit point of that column
// images; NaN where no lit point is seen there) and the bounce's centre
// (NaN where none).
struct CameraImage {
  int width = 0, rows = 0, first_row = 0, bits = 8;
  std::vector<std::uint16_t> pixels;  // width * rows
  std::vector<float> true_row;        // per column
  std::vector<float> bounce_row;      // per column
  std::vector<float> mirror_row;      // per column: the stripe seen in a mirror (NaN if none)
  std::int64_t index = 0;             // the profile's index
  // Set by detect_stripe: per column, which of the column's peaks (0 =
  // lowest row) is the true stripe (nearest true_row, within half its width
  // and at least 1.5 px) and which the detector chose; -1 for none.
  std::vector<int> true_peak, chosen_peak;
  std::vector<float> chosen_row;  // the chosen peak's row, full-image coordinates (NaN: none)
  std::vector<int> peak_count;    // peaks the detector found in the column
};

// Per image column, the primary laser hit seen in that column and the
// laser's one bounce: computed with Embree for one pose.
struct LaserPaths {
  std::vector<float> true_row;     // per image column, NaN when not lit or not seen
  std::vector<float> bounce_row;   // per image column: the bounce's image row, NaN if none
  std::vector<float> bounce_sigma; // its std dev across the stripe, px
  std::vector<float> bounce_radiance;  // its peak radiance, W/(mm^2 sr)
  // The camera-side mirror: the lit line of one surface seen mirrored in
  // another lit plane (the brightest where several are).
  std::vector<float> mirror_row, mirror_sigma, mirror_radiance;
  // The stripe itself, the laser light on the surfaces it reaches as the
  // camera sees them (W/(mm^2 sr)), in the region of interest: column c has
  // rows stripe_first_row[c] .. (full-image rows), its values
  // stripe_radiance[stripe_offset[c] .. stripe_offset[c + 1]).
  std::vector<int> stripe_offset, stripe_first_row;
  std::vector<float> stripe_radiance;
};
// Casts one ray per image column through the laser plane (the column's
// direction at the depth of field's middle), finds where it is seen in the
// image, the stripe's radiance in that column's pixels (the sheet on the
// surface the ray hits; pixel by pixel where the surface or its light
// changes across the band) and, when the surface has a specular share, where its mirror
// reflection lands and how bright it is there, and where the camera sees
// the lit line mirrored in one of the planes it lights (docs/SENSOR_MODEL.md,
// "One bounce" and "The stripe in a mirror"). Mirrors are the planes of runs
// of at least 3 consecutive primary hits (a curved mirror is not traced).
void trace_laser_paths(const ScannerDesc& desc, const RayScene& scene, const Pose& world_from_sensor,
                       LaserPaths& out);

// Adds the stripe of `paths` (trace_laser_paths) to the laser radiance of
// the region of interest.
void add_stripe(const LaserPaths& paths, RadianceImage& radiance);

// Turns rendered radiance into the recorded image: to the ambient light adds
// the laser light of `paths`, the stripe (as add_stripe would) and the
// bounce and the mirror image (blurred by the lens; the stripe's blur is in
// its profile), applies speckle (an amplitude and a shift of the stripe per
// image column, correlated over the speckle grain), converts to electrons,
// adds shot and read noise, saturates and quantizes. Draws are keyed by
// (seed, index): the same profile gives the same image. `radiance.laser` is
// not read: it is overwritten as scratch.
void form_image(const ScannerDesc& desc, RadianceImage& radiance, const LaserPaths& paths,
                std::uint64_t seed, std::int64_t index, CameraImage& out);

// The detector's parameters of a description (peak_* fields; a threshold
// of 0 is the detector's default, full scale / 16). Throws
// std::invalid_argument naming the field for an unknown method or policy.
stripe::PeakParams peak_params(const ScannerDesc& desc);

// Runs the description's peak detector over the image into `peaks` (rows
// relative to the region of interest: add image.first_row) and labels the
// image's columns (true_peak, chosen_peak).
void detect_stripe(const ScannerDesc& desc, CameraImage& image, stripe::PeakResult& peaks);

// The profile from the detected peaks: per profile column, its ray's image
// column (iterated with the tilt), the chosen peaks' rows interpolated there
// between neighbouring columns that continue each other, quantized to the
// sub-pixel step and triangulated onto the laser plane. `ideal` supplies
// pose, time, index, the truth and the incidence; intensity is the peak's
// value over full scale. Columns whose point falls outside the depth of
// field, the image-processing region or the image are invalid.
void profile_from_peaks(const ScannerDesc& desc, const CameraImage& image, const stripe::PeakResult& peaks,
                        const Profile& ideal, Profile& measured);

}  // namespace vts
