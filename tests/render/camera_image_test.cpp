// The camera image (render/camera_renderer.h + sensor/camera_image.h) against
// the geometric error model, the radiometry worked out here and mirror
// geometry worked out here from the planes of a v-groove.
#include <catch2/catch.hpp>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "render/camera_renderer.h"
#include "sensor/camera_image.h"
#include "sensor/cell.h"
#include "sensor/error_model.h"
#include "sensor/mesh.h"
#include "sensor/presets.h"
#include "sensor/ray_scene.h"
#include "sensor/reference_source.h"
#include "tests/sensor/box_mesh.h"

namespace {

constexpr double kPi = std::numbers::pi;

void add_quad(vts::Mesh& m, const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
              const Eigen::Vector3d& d) {
  const auto base = static_cast<std::uint32_t>(m.vertices.size());
  for (const auto& p : {a, b, c, d}) m.vertices.push_back(p.cast<float>());
  m.triangles.push_back({base, base + 1, base + 2});
  m.triangles.push_back({base, base + 2, base + 3});
}

// A plate facing the sensor at depth z (sensor = world frame), tilted by
// `tilt` degrees about the travel axis (x), so that depth changes along the
// laser line.
vts::Mesh plate(double z, double tilt_deg = 0.0) {
  const double t = std::tan(tilt_deg * kPi / 180.0);
  const double h = 0.8 * z + 50.0;
  vts::Mesh m;
  add_quad(m, {-h, -h, z - h * t}, {h, -h, z - h * t}, {h, h, z + h * t}, {-h, h, z + h * t});
  return m;
}

// A v-groove along x with its root at depth z0 and walls `half_deg` from
// the optical axis, `depth` deep, plate tops beyond.
struct VGroove {
  double z0, half_deg, depth;
  double reach() const { return depth * std::tan(half_deg * kPi / 180.0); }
  vts::Mesh mesh() const {
    const double y = reach(), top = z0 - depth, x = 60.0, far = 80.0;
    vts::Mesh m;
    add_quad(m, {-x, -far, top}, {x, -far, top}, {x, -y, top}, {-x, -y, top});
    add_quad(m, {-x, -y, top}, {x, -y, top}, {x, 0, z0}, {-x, 0, z0});
    add_quad(m, {-x, 0, z0}, {x, 0, z0}, {x, y, top}, {-x, y, top});
    add_quad(m, {-x, y, top}, {x, y, top}, {x, far, top}, {-x, far, top});
    return m;
  }
  // Wall a (y < 0) or b (y > 0) as n . p = c with n facing the sensor.
  Eigen::Vector3d normal(bool wall_b) const {
    const double a = half_deg * kPi / 180.0;
    return Eigen::Vector3d(0.0, wall_b ? -std::cos(a) : std::cos(a), -std::sin(a));
  }
};

struct Shot {
  vts::Profile ideal, measured;
  vts::CameraImage image;
  vts::LaserPaths paths;
  vts::stripe::PeakResult peaks;
};

Shot shoot(const vts::ScannerDesc& d, const vts::Mesh& mesh, const vts::Pose& pose, std::int64_t index = 7) {
  Shot s;
  vts::ScannerDesc ideal_desc = d;
  auto reference = vts::make_reference_source(ideal_desc, mesh, 1);
  reference->scan(pose, s.ideal);
  s.ideal.index = index;
  vts::CameraRenderer renderer(d, mesh);
  vts::RayScene scene(mesh, "test");
  vts::RadianceImage rad;
  renderer.render(pose, rad);
  vts::trace_laser_paths(d, scene, pose, s.paths);
  vts::form_image(d, rad, s.paths, 11, index, s.image);
  vts::detect_stripe(d, s.image, s.peaks);
  vts::profile_from_peaks(d, s.image, s.peaks, s.ideal, s.measured);
  return s;
}

// Geometry only: no speckle, bounce, noise or outliers; a thin sheet
// focused at `focus`.
vts::ScannerDesc clean(double focus) {
  vts::ScannerDesc d;
  REQUIRE(vts::apply_material(d, "lambertian"));
  d.speckle_px = 0.0;
  d.speckle_contrast = 0.0;
  d.specular_reflectance = 0.0;
  d.image_noise = false;
  d.ambient_w_m2 = 0.0;
  d.sheet_waist_mm = 0.03;
  d.sheet_focus_mm = focus;
  d.max_incidence_deg = 89.0;
  return d;
}

void write_pgm(const std::string& path, const vts::CameraImage& im) {
  std::ofstream f(path, std::ios::binary);
  f << "P5\n" << im.width << " " << im.rows << "\n255\n";
  const double scale = 255.0 / (std::ldexp(1.0, im.bits) - 1.0);
  for (std::uint16_t v : im.pixels) f.put(static_cast<char>(static_cast<unsigned char>(std::min(255.0, v * scale))));
}

}  // namespace

TEST_CASE("without noise, bounce and speckle the image gives the geometric model's profile within the "
          "sub-pixel step",
          "[camera_image][gl]") {
  for (double z : {100.0, 300.0, 950.0}) {
    for (double tilt : {0.0, 25.0}) {
      vts::ScannerDesc d = clean(z);
      if (const char* m = std::getenv("VTS_METHOD")) d.peak_method = m;
      if (const char* m = std::getenv("VTS_WINDOW")) d.peak_window_px = std::atoi(m);
      // Bright enough to find, dark enough not to saturate, at every range.
      d.exposure_us = 0.5 * (z / 100.0) * (z / 100.0);
      const Shot s = shoot(d, plate(z, tilt), vts::Pose::Identity());
      // The geometric model on the same ideal profile, its draws all off.
      vts::ScannerDesc g = d;
      g.dropout_prob_normal = g.dropout_prob_grazing = 0.0;
      vts::ScanState state;
      vts::Profile geometric;
      vts::apply_error_model(g, s.ideal, state, geometric);
      // Both quantize the peak's row to the sub-pixel step; compare rows.
      const vts::CameraModel cam = vts::camera_model(d);
      const double step = d.subpixel_step_px;
      int both = 0, within = 0;
      double worst = 0.0;
      for (int i = 0; i < d.points; ++i) {
        if (!geometric.valid[i] || !s.measured.valid[i]) continue;
        ++both;
        const double drow = std::abs(vts::image_row_px(cam, s.measured.z_mm[i]) - vts::image_row_px(cam, geometric.z_mm[i]));
        worst = std::max(worst, drow);
        within += drow <= step * 1.001;
      }
      INFO("z " << z << " tilt " << tilt << ": " << within << " of " << both << " within the step " << step
                << " px, worst " << worst << " px");
      CHECK(both >= geometric.valid_count() * 98 / 100);
      CHECK(both >= d.points / 2);
      CHECK(within == both);
    }
  }
}

TEST_CASE("the stripe carries the sheet's power: integrated radiance across it is P cos(i) rho / (pi phi r)",
          "[camera_image][gl]") {
  // Across the stripe, sum of the laser radiance of a column times each
  // row's footprint on the plate (mm along x) integrates the sheet's
  // profile, whose integral is 1: P / (phi r) cos(i) rho / pi, cos^4 off axis.
  vts::ScannerDesc d = clean(200.0);
  d.reflectivity = 0.8;
  d.psf_sigma_px = 0.0;
  const double z = 200.0;
  const vts::Mesh mesh = plate(z);
  vts::CameraRenderer renderer(d, mesh);
  vts::RadianceImage rad;
  renderer.render(vts::Pose::Identity(), rad);
  // The stripe is traced on the CPU and added to the laser channel.
  vts::RayScene scene(mesh, "test");
  vts::LaserPaths paths;
  vts::trace_laser_paths(d, scene, vts::Pose::Identity(), paths);
  vts::add_stripe(paths, rad);
  const vts::CameraGeometry cam = vts::camera_geometry(d);
  for (double t : {-0.2, 0.0, 0.25}) {
    const Eigen::Vector3d p(0.0, t * z, z);
    Eigen::Vector2d cr, cr2;
    REQUIRE(vts::project(cam, p, cr));
    REQUIRE(vts::project(cam, p + Eigen::Vector3d(0.01, 0.0, 0.0), cr2));
    const double mm_per_row = 0.01 / std::abs(cr2.y() - cr.y());
    const int c = static_cast<int>(std::lround(cr.x()));
    double sum = 0.0;
    for (int k = 0; k < rad.rows; ++k) sum += rad.laser[static_cast<std::size_t>(k) * rad.width + c];
    const double r = p.norm();
    const Eigen::Vector3d v = (cam.centre - p).normalized();
    const double cos_off = cam.camera_from_sensor.row(2).dot(-v);
    const double expected = d.laser_power_mw * 1e-3 / (d.fan_deg * kPi / 180.0 * r) * (z / r) * d.reflectivity / kPi *
                            std::pow(cos_off, 4);
    CHECK(sum * mm_per_row == Approx(expected).epsilon(0.01));
  }
}

TEST_CASE("a shiny v-groove turned about the laser line shows the mirrored stripe where the planes put it",
          "[camera_image][gl]") {
  // Worked out here: each column's ray is mirrored by the wall it hits and
  // meets the other wall's plane; the camera sees that point.
  const VGroove v{110.0, std::getenv("VTS_HALF") ? std::atof(std::getenv("VTS_HALF")) : 35.0, 12.0};
  vts::ScannerDesc d;
  REQUIRE(vts::apply_material(d, "shiny-steel"));
  d.specular_reflectance = 0.9;
  d.reflectivity = 0.1;
  d.specular_lobe_deg = 0.5;
  d.speckle_px = 0.0;
  d.speckle_contrast = 0.0;
  const double pitch = (std::getenv("VTS_PITCH") ? std::atof(std::getenv("VTS_PITCH")) : 12.0) * kPi / 180.0;
  const vts::Pose pose(Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()));
  const Shot s = shoot(d, v.mesh(), pose);
  if (std::getenv("VTS_DUMP_IMAGES")) write_pgm("vgroove_bounce.pgm", s.image);
  const vts::CameraGeometry cam = vts::camera_geometry(d);
  const Eigen::Matrix3d rot = pose.linear();
  int predicted = 0, found = 0, bounce_brighter = 0, strongest_took_it = 0, continuous_kept_true = 0;
  for (int c = 0; c < cam.width; ++c) {
    // The ray through the laser plane that images in column c.
    Eigen::Vector2d yz;
    if (!vts::triangulate(cam, c, cam.cy, yz)) continue;
    const Eigen::Vector3d dir = rot * Eigen::Vector3d(0.0, yz.x() / yz.y(), 1.0).normalized();
    // First hit among the walls (the tops cannot mirror into the groove).
    for (bool b : {false, true}) {
      const Eigen::Vector3d n = v.normal(b);
      const double c0 = n.dot(Eigen::Vector3d(0.0, 0.0, v.z0));
      const double t = c0 / n.dot(dir);
      const Eigen::Vector3d p = t * dir;
      if (!(t > 0) || (b ? p.y() < 0 : p.y() > 0) || std::abs(p.y()) > v.reach()) continue;
      const Eigen::Vector3d m = dir - 2.0 * dir.dot(n) * n;
      const Eigen::Vector3d n2 = v.normal(!b);
      const double t2 = (c0 - n2.dot(p)) / n2.dot(m);
      const Eigen::Vector3d q = p + t2 * m;
      if (!(t2 > 0) || (b ? q.y() > 0 : q.y() < 0) || std::abs(q.y()) > v.reach()) continue;
      Eigen::Vector2d qi;
      if (!vts::project(cam, pose.inverse() * q, qi)) continue;
      const int qc = static_cast<int>(std::lround(qi.x()));
      if (qc < 0 || qc >= cam.width || !std::isfinite(s.paths.bounce_row[qc])) continue;
      ++predicted;
      if (std::abs(s.paths.bounce_row[qc] - qi.y()) > 1.0 + std::abs(qi.x() - qc) * 2.0) continue;
      ++found;
    }
  }
  INFO("predicted " << predicted << ", found " << found);
  CHECK(predicted >= 40);
  CHECK(found >= predicted * 9 / 10);

  // Where the image holds both the true stripe and a brighter mirrored one,
  // `strongest` takes the mirror and `continuous` keeps the stripe.
  vts::CameraImage image = s.image;
  vts::stripe::PeakResult strongest, continuous;
  vts::ScannerDesc ds = d, dc = d;
  ds.peak_policy = "strongest";
  dc.peak_policy = "continuous";
  vts::detect_stripe(ds, image, strongest);
  const std::vector<int> true_peak = image.true_peak, chosen_strongest = image.chosen_peak;
  vts::detect_stripe(dc, image, continuous);
  for (int c = 0; c < image.width; ++c) {
    if (true_peak[c] < 0 || strongest.count(c) < 2 || !std::isfinite(image.bounce_row[c])) continue;
    const int first = strongest.column_offset[c];
    const auto& t = strongest.peaks[first + true_peak[c]];
    bool brighter = false;
    for (int k = first; k < strongest.column_offset[c + 1]; ++k)
      if (k != first + true_peak[c] && std::abs(strongest.peaks[k].row + image.first_row - image.bounce_row[c]) < 2.0 &&
          strongest.peaks[k].peak_dn > t.peak_dn)
        brighter = true;
    if (!brighter) continue;
    ++bounce_brighter;
    strongest_took_it += chosen_strongest[c] != true_peak[c];
    continuous_kept_true += image.chosen_peak[c] == true_peak[c];
  }
  INFO("bounce brighter in " << bounce_brighter << " columns; strongest took it in " << strongest_took_it
                             << ", continuous kept the stripe in " << continuous_kept_true);
  CHECK(bounce_brighter >= 10);
  CHECK(strongest_took_it == bounce_brighter);
  CHECK(continuous_kept_true >= bounce_brighter * 9 / 10);
}

TEST_CASE("with speckle on, the image's profile is as noisy as the geometric model's speckle_px says",
          "[camera_image][gl]") {
  // A plate at 200 mm, tilted so the stripe crosses rows; sensor noise and
  // bounce off, exposure below saturation. The geometric model gets the
  // same ideal profiles and the same speckle_px.
  const double z = 200.0;
  vts::ScannerDesc d;
  d.exposure_us = 2.0;
  d.image_noise = false;
  d.specular_reflectance = 0.0;
  d.dropout_prob_normal = d.dropout_prob_grazing = 0.0;
  d.shiny_cluster_prob = d.rough_outlier_prob = 0.0;
  const vts::Mesh mesh = plate(z, 15.0);
  auto reference = vts::make_reference_source(d, mesh, 1);
  vts::CameraRenderer renderer(d, mesh);
  vts::RayScene scene(mesh, "test");
  const vts::CameraModel cam = vts::camera_model(d);
  vts::RadianceImage rad;
  vts::LaserPaths paths;
  vts::CameraImage image;
  vts::stripe::PeakResult peaks;
  vts::Profile ideal, measured, geometric;
  vts::ScanState state;
  double sum_image = 0.0, sum_geo = 0.0;
  int n_image = 0, n_geo = 0;
  for (int index = 0; index < 6; ++index) {
    const vts::Pose pose(Eigen::Translation3d(0.3 * index, 0.0, 0.0));
    reference->scan(pose, ideal);
    ideal.index = index;
    renderer.render(pose, rad);
    vts::trace_laser_paths(d, scene, pose, paths);
    vts::form_image(d, rad, paths, 5, index, image);
    vts::detect_stripe(d, image, peaks);
    vts::profile_from_peaks(d, image, peaks, ideal, measured);
    vts::apply_error_model(d, ideal, state, geometric);
    for (int i = 0; i < d.points; ++i) {
      if (!ideal.valid[i]) continue;
      const double truth = vts::image_row_px(cam, ideal.z_mm[i]);
      if (measured.valid[i]) {
        const double e = vts::image_row_px(cam, measured.z_mm[i]) - truth;
        sum_image += e * e;
        ++n_image;
      }
      if (geometric.valid[i]) {
        const double e = vts::image_row_px(cam, geometric.z_mm[i]) - truth;
        sum_geo += e * e;
        ++n_geo;
      }
    }
  }
  REQUIRE(n_image > 2500);
  REQUIRE(n_geo > 2500);
  const double rms_image = std::sqrt(sum_image / n_image), rms_geo = std::sqrt(sum_geo / n_geo);
  INFO("row error rms: image " << rms_image << " px, geometric model " << rms_geo << " px");
  CHECK(rms_image == Approx(rms_geo).epsilon(0.2));
}

TEST_CASE("the camera sees the stripe on one wall mirrored in the other where the wall planes put it",
          "[camera_image][gl]") {
  // Worked out here: the lit point P of each column on wall a (the laser
  // plane cuts it along a line) mirrored by wall b's plane is P'; the camera
  // sees P' through wall b where the line from the camera centre to P'
  // crosses that plane inside the wall. Its image is P' projected.
  const VGroove v{110.0, 35.0, 12.0};
  vts::ScannerDesc d;
  REQUIRE(vts::apply_material(d, "shiny-steel"));
  d.speckle_px = 0.0;
  d.speckle_contrast = 0.0;
  const vts::Pose pose = vts::Pose::Identity();
  const Shot s = shoot(d, v.mesh(), pose);
  const vts::CameraGeometry cam = vts::camera_geometry(d);
  int predicted = 0, found = 0;
  double worst = 0.0;
  for (int c = 0; c < cam.width; ++c) {
    Eigen::Vector2d yz;
    if (!vts::triangulate(cam, c, cam.cy, yz)) continue;
    const Eigen::Vector3d dir = Eigen::Vector3d(0.0, yz.x() / yz.y(), 1.0).normalized();
    for (bool a_is_b : {false, true}) {
      const Eigen::Vector3d na = v.normal(a_is_b), nb = v.normal(!a_is_b);
      const double c0 = na.dot(Eigen::Vector3d(0.0, 0.0, v.z0));  // both planes pass through the root
      const double t = c0 / na.dot(dir);
      const Eigen::Vector3d p = t * dir;
      if (!(t > 0) || (a_is_b ? p.y() < 0 : p.y() > 0) || std::abs(p.y()) > v.reach()) continue;
      const Eigen::Vector3d pv = p - 2.0 * (nb.dot(p) - c0) * nb;
      const Eigen::Vector3d ray = (pv - cam.centre).normalized();
      const double tq = (c0 - nb.dot(cam.centre)) / nb.dot(ray);
      const Eigen::Vector3d q = cam.centre + tq * ray;
      // Inside wall b, not at its very ends (the image's resampling joins
      // neighbouring columns only), and lit from P unoccluded (the walls
      // face each other: nothing lies between).
      if (!(tq > 0) || (a_is_b ? q.y() > -0.3 : q.y() < 0.3) || std::abs(q.y()) > v.reach() - 0.3) continue;
      Eigen::Vector2d qi;
      if (!vts::project(cam, pv, qi)) continue;
      const int qc = static_cast<int>(std::lround(qi.x()));
      if (qc < 0 || qc >= cam.width) continue;
      ++predicted;
      const float row = s.paths.mirror_row[static_cast<std::size_t>(qc)];
      if (!std::isfinite(row)) continue;
      const double err = std::abs(row - qi.y()) - std::abs(qi.x() - qc) * 2.0;
      worst = std::max(worst, err);
      found += err < 0.5;
    }
  }
  INFO("predicted " << predicted << ", found " << found << ", worst " << worst << " px");
  CHECK(predicted >= 100);
  CHECK(found >= predicted * 95 / 100);
}

TEST_CASE("a shiny thick v-groove at the default exposure looks like a welding sensor's image of one",
          "[camera_image][gl]") {
  // Issue 22's figures from real 8-bit images of thick-plate grooves, per
  // lit column: stripe saturated in 80-100 % of columns, width at half
  // maximum 3-9 px where not saturated, background 0-2 DN with 1.5-3 DN
  // noise, two or more separated peaks in 11-33 %. Measured here on the
  // built-in vgroove-thick (40 mm plate, 60 degrees, beads laid) in
  // shiny steel, every statistic worked out in this test from the pixels.
  auto cell = vts::builtin_cell("vgroove-thick");
  REQUIRE(cell);
  vts::ScannerDesc d = cell->scanner;
  REQUIRE(vts::apply_material(d, "shiny-steel"));
  REQUIRE(d.image_bits == 8);
  const vts::Mesh mesh = cell->mesh();
  vts::CameraRenderer renderer(d, mesh);
  vts::RayScene scene(mesh, "test");
  const int full = 255, threshold = 16;  // the detector's default threshold, full scale / 16
  int lit = 0, saturated = 0, multi = 0;
  std::vector<int> widths;
  double bg_sum = 0.0, bg_sq = 0.0;
  long bg_n = 0;
  for (int i = 0; i < 5; ++i) {
    const vts::Pose pose = cell->path.pose_at(i * 10);
    vts::RadianceImage rad;
    vts::LaserPaths paths;
    vts::CameraImage im;
    renderer.render(pose, rad);
    vts::trace_laser_paths(d, scene, pose, paths);
    vts::form_image(d, rad, paths, 3, i, im);
    const auto px = [&](int c, int k) { return static_cast<int>(im.pixels[static_cast<std::size_t>(k) * im.width + c]); };
    for (int c = 0; c < im.width; ++c) {
      // Background: pixels more than 40 rows from any labelled light.
      const auto far_from = [&](float row, int k) { return !std::isfinite(row) || std::abs(k + im.first_row - row) > 40.0f; };
      for (int k = 0; k < im.rows; k += 3)
        if (far_from(im.true_row[c], k) && far_from(im.bounce_row[c], k) && far_from(im.mirror_row[c], k)) {
          bg_sum += px(c, k);
          bg_sq += px(c, k) * px(c, k);
          ++bg_n;
        }
      if (!std::isfinite(im.true_row[c])) continue;
      ++lit;
      int top = 0, at = 0;
      for (int k = 0; k < im.rows; ++k)
        if (px(c, k) > top) top = px(c, k), at = k;
      if (top >= full) {
        ++saturated;
      } else {
        int lo = at, hi = at;
        while (lo > 0 && 2 * px(c, lo - 1) >= top) --lo;
        while (hi + 1 < im.rows && 2 * px(c, hi + 1) >= top) ++hi;
        widths.push_back(hi - lo + 1);
      }
      // Separated peaks: runs above the threshold at least 3 rows apart.
      int runs = 0, gap = 1 << 20;
      for (int k = 0; k < im.rows; ++k) {
        if (px(c, k) >= threshold) {
          runs += gap >= 3;
          gap = 0;
        } else {
          ++gap;
        }
      }
      multi += runs >= 2;
    }
  }
  REQUIRE(lit > 1000);
  std::nth_element(widths.begin(), widths.begin() + static_cast<std::ptrdiff_t>(widths.size() / 2), widths.end());
  const double sat_share = 100.0 * saturated / lit, multi_share = 100.0 * multi / lit;
  const double bg_mean = bg_sum / static_cast<double>(bg_n);
  const double bg_sd = std::sqrt(bg_sq / static_cast<double>(bg_n) - bg_mean * bg_mean);
  const int width = widths.empty() ? 0 : widths[widths.size() / 2];
  INFO("lit columns " << lit << ": saturated " << sat_share << " %, unsaturated width " << width
                      << " px, background " << bg_mean << " / " << bg_sd << " DN, two or more peaks " << multi_share
                      << " %");
  CHECK(sat_share >= 80.0);
  CHECK(width >= 3);
  CHECK(width <= 9);
  CHECK(bg_mean <= 2.0);
  CHECK(bg_sd >= 1.5);
  CHECK(bg_sd <= 3.0);
  CHECK(multi_share >= 11.0);
  CHECK(multi_share <= 33.0);
}

namespace {

// The ray of pixel (column, row) in the sensor frame, from the camera
// centre: the projection's inverse in camera coordinates,
// (u cos(tau), v, f + u sin(tau)) with u = row - cy, v = column - cx. Checked
// against vts::project by the caller.
Eigen::Vector3d pixel_ray(const vts::CameraGeometry& cam, double column, double row) {
  const double u = row - cam.cy, v = column - cam.cx;
  return (cam.camera_from_sensor.transpose() *
          Eigen::Vector3d(u * cam.cos_tilt, v, cam.f_px + u * cam.sin_tilt)).normalized();
}

// The built-in v-groove cell's scanner in the camera-image mode, with more
// ambient light than its default.
vts::ScannerDesc ambient_scanner(const vts::Cell& cell) {
  vts::ScannerDesc d = cell.scanner;
  d.camera_image = true;
  d.ambient_w_m2 = 2.0;
  return d;
}

struct AmbientCheck {
  long seen_both = 0, dark_both = 0, edge = 0, wrong = 0;
  double worst_rel = 0.0;
};

// Every `step`-th pixel of the rendered ambient light against the ray-cast
// reference: where the pixel's ray meets the part, E rho / pi cos^4 of the
// ray's angle off the axis (from the hit point); nothing where it does not.
// A pixel that disagrees is an edge if one of its four neighbours' rays
// disagrees with its own (the rasterizer and the ray see the edge a pixel
// apart at most).
AmbientCheck check_ambient(const vts::ScannerDesc& d, const vts::Mesh& mesh, const vts::Pose& pose, int step) {
  const vts::CameraGeometry cam = vts::camera_geometry(d);
  vts::CameraRenderer renderer(d, mesh);
  vts::RadianceImage rad;
  renderer.render(pose, rad);
  REQUIRE(rad.ambient.size() == static_cast<std::size_t>(rad.width) * rad.rows);
  vts::RayScene scene(mesh, "test");
  const Eigen::Vector3d centre_world = pose * cam.centre;
  const Eigen::Vector3d axis = cam.camera_from_sensor.row(2).transpose();
  const auto hits = [&](double c, double r, Eigen::Vector3d* p_sensor) {
    const Eigen::Vector3d dir = pixel_ray(cam, c, r);
    Eigen::Vector2d back;
    REQUIRE(vts::project(cam, cam.centre + 100.0 * dir, back));
    REQUIRE(std::abs(back.x() - c) < 1e-6);
    REQUIRE(std::abs(back.y() - r) < 1e-6);
    vts::RayScene::Hit hit;
    const bool found = scene.intersect(centre_world.cast<float>(), (pose.linear() * dir).cast<float>(), 1.0f, 1e5f, hit);
    if (found && p_sensor) *p_sensor = cam.centre + static_cast<double>(hit.t) * dir;
    return found;
  };
  const double e_rho = d.ambient_w_m2 * 1e-6 * d.reflectivity / kPi;
  AmbientCheck out;
  for (int k = 0; k < rad.rows; k += step)
    for (int c = 0; c < rad.width; c += step) {
      const int r = rad.first_row + k;
      Eigen::Vector3d p;
      const bool ray = hits(c, r, &p);
      const float got = rad.ambient[static_cast<std::size_t>(k) * rad.width + c];
      if (ray == (got > 0.0f)) {
        if (!ray) {
          ++out.dark_both;
          continue;
        }
        ++out.seen_both;
        const double cos_off = axis.dot((p - cam.centre).normalized());
        const double want = e_rho * std::pow(cos_off, 4);
        out.worst_rel = std::max(out.worst_rel, std::abs(got - want) / want);
        continue;
      }
      bool edge = false;
      for (const auto& [dc, dr] : {std::pair{1, 0}, std::pair{-1, 0}, std::pair{0, 1}, std::pair{0, -1}})
        edge = edge || hits(c + dc, r + dr, nullptr) != ray;
      ++(edge ? out.edge : out.wrong);
    }
  return out;
}

}  // namespace

TEST_CASE("the ambient light is E rho / pi cos^4 wherever the ray-cast reference sees the part, and none "
          "elsewhere",
          "[camera_image][gl]") {
  auto cell = vts::builtin_cell("vgroove");
  REQUIRE(cell);
  vts::ScannerDesc d = ambient_scanner(*cell);
  vts::Mesh mesh = cell->mesh();
  vts::Pose pose = cell->path.pose_at(50);
  int step = 9;
  long min_dark = 100;  // the full frame's edges look past the plates
  SECTION("the v-groove cell, closed solids (faces away from the camera culled), full frame") {
    REQUIRE(vts::mesh_orientation(mesh) == vts::MeshOrientation::Outward);
  }
  SECTION("the same with a 64-row region of interest and the sensor turned") {
    d.image_roi_first_row = 600;
    d.image_roi_rows = 64;
    pose = cell->path.pose_at(20) * Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitY());
    step = 2;
    min_dark = 0;
  }
  SECTION("an open strip (nothing culled), edges in view") {
    mesh = vts::Mesh{};
    add_quad(mesh, {-20, -15, 110}, {20, -15, 110}, {20, 10, 95}, {-20, 10, 95});
    REQUIRE(vts::mesh_orientation(mesh) == vts::MeshOrientation::Open);
    pose = vts::Pose::Identity();
    step = 7;
    min_dark = 3000;
  }
  const AmbientCheck a = check_ambient(d, mesh, pose, step);
  INFO("seen " << a.seen_both << ", dark " << a.dark_both << ", edge " << a.edge << ", wrong " << a.wrong
               << ", worst " << a.worst_rel);
  CHECK(a.seen_both > 3000);
  CHECK(a.dark_both >= min_dark);
  CHECK(a.wrong == 0);
  CHECK(a.edge <= a.seen_both / 100);
  CHECK(a.worst_rel < 1e-5);
}

TEST_CASE("a closed part is seen by its faces toward the camera even where its back lies beyond the far plane",
          "[camera_image][gl]") {
  // A box from 100 mm to 100 m deep (sensor frame = world): its front face
  // fills the image; its back face is far beyond the renderer's far plane.
  // Culling the faces toward the camera instead of those away would leave
  // the side walls' insides, which leave a hole where the back face would
  // be (about a tenth of the image).
  auto cell = vts::builtin_cell("vgroove");
  REQUIRE(cell);
  const vts::ScannerDesc d = ambient_scanner(*cell);
  const vts::CameraGeometry cam = vts::camera_geometry(d);
  const float h = 400.0f, z0 = 100.0f, z1 = 1e5f;
  const vts::Mesh solid = vts::test::box({-h, -h, z0}, {h, h, z1});
  for (const bool inward : {false, true}) {
    const vts::Mesh m = inward ? vts::test::flipped(solid) : solid;
    REQUIRE(vts::mesh_orientation(m) == (inward ? vts::MeshOrientation::Inward : vts::MeshOrientation::Outward));
    vts::CameraRenderer renderer(d, m);
    vts::RadianceImage rad;
    renderer.render(vts::Pose::Identity(), rad);
    // Every 8th pixel; each one's ray meets the front face.
    int seen = 0, checked = 0;
    for (int r = 0; r < cam.height; r += 8)
      for (int c = 0; c < cam.width; c += 8) {
        const Eigen::Vector3d dir = pixel_ray(cam, c, r);
        const double t = (z0 - cam.centre.z()) / dir.z();
        const Eigen::Vector3d p = cam.centre + t * dir;
        REQUIRE(std::abs(p.x()) < h);
        REQUIRE(std::abs(p.y()) < h);
        ++checked;
        seen += rad.ambient[static_cast<std::size_t>(r - rad.first_row) * rad.width + c] > 0.0f;
      }
    INFO((inward ? "inward" : "outward") << ": " << seen << " of " << checked);
    CHECK(seen == checked);
  }
}
