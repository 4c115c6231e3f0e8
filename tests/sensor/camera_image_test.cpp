// The camera image's geometry and radiometry against closed forms worked
// out here and in sensor/error_model.h's camera (u = F tan(theta) - K / z).
#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>

#include "sensor/camera_image.h"
#include "sensor/error_model.h"
#include "sensor/presets.h"

namespace {

constexpr double kPi = std::numbers::pi;

}  // namespace

TEST_CASE("a lit point images on the row and column of the triangulation formula", "[camera_image]") {
  for (const char* name : {"mspot", "lps-2048-short", "lps-1280-mid"}) {
    const vts::ScannerDesc d = *vts::sensor_preset(name);
    const vts::CameraGeometry cam = vts::camera_geometry(d);
    const double theta = d.triangulation_deg * kPi / 180.0;
    const double f = d.focal_length_mm / (d.pixel_pitch_um * 1e-3);
    const double k = f * d.baseline_mm / (std::cos(theta) * std::cos(theta));
    for (double z : {d.min_range_mm, 0.5 * (d.min_range_mm + d.max_range_mm), d.max_range_mm}) {
      for (double t : {-0.3, 0.0, 0.2}) {
        const double y = t * z;
        Eigen::Vector2d cr;
        REQUIRE(vts::project(cam, Eigen::Vector3d(0.0, y, z), cr));
        // Rows: u = F tan(theta) - K / z from the principal point (H - 1) / 2;
        // columns: v = F y / (z cos(theta)) from (W - 1) / 2.
        CHECK(cr.y() == Approx(0.5 * (d.image_height_px - 1) + f * std::tan(theta) - k / z).margin(1e-9));
        CHECK(cr.x() == Approx(0.5 * (d.image_width_px - 1) + f * y / (z * std::cos(theta))).margin(1e-9));
        Eigen::Vector2d yz;
        REQUIRE(vts::triangulate(cam, cr.x(), cr.y(), yz));
        CHECK(yz.x() == Approx(y).margin(1e-9));
        CHECK(yz.y() == Approx(z).margin(1e-9));
      }
    }
  }
}

TEST_CASE("with a Scheimpflug tilt, projection and triangulation invert each other", "[camera_image]") {
  vts::ScannerDesc d;
  d.scheimpflug_deg = 6.0;
  const vts::CameraGeometry cam = vts::camera_geometry(d);
  // The tilted image plane: a point's image is where its ray through the
  // centre meets the plane through the principal point turned by tau about
  // the v axis: worked out here by intersecting in camera coordinates.
  const double tau = 6.0 * kPi / 180.0;
  for (double z : {80.0, 200.0, 700.0}) {
    const Eigen::Vector3d p(0.0, 0.15 * z, z);
    const Eigen::Vector3d x = cam.camera_from_sensor * (p - cam.centre);
    // Plane: s (cos tau, 0, sin tau) + t (0, 1, 0) + (0, 0, F); ray: lambda x.
    Eigen::Matrix3d a;
    a.col(0) = Eigen::Vector3d(std::cos(tau), 0.0, std::sin(tau));
    a.col(1) = Eigen::Vector3d(0.0, 1.0, 0.0);
    a.col(2) = -x;
    const Eigen::Vector3d st = a.colPivHouseholderQr().solve(Eigen::Vector3d(0.0, 0.0, -cam.f_px));
    Eigen::Vector2d cr;
    REQUIRE(vts::project(cam, p, cr));
    CHECK(cr.y() == Approx(cam.cy + st.x()).margin(1e-6));
    CHECK(cr.x() == Approx(cam.cx + st.y()).margin(1e-6));
    Eigen::Vector2d yz;
    REQUIRE(vts::triangulate(cam, cr.x(), cr.y(), yz));
    CHECK(yz.x() == Approx(p.y()).margin(1e-6));
    CHECK(yz.y() == Approx(p.z()).margin(1e-6));
  }
}

TEST_CASE("the sheet widens as a Gaussian beam and the pixel counts photons by the camera equation",
          "[camera_image]") {
  vts::ScannerDesc d;
  d.sheet_waist_mm = 0.1;
  d.sheet_focus_mm = 200.0;
  d.sheet_m2 = 1.0;
  d.wavelength_nm = 660.0;
  // z_R = pi w0^2 / lambda = 47.6 mm: the thickness is sqrt(2) w0 there.
  const double z_r = kPi * 0.01 / 660e-6;
  CHECK(vts::sheet_half_thickness_mm(d, 200.0) == Approx(0.1));
  CHECK(vts::sheet_half_thickness_mm(d, 200.0 + z_r) == Approx(0.1 * std::sqrt(2.0)));
  // A radiance of 1 W/(mm^2 sr) through f/2.5 onto a 5.3 um pixel for 10 us
  // at 50 % quantum efficiency, by hand: E = pi / (4 * 6.25) W/mm^2,
  // times 2.809e-5 mm^2 times 1e-5 s = 3.530e-11 J; a 660 nm photon is
  // 3.0098e-19 J, so 1.1729e8 photons, 5.864e7 electrons.
  d.f_number = 2.5;
  d.exposure_us = 10.0;
  d.quantum_efficiency = 0.5;
  d.pixel_pitch_um = 5.3;
  CHECK(vts::electrons_per_radiance(d) == Approx(5.864e7).epsilon(1e-3));
  d.image_bits = 12;
  d.gain = 2.0;
  d.full_well_e = 8190.0;
  CHECK(vts::dn_per_electron(d) == Approx(1.0));
}
