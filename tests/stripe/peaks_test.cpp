// The peak detector on images synthesised from a formula
// (tests/common/stripe_image.h): per column a Gaussian stripe of known centre
// and sigma, each pixel the Gaussian's mean over the pixel (erf), so the true
// sub-pixel centre of every column is known.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "stripe/peaks.h"
#include "tests/common/stripe_image.h"

namespace {

using namespace vts::stripe;

// A stripe image and its depth.
struct Image : vts::test::StripeImage {
  int bits;
  Image(int w, int h, int b = 16) : StripeImage(w, h), bits(b) {}
  std::vector<std::uint16_t> pixels() const { return StripeImage::pixels(bits); }
};

PeakResult detect(const Image& img, const PeakParams& params) {
  const auto px = img.pixels();
  PeakResult out;
  detect_peaks({px.data(), img.width, img.height, img.width, img.bits}, params, out);
  return out;
}

// Largest |chosen row - truth| over the columns; every column must have a chosen peak.
double max_error(const PeakResult& r, const std::vector<double>& truth) {
  double e = 0.0;
  for (int c = 0; c < r.width(); ++c) {
    REQUIRE(r.chosen_peak(c) != nullptr);
    e = std::max(e, std::abs(r.chosen_peak(c)->row - truth[c]));
  }
  return e;
}

// 64 columns, centres 100 + (c + 0.5) / 64 (every sub-pixel offset, none
// exactly between two rows), no noise.
struct Stripe {
  Image img{64, 200};
  std::vector<double> mu;
  explicit Stripe(double sigma, double a_dn = 40000.0) {
    for (int c = 0; c < img.width; ++c) {
      mu.push_back(100.0 + (c + 0.5) / 64.0);
      img.add(c, mu.back(), sigma, a_dn);
    }
  }
};

PeakParams with(SubPixel m, int window) {
  PeakParams p;
  p.method = m;
  p.window_px = window;
  p.threshold_dn = 1.0;
  return p;
}

}  // namespace

TEST_CASE("the Gaussian fit finds a noise-free Gaussian stripe's centre within 0.01 px", "[stripe]") {
  for (double sigma : {1.0, 1.5, 2.5}) {
    Stripe s(sigma);
    for (int w : {1, 2, 3}) {
      const double e = max_error(detect(s.img, with(SubPixel::gaussian, w)), s.mu);
      INFO("sigma " << sigma << " window " << w << ": max error " << e << " px");
      CHECK(e < 0.01);
    }
  }
}

TEST_CASE("the centre of gravity is unbiased over a wide window and pulled to the pixel centre by a narrow one",
          "[stripe]") {
  const double sigma = 1.5;
  Stripe s(sigma);
  // Window +-8 rows (> 5 sigma): the sum of row * pixel mass is the mean.
  CHECK(max_error(detect(s.img, with(SubPixel::centre_of_gravity, 8)), s.mu) < 0.005);
  // Window +-1: theory is the centre of gravity of the three pixel masses
  // around the brightest pixel, worked out here from the formula.
  const auto r = detect(s.img, with(SubPixel::centre_of_gravity, 1));
  double worst_bias = 0.0;
  for (int c = 0; c < s.img.width; ++c) {
    const int m = static_cast<int>(std::lround(s.mu[c]));
    double sum = 0.0, sum_r = 0.0;
    for (int k = m - 1; k <= m + 1; ++k) sum += s.img.at(k, c) - 1.0, sum_r += k * (s.img.at(k, c) - 1.0);
    const double theory = sum_r / sum;
    CHECK(r.chosen_peak(c)->row == Approx(theory).margin(0.002));
    // Biased towards the pixel centre m, never beyond the truth.
    CHECK(std::abs(theory - m) <= std::abs(s.mu[c] - m) + 1e-9);
    worst_bias = std::max(worst_bias, std::abs(theory - s.mu[c]));
  }
  CHECK(worst_bias > 0.05);  // the bias is real, not rounding
}

TEST_CASE("the 3-point parabola follows its closed form, biased on a Gaussian", "[stripe]") {
  const double sigma = 1.5;
  Stripe s(sigma);
  const auto r = detect(s.img, with(SubPixel::parabolic, 1));
  double worst_bias = 0.0;
  for (int c = 0; c < s.img.width; ++c) {
    const int m = static_cast<int>(std::lround(s.mu[c]));
    const double a = s.img.at(m - 1, c), b = s.img.at(m, c), d = s.img.at(m + 1, c);
    const double theory = m + (a - d) / (2.0 * (a - 2.0 * b + d));
    CHECK(r.chosen_peak(c)->row == Approx(theory).margin(0.002));
    worst_bias = std::max(worst_bias, std::abs(theory - s.mu[c]));
  }
  CHECK(worst_bias > 0.01);
  CHECK(worst_bias < 0.1);
}

TEST_CASE("with seeded noise the Gaussian fit stays within a fiftieth of a pixel rms", "[stripe]") {
  Stripe s(1.5, 2000.0);
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 10.0);  // 0.5 % of the amplitude
  for (double& v : s.img.value) v = std::max(0.0, v + 20.0 + noise(rng));
  PeakParams p = with(SubPixel::gaussian, 2);
  p.threshold_dn = 200.0;
  const auto r = detect(s.img, p);
  double sq = 0.0;
  for (int c = 0; c < s.img.width; ++c) sq += std::pow(r.chosen_peak(c)->row - s.mu[c], 2);
  const double rms = std::sqrt(sq / s.img.width);
  INFO("rms error " << rms << " px");
  CHECK(rms < 0.02);
}

TEST_CASE("the width at half maximum is 2.3548 sigma", "[stripe]") {
  for (double sigma : {1.5, 2.0, 4.0}) {
    Stripe s(sigma);
    const auto r = detect(s.img, with(SubPixel::gaussian, 3));
    for (int c = 0; c < s.img.width; ++c) {
      INFO("sigma " << sigma << " column " << c);
      CHECK(r.chosen_peak(c)->width_px == Approx(2.3548 * sigma).epsilon(0.05));
    }
  }
}

TEST_CASE("a saturated stripe is placed by the plateau rule", "[stripe]") {
  // Amplitude 3x full scale, sigma 3: about 8 saturated rows.
  Image img(66, 200);
  std::vector<double> mu;
  for (int c = 0; c < 64; ++c) mu.push_back(100.0 + c / 64.0);
  mu.push_back(120.0);  // symmetric about a pixel centre
  mu.push_back(120.5);  // and about a pixel edge
  for (int c = 0; c < img.width; ++c) img.add(c, mu[c], 3.0, 3.0 * 65535);
  for (SubPixel m : {SubPixel::gaussian, SubPixel::parabolic, SubPixel::centre_of_gravity}) {
    const auto r = detect(img, with(m, 3));
    for (int c = 0; c < img.width; ++c) {
      const Peak* p = r.chosen_peak(c);
      REQUIRE(p);
      CHECK(p->saturated);
      CHECK(p->peak_dn == 65535.0f);
      CHECK(std::abs(p->row - mu[c]) < 0.01);
    }
    CHECK(r.chosen_peak(64)->row == Approx(120.0).margin(1e-4));
    CHECK(r.chosen_peak(65)->row == Approx(120.5).margin(1e-4));
  }
  // A saturation level below full scale is honoured.
  Image low(1, 100);
  low.add(0, 50.25, 2.0, 30000.0);
  PeakParams p = with(SubPixel::gaussian, 3);
  p.saturation_dn = 20000.0;
  const auto r = detect(low, p);
  REQUIRE(r.chosen_peak(0));
  CHECK(r.chosen_peak(0)->saturated);
  CHECK(r.chosen_peak(0)->row == Approx(50.25).margin(0.05));
}

TEST_CASE("a brighter reflection 40 rows off in one column in ten: strongest takes it, continuous does not",
          "[stripe]") {
  Image img(200, 200);
  std::vector<double> mu;
  for (int c = 0; c < img.width; ++c) {
    mu.push_back(60.0 + 0.05 * c);
    img.add(c, mu[c], 1.5, 20000.0);
    if (c % 10 == 5) img.add(c, mu[c] + 40.0, 2.0, 50000.0);
  }
  PeakParams p = with(SubPixel::gaussian, 3);
  p.threshold_dn = 1000.0;
  p.policy = PeakPolicy::strongest;
  const auto strongest = detect(img, p);
  p.policy = PeakPolicy::continuous;
  const auto continuous = detect(img, p);
  for (int c = 0; c < img.width; ++c) {
    INFO("column " << c);
    const bool reflected = c % 10 == 5;
    REQUIRE(continuous.count(c) == (reflected ? 2 : 1));
    CHECK(strongest.chosen_peak(c)->row == Approx(mu[c] + (reflected ? 40.0 : 0.0)).margin(0.01));
    CHECK(continuous.chosen_peak(c)->row == Approx(mu[c]).margin(0.01));
  }
}

TEST_CASE("continuous follows the stripe through a gap and across a real step", "[stripe]") {
  // Rows 50 for columns 0..49, nothing for 50..54, rows 90 from 55 on (a lap
  // joint's edge); a bright blob at row 20 in column 70.
  Image img(120, 150);
  for (int c = 0; c < 120; ++c) {
    if (c < 50) img.add(c, 50.0, 1.5, 20000.0);
    if (c >= 55) img.add(c, 90.0, 1.5, 20000.0);
  }
  img.add(70, 20.0, 1.5, 60000.0);
  PeakParams p = with(SubPixel::gaussian, 3);
  p.threshold_dn = 1000.0;
  p.policy = PeakPolicy::continuous;
  const auto r = detect(img, p);
  for (int c = 0; c < 120; ++c) {
    INFO("column " << c);
    if (c >= 50 && c < 55) {
      CHECK(r.chosen[c] == -1);
      continue;
    }
    REQUIRE(r.chosen_peak(c));
    CHECK(r.chosen_peak(c)->row == Approx(c < 50 ? 50.0 : 90.0).margin(0.01));
  }
}

TEST_CASE("a close second peak does not pull the fit", "[stripe]") {
  // Two stripes 5 rows apart, separate runs above the threshold: each
  // window stops at the darkest row between them.
  Image img(8, 100);
  std::vector<double> mu;
  for (int c = 0; c < img.width; ++c) {
    mu.push_back(50.0 + c / 8.0);
    img.add(c, mu[c], 1.0, 20000.0);
    img.add(c, mu[c] + 5.0, 1.0, 20000.0);
  }
  for (SubPixel m : {SubPixel::gaussian, SubPixel::centre_of_gravity}) {
    PeakParams p = with(m, 3);
    p.threshold_dn = 6000.0;
    const auto r = detect(img, p);
    for (int c = 0; c < img.width; ++c) {
      INFO(to_string(m) << " column " << c);
      REQUIRE(r.count(c) == 2);
      const Peak& a = r.peaks[r.column_offset[c]];
      const Peak& b = r.peaks[r.column_offset[c] + 1];
      CHECK(a.row == Approx(mu[c]).margin(m == SubPixel::gaussian ? 0.01 : 0.06));
      CHECK(b.row == Approx(mu[c] + 5.0).margin(m == SubPixel::gaussian ? 0.01 : 0.06));
    }
  }
}

TEST_CASE("first, last, widest and strongest as defined", "[stripe]") {
  Image img(1, 200);
  img.add(0, 30.0, 1.0, 20000.0);   // first
  img.add(0, 80.0, 4.0, 10000.0);   // widest
  img.add(0, 150.0, 2.0, 30000.0);  // last and strongest
  PeakParams p = with(SubPixel::gaussian, 3);
  p.threshold_dn = 1000.0;
  const std::pair<PeakPolicy, double> expected[] = {
      {PeakPolicy::first, 30.0}, {PeakPolicy::last, 150.0}, {PeakPolicy::widest, 80.0}, {PeakPolicy::strongest, 150.0}};
  for (const auto& [policy, row] : expected) {
    p.policy = policy;
    const auto r = detect(img, p);
    INFO(to_string(policy));
    REQUIRE(r.count(0) == 3);
    CHECK(r.peaks[0].row < r.peaks[1].row);
    CHECK(r.peaks[1].row < r.peaks[2].row);
    CHECK(r.chosen_peak(0)->row == Approx(row).margin(0.01));
  }
}

TEST_CASE("the threshold: absolute, relative to the column maximum, strict, default 1/16 of full scale", "[stripe]") {
  Image img(1, 200);
  img.add(0, 40.0, 1.5, 20000.0);
  img.add(0, 120.0, 1.5, 8000.0);
  PeakParams p = with(SubPixel::gaussian, 3);
  p.threshold_dn = 5000.0;
  CHECK(detect(img, p).count(0) == 2);
  p.threshold_dn = 9000.0;  // above the dim peak's maximum
  CHECK(detect(img, p).count(0) == 1);
  p.threshold_dn = 1.0;
  p.threshold_rel = 0.5;  // 10000 DN
  auto r = detect(img, p);
  CHECK(r.count(0) == 1);
  CHECK(r.threshold_dn[0] == Approx(r.peaks[0].peak_dn * 0.5));
  // A pixel equal to the threshold is not lit.
  const std::uint16_t column[5] = {0, 100, 200, 100, 0};
  PeakParams q;
  q.threshold_dn = 200.0;
  detect_peaks({column, 1, 5, 1, 16}, q, r);
  CHECK(r.count(0) == 0);
  q.threshold_dn = 199.0;
  detect_peaks({column, 1, 5, 1, 16}, q, r);
  CHECK(r.count(0) == 1);
  // Default threshold at 8 bits: 255 / 16 = 15.9 DN, so 15 DN of glow is no peak.
  const std::uint16_t glow[5] = {15, 15, 15, 15, 15};
  detect_peaks({glow, 1, 5, 1, 8}, PeakParams{}, r);
  CHECK(r.count(0) == 0);
  CHECK(r.threshold_dn[0] == Approx(255.0 / 16.0));
}

TEST_CASE("an empty column has no peak and chosen -1, under every policy", "[stripe]") {
  Image img(3, 50);
  img.add(0, 20.0, 1.5, 20000.0);
  img.add(2, 21.0, 1.5, 20000.0);
  for (int k = 0; k < 5; ++k) {
    PeakParams p;
    p.policy = static_cast<PeakPolicy>(k);
    const auto r = detect(img, p);
    INFO(to_string(p.policy));
    CHECK(r.count(1) == 0);
    CHECK(r.chosen[1] == -1);
    CHECK(r.chosen[0] >= 0);
    CHECK(r.chosen[2] >= 0);
  }
}

TEST_CASE("close runs merge into one peak, short runs are dropped, the row range is searched only", "[stripe]") {
  // Two maxima 2 rows apart with a dip below the threshold between them.
  const std::uint16_t column[12] = {0, 0, 0, 900, 3000, 900, 3500, 900, 0, 0, 2000, 0};
  PeakParams p;
  p.threshold_dn = 1000.0;
  p.min_separation_px = 3.0;
  PeakResult r;
  detect_peaks({column, 1, 12, 1, 12}, p, r);
  REQUIRE(r.count(0) == 2);
  CHECK(r.peaks[0].first_row == 4);
  CHECK(r.peaks[0].last_row == 6);
  CHECK(r.peaks[0].peak_dn == 3500.0f);
  CHECK(r.peaks[0].strength == Approx(2000.0 + 2500.0));
  p.min_separation_px = 0.0;
  detect_peaks({column, 1, 12, 1, 12}, p, r);
  CHECK(r.count(0) == 3);
  p.min_width_px = 2;  // every run here is one row long
  detect_peaks({column, 1, 12, 1, 12}, p, r);
  CHECK(r.count(0) == 0);
  p.min_width_px = 1;
  p.row_first = 8;
  p.row_last = 11;
  detect_peaks({column, 1, 12, 1, 12}, p, r);
  REQUIRE(r.count(0) == 1);
  CHECK(r.peaks[0].row == Approx(10.0));  // image rows, not rows from row_first
  CHECK(r.peaks[0].first_row == 10);
}

TEST_CASE("the result is reused without allocating", "[stripe]") {
  Stripe s(1.5);
  const auto px = s.img.pixels();
  PeakResult r;
  const ImageView view{px.data(), s.img.width, s.img.height, s.img.width, 16};
  detect_peaks(view, PeakParams{.policy = PeakPolicy::continuous}, r);
  const auto* peaks = r.peaks.data();
  const auto* score = r.score_.data();
  const auto* strip = r.strip_.data();
  detect_peaks(view, PeakParams{.policy = PeakPolicy::continuous}, r);
  CHECK(r.peaks.data() == peaks);
  CHECK(r.score_.data() == score);
  CHECK(r.strip_.data() == strip);
}

TEST_CASE("bad parameters and images are refused with the field and the value", "[stripe]") {
  const std::uint16_t column[4] = {0, 10, 0, 0};
  PeakResult r;
  auto message = [&](PeakParams p, ImageView v) {
    try {
      detect_peaks(v, p, r);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  auto msg = [&](PeakParams p) { return message(p, {column, 1, 4, 1, 8}); };
  using Catch::Matchers::StartsWith;
  CHECK_THAT(msg({.window_px = 0}), StartsWith("window_px = 0: must be 1..32"));
  CHECK_THAT(msg({.threshold_dn = 300}), StartsWith("threshold_dn = 300: ") && Catch::Contains("255"));
  CHECK_THAT(msg({.threshold_rel = 1.0}), StartsWith("threshold_rel = 1: "));
  CHECK_THAT(msg({.min_width_px = 5}), StartsWith("min_width_px = 5: must be 1..4"));
  CHECK_THAT(msg({.saturation_dn = 10}), StartsWith("saturation_dn = 10: "));
  CHECK_THAT(msg({.min_separation_px = -1}), StartsWith("min_separation_px = -1: "));
  CHECK_THAT(msg({.row_first = 4}), StartsWith("row_first = 4: "));
  CHECK_THAT(msg({.row_first = 2, .row_last = 1}), StartsWith("row_last = 1: "));
  CHECK_THAT(msg({.max_jump_px = -2}), StartsWith("max_jump_px = -2: "));
  CHECK_THAT(msg({.jump_cost = NAN}), StartsWith("jump_cost = nan: "));
  CHECK_THAT(msg({.miss_cost = -1}), StartsWith("miss_cost = -1: "));
  CHECK_THAT(message({}, {column, 1, 4, 1, 9}), StartsWith("bits = 9: must be 8, 10, 12 or 16"));
  CHECK_THAT(message({}, {column, 2, 2, 1, 8}), StartsWith("ImageView.stride = 1: "));
  CHECK_THAT(message({}, {nullptr, 1, 4, 1, 8}), StartsWith("ImageView.data is null"));
  CHECK(msg({}) == "no error");
}

TEST_CASE("method and policy names round-trip", "[stripe]") {
  for (int k = 0; k < 3; ++k) CHECK(parse_sub_pixel(to_string(static_cast<SubPixel>(k))) == static_cast<SubPixel>(k));
  for (int k = 0; k < 5; ++k)
    CHECK(parse_peak_policy(to_string(static_cast<PeakPolicy>(k))) == static_cast<PeakPolicy>(k));
  CHECK(to_string(SubPixel::centre_of_gravity) == "cog");
  CHECK(!parse_sub_pixel("gauss"));
  CHECK(!parse_peak_policy("brightest"));
}
