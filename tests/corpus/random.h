// Deterministic random numbers for the test corpus.
//
// The std distributions are implementation-defined (libstdc++ and libc++
// give different normals for the same engine), so every transform from bits
// to numbers is written out here: xoshiro256** seeded through splitmix64,
// 53-bit uniforms, and Marsaglia's polar method for normals with dm::log
// (dmath.h), so the same seed gives the same numbers on every machine.
#pragma once

#include "dmath.h"

#include <cmath>
#include <cstdint>
#include <string_view>

namespace vts_corpus {

inline std::uint64_t splitmix64(std::uint64_t& state) {
  std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

// Combines two 64-bit values into a well-mixed one (for stream keys).
inline std::uint64_t mix_seed(std::uint64_t a, std::uint64_t b) {
  std::uint64_t s = a ^ (b * 0xD1B54A32D192ED03ull + 0x8CB92BA72F3D8DD7ull);
  splitmix64(s);
  return splitmix64(s);
}

// FNV-1a: turns a stream name into a key, so streams are named in the code.
constexpr std::uint64_t name_key(std::string_view name) {
  std::uint64_t h = 0xCBF29CE484222325ull;
  for (char c : name) h = (h ^ static_cast<unsigned char>(c)) * 0x100000001B3ull;
  return h;
}

class Rng {
 public:
  explicit Rng(std::uint64_t seed) {
    for (auto& w : s_) w = splitmix64(seed);
  }
  // A named, independent stream of (seed, key...): changing what one stream
  // draws (e.g. the noise level) leaves the others' draws unchanged.
  static Rng stream(std::uint64_t seed, std::string_view name, std::uint64_t index = 0) {
    return Rng(mix_seed(mix_seed(seed, name_key(name)), index));
  }

  std::uint64_t next() {
    const std::uint64_t result = rotl(s_[1] * 5, 7) * 9;
    const std::uint64_t t = s_[1] << 17;
    s_[2] ^= s_[0];
    s_[3] ^= s_[1];
    s_[1] ^= s_[2];
    s_[0] ^= s_[3];
    s_[2] ^= t;
    s_[3] = rotl(s_[3], 45);
    return result;
  }
  // [0, 1) with 53 random bits.
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  // Integer in [lo, hi] (inclusive). Multiply-shift: bias below 2^-32, fine here.
  int uniform_int(int lo, int hi) {
    const std::uint64_t span = static_cast<std::uint64_t>(static_cast<std::int64_t>(hi) - lo + 1);
    return lo + static_cast<int>(((next() >> 32) * span) >> 32);
  }
  bool chance(double p) { return uniform() < p; }
  double sign() { return (next() >> 63) ? 1.0 : -1.0; }
  // Standard normal, Marsaglia polar method (uses only log and sqrt).
  double normal() {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    double u, v, s;
    do {
      u = 2.0 * uniform() - 1.0;
      v = 2.0 * uniform() - 1.0;
      s = u * u + v * v;
    } while (s >= 1.0 || s == 0.0);
    const double f = std::sqrt(-2.0 * dm::log(s) / s);
    spare_ = v * f;
    has_spare_ = true;
    return u * f;
  }

 private:
  static std::uint64_t rotl(std::uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
  std::uint64_t s_[4];
  double spare_ = 0.0;
  bool has_spare_ = false;
};

}  // namespace vts_corpus
