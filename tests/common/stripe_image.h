#pragma once
// A camera image of a laser stripe from a formula, for the peak detector's
// tests: per column Gaussian stripes of known centre, sigma and amplitude,
// each pixel the Gaussian's mean over the pixel (erf), so the true sub-pixel
// centre of every column is known. Row r's pixel covers [r - 0.5, r + 0.5].
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace vts::test {

struct StripeImage {
  int width, height;
  std::vector<double> value;  // DN, row-major, before rounding and clipping

  StripeImage(int w, int h) : width(w), height(h), value(static_cast<std::size_t>(w) * h, 0.0) {}

  // Adds to column c a Gaussian stripe of peak amplitude a_dn, centre mu (rows) and sigma (rows).
  void add(int c, double mu, double sigma, double a_dn) {
    const double k = a_dn * sigma * std::sqrt(M_PI / 2.0);
    for (int r = 0; r < height; ++r)
      value[static_cast<std::size_t>(r) * width + c] += k * (std::erf((r + 0.5 - mu) / (M_SQRT2 * sigma)) -
                                                              std::erf((r - 0.5 - mu) / (M_SQRT2 * sigma)));
  }
  double at(int r, int c) const { return value[static_cast<std::size_t>(r) * width + c]; }

  // The pixels of a `bits`-bit image: rounded, clipped to [0, 2^bits - 1].
  std::vector<std::uint16_t> pixels(int bits) const {
    std::vector<std::uint16_t> p(value.size());
    const double full_scale = (1 << bits) - 1;
    for (std::size_t i = 0; i < p.size(); ++i)
      p[i] = static_cast<std::uint16_t>(std::clamp(std::round(value[i]), 0.0, full_scale));
    return p;
  }
};

}  // namespace vts::test
