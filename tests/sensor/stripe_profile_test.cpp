// peaks_to_profile against the camera worked out here from the preset's
// fields, and write_peaks_csv's lines.
#include <catch2/catch.hpp>

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "sensor/presets.h"
#include "sensor/stripe_profile.h"

namespace {

// A result of `width` columns, column c holding one peak at rows[c] (< 0: none).
vts::stripe::PeakResult peaks_at(const std::vector<double>& rows) {
  vts::stripe::PeakResult r;
  r.column_offset.push_back(0);
  for (double row : rows) {
    r.chosen.push_back(row < 0 ? -1 : static_cast<int>(r.peaks.size()));
    if (row >= 0) r.peaks.push_back({.row = static_cast<float>(row), .width_px = 3.5f, .peak_dn = 2000.0f});
    r.column_offset.push_back(static_cast<int>(r.peaks.size()));
  }
  return r;
}

}  // namespace

TEST_CASE("peaks_to_profile inverts the camera's projection, also for a region of interest", "[stripe_profile]") {
  const auto desc = vts::sensor_preset("lps-1280-mid");
  REQUIRE(desc);
  const int w = desc->image_width_px, h = desc->image_height_px;
  const double theta = desc->triangulation_deg * M_PI / 180.0;
  const double f = desc->focal_length_mm / (desc->pixel_pitch_um * 1e-3);
  const double k = f * desc->baseline_mm / std::pow(std::cos(theta), 2);
  // A plane tilted along the laser line: z = 300 + 0.2 y; column c sees y = v z cos / F.
  std::vector<double> rows(w, -1.0), y(w), z(w);
  for (int c = 0; c < w; c += 3) {
    const double v = c - 0.5 * (w - 1), s = v * std::cos(theta) / f;  // y = s z
    z[c] = 300.0 / (1.0 - 0.2 * s);
    y[c] = s * z[c];
    rows[c] = f * std::tan(theta) - k / z[c] + 0.5 * (h - 1);
  }
  for (int offset : {0, 200}) {
    std::vector<double> roi = rows;
    for (double& r : roi)
      if (r >= 0) r -= offset;
    vts::Profile p;
    vts::peaks_to_profile(*desc, peaks_at(roi), h - offset, 12, offset, p);
    REQUIRE(p.size() == w);
    for (int c = 0; c < w; ++c) {
      INFO("offset " << offset << " column " << c);
      REQUIRE(p.valid[c] == (c % 3 == 0));
      if (!p.valid[c]) continue;
      CHECK(p.y_mm[c] == Approx(y[c]).margin(1e-3));
      CHECK(p.z_mm[c] == Approx(z[c]).margin(1e-3));
      CHECK(p.intensity[c] == Approx(2000.0 / 4095.0));
    }
  }
  vts::Profile p;
  CHECK_THROWS_WITH(vts::peaks_to_profile(*desc, peaks_at({10.0, 20.0}), h, 12, 0, p),
                    "the image is 2 columns wide, the sensor's camera " + std::to_string(w));
  CHECK_THROWS_WITH(vts::peaks_to_profile(*desc, peaks_at(rows), 64, 12, h - 32, p),
                    Catch::StartsWith("rows " + std::to_string(h - 32) + ".." + std::to_string(h + 31) +
                                      " are outside the sensor camera's rows"));
}

TEST_CASE("write_peaks_csv: the chosen peak, the count and the others", "[stripe_profile]") {
  vts::stripe::PeakResult r = peaks_at({12.25, -1.0});
  r.peaks.push_back({.row = 40.5f, .width_px = 2.0f, .peak_dn = 255.0f, .strength = 900.0f, .saturated = true});
  r.column_offset[1] = r.column_offset[2] = 2;  // column 0: both peaks, the first chosen
  std::ostringstream out;
  vts::write_peaks_csv(out, r);
  CHECK(out.str() ==
        "column,row,width_px,peak_dn,strength,saturated,peaks,others\n"
        "0,12.2500,3.500,2000,0.0,0,2,40.5000:2.000:255:900.0:1\n"
        "1,,,,,,0,\n");
}
