// vts peaks: images written here with OpenImageIO from a formula
// (tests/common/stripe_image.h: a Gaussian stripe of known centre per column,
// each pixel the Gaussian's mean over the pixel), run through bin/vts, the CSV read back against the known centres
// (the exact messages for bad input are in tests/malformed/cases.txt).
#include <catch2/catch.hpp>

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <sstream>
#include <string>
#include <vector>

#include "sensor/presets.h"
#include "tests/common/stripe_image.h"
#include "vts_runner.h"

namespace {

using namespace vts_test;

// A stripe image written as an 8- or 16-bit PNG.
struct Picture : vts::test::StripeImage {
  using StripeImage::StripeImage;
  void write(const fs::path& path, int bits) const {
    const std::vector<std::uint16_t> px = pixels(bits);
    auto out = OIIO::ImageOutput::create(path.string());
    REQUIRE(out);
    const OIIO::TypeDesc type = bits == 8 ? OIIO::TypeDesc::UINT8 : OIIO::TypeDesc::UINT16;
    REQUIRE(out->open(path.string(), OIIO::ImageSpec(width, height, 1, type)));
    if (bits == 8) {
      const std::vector<std::uint8_t> p8(px.begin(), px.end());
      REQUIRE(out->write_image(type, p8.data()));
    } else {
      REQUIRE(out->write_image(type, px.data()));
    }
    REQUIRE(out->close());
  }
};

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> parts;
  std::string part;
  std::istringstream in(s);
  while (std::getline(in, part, sep)) parts.push_back(part);
  if (!s.empty() && s.back() == sep) parts.push_back("");
  return parts;
}

// The CSV's lines after the header, split into fields.
std::vector<std::vector<std::string>> csv_rows(const std::string& text, std::string& header) {
  std::istringstream in(text);
  std::getline(in, header);
  std::vector<std::vector<std::string>> rows;
  for (std::string line; std::getline(in, line);) rows.push_back(split(line, ','));
  return rows;
}

}  // namespace

TEST_CASE("vts peaks: each column's stripe centre from a 16-bit PNG, the reflection among the others", "[apps]") {
  TempDir dir;
  Picture pic(120, 100);
  std::vector<double> mu;
  for (int c = 0; c < pic.width; ++c) {
    mu.push_back(40.0 + 0.073 * c);
    pic.add(c, mu[c], 1.5, 30000.0);
    if (c % 10 == 5) pic.add(c, mu[c] + 30.0, 2.0, 60000.0);
  }
  pic.write(dir.path / "stripe.png", 16);
  for (const char* policy : {"strongest", "continuous"}) {
    const Result r = run_vts(dir, std::string("peaks stripe.png --threshold 1000 --policy ") + policy);
    INFO(r.err);
    REQUIRE(r.code == 0);
    CHECK(contains(r.out, "stripe.png (120x100, 16-bit): 132 peaks, one chosen (" + std::string(policy) +
                              ") in 120 of 120 columns; wrote stripe.peaks.csv"));
    std::string header;
    const auto rows = csv_rows(slurp(dir.path / "stripe.peaks.csv"), header);
    CHECK(header == "column,row,width_px,peak_dn,strength,saturated,peaks,others");
    REQUIRE(rows.size() == 120u);
    for (int c = 0; c < 120; ++c) {
      INFO(policy << " column " << c);
      const auto& f = rows[c];
      REQUIRE(f.size() == 8u);
      CHECK(f[0] == std::to_string(c));
      const bool reflected = c % 10 == 5;
      const bool takes_reflection = reflected && std::string(policy) == "strongest";
      CHECK(std::stod(f[1]) == Approx(mu[c] + (takes_reflection ? 30.0 : 0.0)).margin(0.002));
      CHECK(std::stod(f[2]) == Approx(2.3548 * (takes_reflection ? 2.0 : 1.5)).epsilon(0.05));
      CHECK(f[5] == "0");
      CHECK(f[6] == (reflected ? "2" : "1"));
      if (!reflected) {
        CHECK(f[7].empty());
        continue;
      }
      const auto other = split(f[7], ':');
      REQUIRE(other.size() == 5u);
      CHECK(std::stod(other[0]) == Approx(mu[c] + (takes_reflection ? 0.0 : 30.0)).margin(0.002));
    }
  }
}

TEST_CASE("vts peaks: an 8-bit saturated stripe, an empty column, --out and --method", "[apps]") {
  TempDir dir;
  Picture pic(20, 60);
  for (int c = 0; c < pic.width; ++c)
    if (c != 7) pic.add(c, 30.5, 2.5, 3.0 * 255);  // symmetric about a pixel edge: the plateau's centre
  pic.write(dir.path / "sat.png", 8);
  const Result r = run_vts(dir, "peaks sat.png --out out/peaks.csv");
  CHECK(r.code == 2);
  CHECK(contains(r.err, "--out = 'out/peaks.csv': directory 'out' does not exist"));
  for (const char* method : {"cog", "gaussian", "parabolic"}) {
    const Result ok = run_vts(dir, std::string("peaks sat.png --out p.csv --method ") + method);
    INFO(ok.err);
    REQUIRE(ok.code == 0);
    std::string header;
    const auto rows = csv_rows(slurp(dir.path / "p.csv"), header);
    REQUIRE(rows.size() == 20u);
    for (int c = 0; c < 20; ++c) {
      INFO("column " << c);
      if (c == 7) {
        CHECK(rows[c] == std::vector<std::string>{"7", "", "", "", "", "", "0", ""});
        continue;
      }
      CHECK(std::stod(rows[c][1]) == Approx(30.5).margin(1e-4));
      CHECK(rows[c][3] == "255");
      CHECK(rows[c][5] == "1");
    }
  }
}

TEST_CASE("vts peaks --sensor: a plane at a known range gives its profile", "[apps]") {
  // The camera of the preset, worked out here from its fields: a point of the
  // laser plane at depth z is on row u = F tan(theta) - F b / (cos^2(theta) z)
  // from the principal point, at the centre of the image.
  const auto desc = vts::sensor_preset("mspot");
  REQUIRE(desc);
  const double theta = desc->triangulation_deg * M_PI / 180.0;
  const double f_px = desc->focal_length_mm / (desc->pixel_pitch_um * 1e-3);
  const double z0 = 0.5 * (desc->min_range_mm + std::min(desc->max_range_mm, 400.0));
  const double u = f_px * std::tan(theta) - f_px * desc->baseline_mm / (std::pow(std::cos(theta), 2) * z0);
  const int w = desc->image_width_px, h = desc->image_height_px;
  const double row = u + 0.5 * (h - 1);
  REQUIRE(row > 10.0);
  REQUIRE(row < h - 10.0);
  TempDir dir;
  Picture pic(w, h);
  for (int c = 0; c < w; ++c) pic.add(c, row, 1.5, 30000.0);
  pic.write(dir.path / "plane.png", 16);
  const Result r = run_vts(dir, "peaks plane.png --sensor mspot --profile plane.csv --threshold 1000");
  INFO(r.err);
  REQUIRE(r.code == 0);
  CHECK(contains(r.out, "profile through mspot's camera: " + std::to_string(w) + " valid points; wrote plane.csv"));
  // The preset's detector (its peak_* fields), as the image mode runs it.
  CHECK(contains(r.out, "one chosen (" + desc->peak_policy + ")"));
  std::string header;
  const auto rows = csv_rows(slurp(dir.path / "plane.csv"), header);
  CHECK(header == "profile,y,z,valid");
  REQUIRE(rows.size() == static_cast<std::size_t>(w));
  for (int c = 0; c < w; c += 37) {
    INFO("column " << c);
    const double y = (c - 0.5 * (w - 1)) * z0 * std::cos(theta) / f_px;
    CHECK(std::stod(rows[c][1]) == Approx(y).margin(0.001));
    CHECK(std::stod(rows[c][2]) == Approx(z0).margin(0.001));
    CHECK(rows[c][3] == "1");
  }
  // An option overrides the preset's detector; without --sensor the
  // detector's own defaults apply.
  const Result strongest = run_vts(dir, "peaks plane.png --sensor mspot --policy strongest --out p1.csv --threshold 1000");
  CHECK(contains(strongest.out, "one chosen (strongest)"));
  const Result plain = run_vts(dir, "peaks plane.png --out p2.csv --threshold 1000");
  CHECK(contains(plain.out, "one chosen (strongest)"));
  // An image of another size is not this camera's.
  Picture(w / 2, 40).write(dir.path / "small.png", 16);
  const Result bad = run_vts(dir, "peaks small.png --sensor mspot --out s.csv");
  CHECK(bad.code == 2);
  CHECK(contains(bad.err, "vts peaks: --sensor = 'mspot': small.png: the image is " + std::to_string(w / 2) +
                              " columns wide, the sensor's camera " + std::to_string(w)));
  CHECK(!fs::exists(dir.path / "s.csv"));
}
