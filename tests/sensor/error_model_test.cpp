// The triangulation error model (sensor/error_model.h) measured on ideal
// profiles built here from analytic geometry: a plane at a known distance and
// tilt. Every expectation is computed in this file from the camera's figures
// (focal length, pixel pitch, baseline, triangulation angle), not read back
// from the model's own prediction functions, except where the test is that
// the two agree.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <set>
#include <vector>

#include "sensor/error_model.h"
#include "sensor/presets.h"
#include "sensor/rays.h"

using namespace vts;

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// The ideal profile of the plane z' = z0 + y' * tan(tilt) (sensor frame;
// tilt 0: square to the optical axis) as a source would produce it.
Profile plane_profile(const ScannerDesc& d, double z0, double tilt_deg, std::int64_t index) {
  Profile p;
  p.resize(d.points);
  p.index = index;
  const double k = std::tan(tilt_deg * kDeg);
  // Plane normal (0, -k, 1) / |.|.
  const double nn = std::sqrt(1.0 + k * k);
  for (int i = 0; i < d.points; ++i) {
    const double t = column_tan(d, i);
    // Ray (0, t, 1) s: s = z0 + t s k  ->  s = z0 / (1 - t k).
    const double z = z0 / (1.0 - t * k);
    const double len = std::sqrt(1.0 + t * t);
    // Beyond the depth of field (or the plane's horizon): no return, as a source gives.
    if (!(z >= d.min_range_mm && z <= d.max_range_mm)) continue;
    p.valid[i] = 1;
    p.camera_visible[i] = 1;
    p.z_mm[i] = static_cast<float>(z);
    p.y_mm[i] = static_cast<float>(t * z);
    p.range_mm[i] = static_cast<float>(z * len);
    p.cos_incidence[i] = static_cast<float>(std::abs(1.0 - t * k) / (len * nn));
  }
  return p;
}

// Surface with speckle only: no outliers, no dropouts.
ScannerDesc speckle_only(ScannerDesc d) {
  d.shiny_cluster_prob = 0.0;
  d.rough_outlier_prob = 0.0;
  d.dropout_prob_normal = 0.0;
  d.dropout_prob_grazing = 0.0;
  return d;
}

// K = F b / cos^2(theta), F = f / pitch: worked out here from the figures.
double gain_k(const ScannerDesc& d) {
  const double f_px = d.focal_length_mm / (d.pixel_pitch_um * 1e-3);
  const double c = std::cos(d.triangulation_deg * kDeg);
  return f_px * d.baseline_mm / (c * c);
}

}  // namespace

TEST_CASE("error model: the default sensor has the paper's depth resolution", "[error_model]") {
  // Paper, section 3.2.2: 0.015 mm at 100 mm, 1.5 mm at 1000 mm, quadratic in
  // range. The quantization step dz = z^2 s / K of the camera figures.
  const ScannerDesc d = *sensor_preset("mspot");
  CHECK(d.points == 512);
  CHECK(d.rate_hz == 20.0);
  const double k = gain_k(d);
  for (double z : {100.0, 300.0, 1000.0}) {
    const double paper = 0.015 * (z / 100.0) * (z / 100.0);
    const double step = z * z * d.subpixel_step_px / k;
    INFO("z = " << z);
    CHECK(std::abs(step - paper) <= 0.1 * paper);
    CHECK(depth_step_mm(d, z) == Approx(step).epsilon(1e-12));
  }
  // The image rows cover the depth of field, and the image columns the fan.
  const Eigen::Vector2d limits = image_depth_limits_mm(d);
  CHECK(limits.x() <= d.min_range_mm);
  CHECK(limits.y() >= d.max_range_mm);
  CHECK(image_covers_fan(d));
}

TEST_CASE("error model: every preset's image covers its depth of field and fan", "[error_model]") {
  for (const std::string& name : sensor_preset_names()) {
    INFO(name);
    const ScannerDesc d = *sensor_preset(name);
    CHECK(validate(d).empty());
    const Eigen::Vector2d limits = image_depth_limits_mm(d);
    CHECK(limits.x() <= d.min_range_mm);
    CHECK(limits.y() >= d.max_range_mm);
    CHECK(image_covers_fan(d));
    // Resolution worsens with range.
    CHECK(depth_step_mm(d, d.max_range_mm) > depth_step_mm(d, d.min_range_mm));
  }
}

TEST_CASE("error model: camera rows map to depth and back", "[error_model]") {
  const ScannerDesc d = *sensor_preset("mspot");
  const CameraModel cam = camera_model(d);
  for (double z : {40.0, 100.0, 333.3, 1000.0}) {
    // Project the point (0, 0, z) with the pinhole worked out here: camera
    // centre c, axis w, and the image row direction u = y_cam cross w.
    const double th = d.triangulation_deg * kDeg;
    const Eigen::Vector3d c(d.baseline_mm, 0.0, d.baseline_mm * std::tan(th));
    const Eigen::Vector3d w(-std::sin(th), 0.0, std::cos(th));
    const Eigen::Vector3d u(std::cos(th), 0.0, std::sin(th));  // perpendicular to w in x-z
    const Eigen::Vector3d q = Eigen::Vector3d(0, 0, z) - c;
    const double f_px = d.focal_length_mm / (d.pixel_pitch_um * 1e-3);
    // Image coordinate along u (rows grow with z, towards F tan(theta) at infinity).
    const double row = f_px * q.dot(u) / q.dot(w);
    INFO("z = " << z);
    CHECK(image_row_px(cam, z) == Approx(row).epsilon(1e-9));
    CHECK(depth_of_row_mm(cam, image_row_px(cam, z)) == Approx(z).epsilon(1e-12));
  }
}

TEST_CASE("error model: measured depth step and noise against range on a flat plate",
          "[error_model]") {
  // (a) The quantization step is the spacing of the distinct depths the model
  // returns; the noise is the standard deviation of measured - true depth,
  // which for a Gaussian peak jitter sigma quantized to steps s is
  // sqrt(sigma^2 + s^2 / 12) pixels, times z^2 / K.
  ScannerDesc d = speckle_only(*sensor_preset("mspot"));
  d.max_range_mm = 1100.0;  // room for the plate at 1000 mm and its noise
  const double k = gain_k(d);
  for (double z0 : {100.0, 300.0, 1000.0}) {
    INFO("plate at " << z0 << " mm");
    ScanState state;
    state.seed = 42;
    Profile m;
    std::set<float> levels;
    double sum = 0.0, sum2 = 0.0;
    int count = 0;
    for (int prof = 0; prof < 40; ++prof) {
      apply_error_model(d, plane_profile(d, z0, 0.0, prof), state, m);
      for (int i = 0; i < m.size(); ++i) {
        REQUIRE(m.valid[i]);
        levels.insert(m.z_mm[i]);
        const double e = double(m.z_mm[i]) - z0;
        sum += e;
        sum2 += e * e;
        ++count;
      }
    }
    // Distinct levels are consecutive multiples of the sub-pixel step: the
    // median spacing between them is the step.
    std::vector<double> gaps;
    for (auto it = std::next(levels.begin()); it != levels.end(); ++it)
      gaps.push_back(double(*it) - double(*std::prev(it)));
    REQUIRE(gaps.size() >= 5);
    std::nth_element(gaps.begin(), gaps.begin() + gaps.size() / 2, gaps.end());
    const double measured_step = gaps[gaps.size() / 2];
    const double predicted_step = z0 * z0 * d.subpixel_step_px / k;
    CHECK(std::abs(measured_step - predicted_step) <= 0.1 * predicted_step);

    const double mean = sum / count;
    const double sd = std::sqrt(sum2 / count - mean * mean);
    const double sigma_px =
        std::sqrt(d.speckle_px * d.speckle_px + d.subpixel_step_px * d.subpixel_step_px / 12.0);
    const double predicted_sd = z0 * z0 * sigma_px / k;
    CHECK(std::abs(sd - predicted_sd) <= 0.1 * predicted_sd);
    // Unbiased within 4 standard errors plus half a step.
    CHECK(std::abs(mean) <= 4.0 * predicted_sd / std::sqrt(double(count)) + 0.5 * predicted_step);
    // The model's own noise prediction (speckle only) is within 10% too.
    CHECK(std::abs(depth_noise_mm(d, z0) - z0 * z0 * d.speckle_px / k) < 1e-12);
  }
}

TEST_CASE("error model: lateral point spacing against range", "[error_model]") {
  // (b) Points lie on the column rays, so the spacing along the line is
  // z * 2 tan(fan / 2) / N at the centre of the line, growing with range.
  ScannerDesc d = speckle_only(*sensor_preset("mspot"));
  d.max_range_mm = 1100.0;
  for (double z0 : {100.0, 300.0, 1000.0}) {
    INFO("plate at " << z0 << " mm");
    ScanState state;
    state.seed = 7;
    Profile m;
    // Least-squares slope of measured y against column number over 20 profiles.
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    int n = 0;
    for (int prof = 0; prof < 20; ++prof) {
      apply_error_model(d, plane_profile(d, z0, 0.0, prof), state, m);
      for (int i = 0; i < m.size(); ++i) {
        sx += i;
        sy += m.y_mm[i];
        sxx += double(i) * i;
        sxy += double(i) * m.y_mm[i];
        ++n;
      }
    }
    const double slope = (n * sxy - sx * sy) / (n * sxx - sx * sx);
    const double expected = z0 * 2.0 * std::tan(20.0 * kDeg) / 512.0;
    CHECK(std::abs(slope - expected) <= 0.01 * expected);
    CHECK(lateral_spacing_mm(d, z0) == Approx(expected).epsilon(1e-12));
  }
}

TEST_CASE("error model: dropout rates follow the configured probabilities", "[error_model]") {
  // (d) Dropout probability p(i) = p0 + (p90 - p0) sin^4(incidence). Counted
  // from the output: lit, visible, in-window columns that come back invalid.
  ScannerDesc d = speckle_only(*sensor_preset("mspot"));
  d.dropout_prob_normal = 0.02;
  d.dropout_prob_grazing = 0.6;
  d.max_incidence_deg = 89.0;
  for (double tilt : {0.0, 40.0, 55.0}) {
    INFO("plate tilted " << tilt << " deg");
    ScanState state;
    state.seed = 1234;
    Profile m;
    double expected = 0.0;
    int lost = 0, n = 0;
    for (int prof = 0; prof < 200; ++prof) {
      const Profile ideal = plane_profile(d, 200.0, tilt, prof);
      apply_error_model(d, ideal, state, m);
      for (int i = 0; i < m.size(); ++i) {
        REQUIRE(ideal.valid[i]);
        const double c = ideal.cos_incidence[i];
        const double s2 = 1.0 - c * c;
        expected += d.dropout_prob_normal + (d.dropout_prob_grazing - d.dropout_prob_normal) * s2 * s2;
        lost += !m.valid[i];
        ++n;
      }
    }
    // Sum of independent Bernoulli draws: within 5 standard deviations.
    const double p = expected / n;
    CHECK(std::abs(lost - expected) <= 5.0 * std::sqrt(n * p * (1.0 - p)));
    CHECK(state.dropouts == lost);
  }
}

TEST_CASE("error model: shiny clusters and rough outliers at their configured rates",
          "[error_model]") {
  // (d) Shiny: a cluster starts at a column with probability p and covers
  // 1..L columns (uniform), all displaced along the ray by one offset of
  // magnitude in [min, max]. Rough: isolated points displaced by [min, max].
  // On a plate at 100 mm the speckle is 0.025 mm, so anything off by more
  // than 0.15 mm (6 sd) is an outlier.
  ScannerDesc d = speckle_only(*sensor_preset("mspot"));
  const double z0 = 100.0;
  const double noise_bound = 0.15;

  SECTION("shiny clusters") {
    d.shiny_cluster_prob = 0.004;
    d.shiny_cluster_max_points = 5;
    d.shiny_offset_min_mm = 0.5;
    d.shiny_offset_max_mm = 2.0;
    ScanState state;
    state.seed = 99;
    Profile m;
    int starts_seen = 0, off_points = 0, n = 0;
    for (int prof = 0; prof < 400; ++prof) {
      apply_error_model(d, plane_profile(d, z0, 0.0, prof), state, m);
      int run = 0;
      double run_offset = 0.0;
      for (int i = 0; i <= m.size(); ++i) {
        const double e = i < m.size() ? double(m.range_mm[i]) - z0 * std::sqrt(1.0 + std::pow(column_tan(d, i), 2)) : 0.0;
        const bool off = i < m.size() && std::abs(e) > noise_bound;
        if (off) {
          ++off_points;
          // Displacement along the ray within the configured magnitude (plus noise).
          CHECK(std::abs(e) >= d.shiny_offset_min_mm - noise_bound);
          CHECK(std::abs(e) <= d.shiny_offset_max_mm + noise_bound);
          if (run > 0 && std::abs(e - run_offset) > 2 * noise_bound) {
            ++starts_seen;  // a later cluster overriding an earlier one
            run = 0;
          }
          if (run == 0) run_offset = e;
          ++run;
        } else if (run > 0) {
          ++starts_seen;
          run = 0;
        }
      }
      n += m.size();
    }
    // Each column is covered by a cluster with probability
    // 1 - prod_{k=0}^{L-1} (1 - p P(len > k)), P(len > k) = (L - k) / L.
    double miss = 1.0;
    for (int k = 0; k < d.shiny_cluster_max_points; ++k)
      miss *= 1.0 - d.shiny_cluster_prob * (d.shiny_cluster_max_points - k) /
                        double(d.shiny_cluster_max_points);
    // Columns near the start see fewer possible cluster starts; negligible
    // over 512 columns but bounded by 4 columns per profile.
    const double p_cov = 1.0 - miss;
    const double expected = n * p_cov;
    // Points of one cluster are not independent: allow 5 sd of the cluster
    // count times the mean cluster length.
    const double mean_len = (d.shiny_cluster_max_points + 1) / 2.0;
    const double clusters = n * d.shiny_cluster_prob;
    CHECK(std::abs(off_points - expected) <=
          5.0 * std::sqrt(clusters) * mean_len + 4.0 * 400 * d.shiny_cluster_prob * mean_len);
    CHECK(std::abs(starts_seen - clusters) <= 5.0 * std::sqrt(clusters) + 0.1 * clusters);
    CHECK(state.shiny_outliers == off_points);
  }
  SECTION("rough outliers") {
    d.rough_outlier_prob = 0.01;
    d.rough_offset_min_mm = 0.4;
    d.rough_offset_max_mm = 0.8;
    ScanState state;
    state.seed = 5;
    Profile m;
    int off_points = 0, n = 0;
    for (int prof = 0; prof < 100; ++prof) {
      apply_error_model(d, plane_profile(d, z0, 0.0, prof), state, m);
      for (int i = 0; i < m.size(); ++i) {
        const double e = double(m.range_mm[i]) - z0 * std::sqrt(1.0 + std::pow(column_tan(d, i), 2));
        if (std::abs(e) > noise_bound) {
          ++off_points;
          CHECK(std::abs(e) >= d.rough_offset_min_mm - noise_bound);
          CHECK(std::abs(e) <= d.rough_offset_max_mm + noise_bound);
        }
        ++n;
      }
    }
    const double p = d.rough_outlier_prob;
    CHECK(std::abs(off_points - n * p) <= 5.0 * std::sqrt(n * p * (1.0 - p)));
    CHECK(state.rough_outliers == off_points);
  }
}

TEST_CASE("error model: measuring window - region of interest and incidence limit",
          "[error_model]") {
  ScannerDesc d = speckle_only(*sensor_preset("mspot"));
  d.roi_first_column = 100;
  d.roi_last_column = 399;
  d.max_incidence_deg = 60.0;
  ScanState state;
  Profile m;
  apply_error_model(d, plane_profile(d, 200.0, 0.0, 0), state, m);
  for (int i = 0; i < m.size(); ++i) {
    INFO("column " << i);
    CHECK(bool(m.valid[i]) == (i >= 100 && i <= 399));
    CHECK(m.true_valid[i] == 1);  // ground truth is kept for every lit column
  }
  // Tilted 70 degrees: incidence is 70 deg +- the fan; columns whose
  // incidence exceeds 60 degrees return nothing.
  d.roi_first_column = 0;
  d.roi_last_column = kMaxPoints - 1;
  const Profile tilted = plane_profile(d, 200.0, 70.0, 1);
  apply_error_model(d, tilted, state, m);
  int kept = 0;
  for (int i = 0; i < m.size(); ++i) {
    const double incidence = std::acos(double(tilted.cos_incidence[i])) / kDeg;
    if (std::abs(incidence - 60.0) < 1e-3) continue;
    CHECK(bool(m.valid[i]) == (incidence <= 60.0));
    kept += m.valid[i];
  }
  CHECK(kept > 0);
  CHECK(kept < m.size());
}

TEST_CASE("error model: camera shadow and the ideal switch", "[error_model]") {
  ScannerDesc d = speckle_only(*sensor_preset("mspot"));
  Profile ideal = plane_profile(d, 150.0, 0.0, 3);
  for (int i = 200; i < 260; ++i) ideal.camera_visible[i] = 0;
  ScanState state;
  Profile m;
  apply_error_model(d, ideal, state, m);
  for (int i = 0; i < m.size(); ++i) CHECK(bool(m.valid[i]) == !(i >= 200 && i < 260));
  CHECK(state.shadowed == 60);

  d.ideal = true;
  apply_error_model(d, ideal, state, m);
  for (int i = 0; i < m.size(); ++i) {
    CHECK(m.valid[i] == 1);
    CHECK(m.z_mm[i] == ideal.z_mm[i]);
    CHECK(m.y_mm[i] == ideal.y_mm[i]);
  }
}

TEST_CASE("error model: intensity falls with range and incidence", "[error_model]") {
  ScannerDesc d = speckle_only(*sensor_preset("mspot"));
  d.reflectivity = 1.0;
  ScanState state;
  Profile m;
  const int c = d.points / 2;
  auto intensity = [&](double z, double tilt) {
    apply_error_model(d, plane_profile(d, z, tilt, 0), state, m);
    return double(m.intensity[c]);
  };
  // reflectivity * cos(incidence) * (r_ref / r)^2, clamped to 1.
  const double r_ref = d.intensity_ref_range_mm;
  const double range_c = 400.0 * std::sqrt(1.0 + std::pow(column_tan(d, c), 2));
  const double cos_c = plane_profile(d, 400.0, 0.0, 0).cos_incidence[c];
  CHECK(intensity(400.0, 0.0) == Approx(cos_c * (r_ref / range_c) * (r_ref / range_c)).epsilon(1e-5));
  CHECK(intensity(300.0, 0.0) > intensity(400.0, 0.0));
  CHECK(intensity(400.0, 0.0) > intensity(400.0, 40.0));
  CHECK(intensity(400.0, 40.0) > intensity(400.0, 70.0));
  CHECK(intensity(50.0, 0.0) == 1.0f);  // clamped
}

TEST_CASE("error model: the same seed gives the same profile - another seed does not",
          "[error_model]") {
  // (e) Draws are keyed by (seed, profile index, column): order and batching
  // do not matter.
  const ScannerDesc d = *sensor_preset("mspot");
  auto run = [&](std::uint64_t seed, bool reverse) {
    ScanState state;
    state.seed = seed;
    std::vector<Profile> out(50);
    for (int k = 0; k < 50; ++k) {
      const int prof = reverse ? 49 - k : k;
      apply_error_model(d, plane_profile(d, 120.0, 10.0, prof), state, out[prof]);
    }
    return out;
  };
  const auto a = run(17, false), b = run(17, true), c = run(18, false);
  bool any_difference = false;
  for (int k = 0; k < 50; ++k) {
    CHECK(a[k].z_mm == b[k].z_mm);
    CHECK(a[k].y_mm == b[k].y_mm);
    CHECK(a[k].valid == b[k].valid);
    any_difference = any_difference || a[k].z_mm != c[k].z_mm;
  }
  CHECK(any_difference);
}
