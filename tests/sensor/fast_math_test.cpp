// sensor/fast_math.h against libm: the error model's draws depend on these
// being what they claim (exact, or within a few units in the last place).
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <random>

#include "sensor/fast_math.h"

using namespace vts;

TEST_CASE("fast math: unit_from_hash is the top 53 bits of the hash times 2^-53 exactly", "[fast_math]") {
  std::mt19937_64 rng(11);
  for (int i = 0; i < 200000; ++i) {
    const std::uint64_t h = rng();
    REQUIRE(unit_from_hash(h) == static_cast<double>(h >> 11) * 0x1.0p-53);
  }
  CHECK(unit_from_hash(0) == 0.0);
  CHECK(unit_from_hash(~std::uint64_t{0}) == 1.0 - 0x1.0p-53);
}

TEST_CASE("fast math: cos_turns of u is cos of 2 pi u within 4e-16", "[fast_math]") {
  std::mt19937_64 rng(12);
  double worst = 0.0;
  for (int i = 0; i < 200000; ++i) {
    const double u = unit_from_hash(rng());
    // The reference in long double, so that libm's rounding of 2 pi u does
    // not count against cos_turns.
    const double ref = static_cast<double>(std::cos(2.0L * std::numbers::pi_v<long double> * u));
    worst = std::max(worst, std::abs(cos_turns(u) - ref));
  }
  // Quadrant boundaries, where the reduction switches between sin and cos.
  for (double u : {0.0, 0.125, 0.25, 0.375, 0.5, 0.625, 0.75, 0.875, 1.0 - 0x1.0p-53}) {
    const double ref = static_cast<double>(std::cos(2.0L * std::numbers::pi_v<long double> * u));
    worst = std::max(worst, std::abs(cos_turns(u) - ref));
    for (double e : {0x1.0p-53, -0x1.0p-53}) {
      const double v = u + e;
      if (v < 0.0 || v >= 1.0) continue;
      const double r = static_cast<double>(std::cos(2.0L * std::numbers::pi_v<long double> * v));
      worst = std::max(worst, std::abs(cos_turns(v) - r));
    }
  }
  CHECK(cos_turns(0.0) == 1.0);
  CHECK(cos_turns(0.5) == -1.0);
  INFO("worst |cos_turns - cos| " << worst);
  CHECK(worst < 4e-16);
}

TEST_CASE("fast math: log_unit is log within 3e-16 relative on the unit interval", "[fast_math]") {
  std::mt19937_64 rng(13);
  double worst = 0.0;
  auto check = [&](double x) {
    const double ref = static_cast<double>(std::log(static_cast<long double>(x)));
    worst = std::max(worst, std::abs(log_unit(x) - ref) / std::max(1.0, std::abs(ref)));
  };
  for (int i = 0; i < 200000; ++i) check(1.0 - unit_from_hash(rng()));  // as the error model draws
  for (int k = 0; k <= 1022; ++k) check(std::ldexp(1.0, -k));          // every binade's start
  for (double x : {1.0, 1.0 - 0x1.0p-53, 0.5 + 0x1.0p-53, std::numbers::sqrt2 / 2, 0x1.0p-53,
                   std::numeric_limits<double>::min()})
    check(x);
  CHECK(log_unit(1.0) == 0.0);
  INFO("worst relative |log_unit - log| " << worst);
  CHECK(worst < 3e-16);
}

TEST_CASE("fast math: round_half_away is std::round", "[fast_math]") {
  std::mt19937_64 rng(14);
  std::uniform_real_distribution<double> any(-1e6, 1e6);
  for (int i = 0; i < 200000; ++i) {
    const double x = any(rng);
    REQUIRE(round_half_away(x) == std::round(x));
  }
  for (double x : {0.5, -0.5, 1.5, -1.5, 2.5, -2.5, 0.49999999999999994, -0.49999999999999994, 0.0, -0.0,
                   4503599627370495.5, 4503599627370497.0, 1e300, -1e300,
                   std::numeric_limits<double>::infinity()})
    CHECK(round_half_away(x) == std::round(x));
  CHECK(std::isnan(round_half_away(std::numeric_limits<double>::quiet_NaN())));
}
