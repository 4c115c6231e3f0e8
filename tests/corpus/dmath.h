// Deterministic elementary functions for the corpus.
//
// libm's sin, cos, tan, atan2 and log are not correctly rounded, and glibc
// picks an FMA or a plain build of them at run time by CPU, so their last
// bits can differ between machines. The corpus promises the same bytes for
// the same seed everywhere, so everything that shapes its output uses these
// instead: range reduction and fixed polynomials in +, -, *, / and sqrt (all
// correctly rounded in IEEE 754, and the corpus is compiled with
// -ffp-contract=off and no auto-vectorization, see CMakeLists.txt). Accuracy
// about 1e-15 relative; speed close to libm's.
#pragma once

#include <bit>
#include <cmath>
#include <cstdint>

namespace vts_corpus::dm {

inline constexpr double kPi = 3.14159265358979323846;

namespace detail {
// pi/2 split so that k * kPio2Hi is exact for |k| < 2^20 (fdlibm's pio2_1, pio2_1t).
inline constexpr double kPio2Hi = 1.57079632673412561417e+00;
inline constexpr double kPio2Lo = 6.07710050650619224932e-11;

// sin and cos of r in [-pi/4, pi/4] (Taylor series to r^17 and r^18: the
// first terms left out are below 1e-19).
inline double sin_poly(double r) {
  const double r2 = r * r;
  double p = 1.0 / 355687428096000.0;  // 1/17!
  p = p * r2 - 1.0 / 1307674368000.0;  // 1/15!
  p = p * r2 + 1.0 / 6227020800.0;     // 1/13!
  p = p * r2 - 1.0 / 39916800.0;       // 1/11!
  p = p * r2 + 1.0 / 362880.0;         // 1/9!
  p = p * r2 - 1.0 / 5040.0;
  p = p * r2 + 1.0 / 120.0;
  p = p * r2 - 1.0 / 6.0;
  return r + r * r2 * p;
}
inline double cos_poly(double r) {
  const double r2 = r * r;
  double p = 1.0 / 6402373705728000.0;  // 1/18!
  p = p * r2 - 1.0 / 20922789888000.0;  // 1/16!
  p = p * r2 + 1.0 / 87178291200.0;     // 1/14!
  p = p * r2 - 1.0 / 479001600.0;       // 1/12!
  p = p * r2 + 1.0 / 3628800.0;         // 1/10!
  p = p * r2 - 1.0 / 40320.0;
  p = p * r2 + 1.0 / 720.0;
  p = p * r2 - 1.0 / 24.0;
  p = p * r2 + 0.5;
  return 1.0 - r2 * p;
}
// x = k pi/2 + r, |r| <= pi/4 (up to rounding); quadrant k mod 4.
inline int reduce(double x, double& r) {
  const double kf = x * (2.0 / kPi);
  const long long q = static_cast<long long>(kf + (kf >= 0 ? 0.5 : -0.5));  // round half away from 0
  const double k = static_cast<double>(q);
  r = (x - k * kPio2Hi) - k * kPio2Lo;
  return static_cast<int>(q & 3);  // two's complement: q mod 4, also for q < 0
}
// atan of t in [0, 2 - sqrt(3)]: the series to t^29 (next term below 1e-19).
inline double atan_poly(double t) {
  const double t2 = t * t;
  // atan t = t + t^3 p(t^2), p = sum_{k=1..14} (-1)^k t^(2k-2) / (2k + 1).
  double p = 1.0 / 29;
  for (int k = 13; k >= 1; --k) p = p * t2 + ((k % 2) ? -1.0 : 1.0) / (2 * k + 1);
  return t + t * t2 * p;
}
}  // namespace detail

inline double sin(double x) {
  double r;
  switch (detail::reduce(x, r)) {
    case 0: return detail::sin_poly(r);
    case 1: return detail::cos_poly(r);
    case 2: return -detail::sin_poly(r);
    default: return -detail::cos_poly(r);
  }
}

inline double cos(double x) {
  double r;
  switch (detail::reduce(x, r)) {
    case 0: return detail::cos_poly(r);
    case 1: return -detail::sin_poly(r);
    case 2: return -detail::cos_poly(r);
    default: return detail::sin_poly(r);
  }
}

inline double tan(double x) { return dm::sin(x) / dm::cos(x); }

// Both at once; no reduction needed for |x| <= pi/4 (column angles).
inline void sincos(double x, double& s, double& c) {
  if (std::abs(x) <= kPi / 4) {
    s = detail::sin_poly(x);
    c = detail::cos_poly(x);
  } else {
    s = dm::sin(x);
    c = dm::cos(x);
  }
}

// atan(t) for t >= 0.
inline double atan_pos(double t) {
  constexpr double kSqrt3 = 1.73205080756887729353;
  constexpr double kTan15 = 0.26794919243112270647;  // 2 - sqrt(3)
  if (t > 1.0) return kPi / 2 - atan_pos(1.0 / t);
  if (t > kTan15) return kPi / 6 + detail::atan_poly((t * kSqrt3 - 1.0) / (kSqrt3 + t));
  return detail::atan_poly(t);
}

inline double atan2(double y, double x) {
  if (x == 0.0 && y == 0.0) return 0.0;
  const double ay = std::abs(y), ax = std::abs(x);
  double a = ay <= ax ? atan_pos(ay / ax) : kPi / 2 - atan_pos(ax / ay);
  if (x < 0) a = kPi - a;
  return y < 0 ? -a : a;
}

inline double acos(double c) {
  c = c < -1.0 ? -1.0 : (c > 1.0 ? 1.0 : c);
  return dm::atan2(std::sqrt((1.0 - c) * (1.0 + c)), c);
}

// Natural log of x > 0: x = m 2^e with m in [sqrt(1/2), sqrt(2)), log m =
// 2 atanh((m - 1) / (m + 1)) by its series to z^23.
inline double log(double x) {
  if (!(x > 0)) return x == 0 ? -HUGE_VAL : NAN;
  int e = 0;
  double m;
  const auto bits = std::bit_cast<std::uint64_t>(x);
  if ((bits >> 52) == 0 || (bits >> 52) >= 0x7ff) {
    m = std::frexp(x, &e);  // subnormal or infinite: rare
  } else {  // m in [0.5, 1), x = m 2^e: the exponent field swapped, exact
    e = static_cast<int>(bits >> 52) - 1022;
    m = std::bit_cast<double>((bits & 0x000FFFFFFFFFFFFFull) | 0x3FE0000000000000ull);
  }
  if (m < 0.70710678118654752440) {
    m *= 2.0;
    e -= 1;
  }
  const double z = (m - 1.0) / (m + 1.0), z2 = z * z;
  double p = 1.0 / 23;
  for (int k = 21; k >= 3; k -= 2) p = p * z2 + 1.0 / k;
  const double log_m = 2.0 * (z + z * z2 * p);
  constexpr double kLn2Hi = 6.93147180369123816490e-01, kLn2Lo = 1.90821492927058770002e-10;  // fdlibm
  return (e * kLn2Hi + log_m) + e * kLn2Lo;
}

inline double deg_to_rad(double deg) { return deg * (kPi / 180.0); }
inline double rad_to_deg(double rad) { return rad * (180.0 / kPi); }

}  // namespace vts_corpus::dm
