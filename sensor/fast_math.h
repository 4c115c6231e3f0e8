#pragma once
// Small, exact-enough replacements for libm calls on the error model's hot
// path (sensor/error_model.cpp). Tested against libm in
// tests/sensor/error_model_test.cpp.
#include <bit>
#include <cmath>
#include <cstdint>
#include <numbers>

namespace vts {

// cos(2 pi u) for u in [0, 1), within 4e-16 of std::cos(2 pi u) and several
// times faster: the quadrant comes exactly from u (u - q / 4 is exact for
// such u), leaving x = 2 pi r, |x| <= pi / 4, for the Taylor series of cos x
// or sin x (the first term left out is below 5e-17). Branch-free.
inline double cos_turns(double u) {
  const int k4 = static_cast<int>(4.0 * u + 0.5);  // nearest quadrant, 0..4 (floor: u >= 0)
  const double q = k4;
  const double x = (2.0 * std::numbers::pi) * (u - 0.25 * q);
  const double x2 = x * x;
  // c = cos x, Horner in x^2 with coefficients (-1)^k / (2k)!.
  double c = 1.0 / 20922789888000.0;  // 1/16!
  c = c * x2 - 1.0 / 87178291200.0;
  c = c * x2 + 1.0 / 479001600.0;
  c = c * x2 - 1.0 / 3628800.0;
  c = c * x2 + 1.0 / 40320.0;
  c = c * x2 - 1.0 / 720.0;
  c = c * x2 + 1.0 / 24.0;
  c = c * x2 - 0.5;
  c = c * x2 + 1.0;
  // s = -sin x = x^3 (1/3! - x^2/5! + ...) - x.
  double s = 1.0 / 1307674368000.0;  // 1/15!
  s = s * x2 - 1.0 / 6227020800.0;
  s = s * x2 + 1.0 / 39916800.0;
  s = s * x2 - 1.0 / 362880.0;
  s = s * x2 + 1.0 / 5040.0;
  s = s * x2 - 1.0 / 120.0;
  s = s * x2 + 1.0 / 6.0;
  s = (s * x2) * x - x;
  // cos(x + k pi / 2): k = 0: cos x, 1: -sin x, 2: -cos x, 3: sin x.
  const int k = k4 & 3;
  const double v = (k & 1) ? s : c;
  return (k & 2) ? -v : v;
}

// (h >> 11) * 2^-53 (a uniform draw in [0, 1) from a 64-bit hash), exactly,
// in two int32 conversions that vectorize on AVX2 (a 64-bit one does not).
inline double unit_from_hash(std::uint64_t h) {
  const auto hi = static_cast<std::int32_t>(h >> 33);                 // top 31 bits
  const auto lo = static_cast<std::int32_t>((h >> 11) & 0x3FFFFFu);  // next 22 bits
  return static_cast<double>(hi) * 0x1p-31 + static_cast<double>(lo) * 0x1p-53;
}

// log x for normal x in (0, 1] (x >= 2^-1022), within 3e-16 * max(1, |log x|)
// of std::log, branch-free so that a loop of it vectorizes: x = m 2^e with
// m in [sqrt(1/2), sqrt(2)), log m = 2 atanh f, f = (m - 1) / (m + 1),
// |f| <= 0.172, whose odd series is summed to f^23 (next term below 1e-19).
inline double log_unit(double x) {
  const std::uint64_t b = std::bit_cast<std::uint64_t>(x);
  const double m1 = std::bit_cast<double>((b & 0x000FFFFFFFFFFFFFull) | 0x3FF0000000000000ull);  // [1, 2)
  const bool big = m1 > std::numbers::sqrt2;
  const double m = big ? 0.5 * m1 : m1;
  const int e = static_cast<int>(static_cast<std::uint32_t>(b >> 52)) - 1023 + (big ? 1 : 0);
  const double f = (m - 1.0) / (m + 1.0);
  const double s = f * f;
  double p = 1.0 / 23.0;
  p = p * s + 1.0 / 21.0;
  p = p * s + 1.0 / 19.0;
  p = p * s + 1.0 / 17.0;
  p = p * s + 1.0 / 15.0;
  p = p * s + 1.0 / 13.0;
  p = p * s + 1.0 / 11.0;
  p = p * s + 1.0 / 9.0;
  p = p * s + 1.0 / 7.0;
  p = p * s + 1.0 / 5.0;
  p = p * s + 1.0 / 3.0;
  const double log_m = 2.0 * f + 2.0 * f * s * p;
  // ln 2 split so that e * kLn2Hi is exact for |e| < 2^11.
  constexpr double kLn2Hi = 6.93147180369123816490e-01;
  constexpr double kLn2Lo = 1.90821492927058770002e-10;
  const double ed = static_cast<double>(e);
  return ed * kLn2Hi + (log_m + ed * kLn2Lo);
}

// std::round (halves away from zero) as trunc(x + (the largest double below
// 1/2, with x's sign)): exact for every x, and inlined (vectorized where the
// target has a rounding instruction), which the library call is not.
inline double round_half_away(double x) { return std::trunc(x + std::copysign(0.49999999999999994, x)); }

}  // namespace vts
