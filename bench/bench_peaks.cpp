// Frames per second of the stripe peak detector (stripe/peaks.h) on a
// synthetic 16-bit camera image: a Gaussian stripe (sigma 2 px, 60 % of full
// scale, saturated in one column in eight) wandering over the rows, a
// reflection 20 rows below it in one column in ten, 0-40 DN of background
// noise. 1280x64 is a region of interest around the stripe, 1280x1024 the
// full frame. items_per_second = frames. Target (issue 22): well under 20 ms
// a full frame on one core.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "stripe/peaks.h"

namespace {

namespace st = vts::stripe;

std::vector<std::uint16_t> stripe_image(int width, int height) {
  std::vector<std::uint16_t> px(static_cast<std::size_t>(width) * height);
  std::mt19937 rng(1);
  std::uniform_int_distribution<int> noise(0, 40);
  for (auto& v : px) v = static_cast<std::uint16_t>(noise(rng));
  auto add = [&](int c, double mu, double sigma, double a) {
    for (int r = std::max(0, int(mu - 6 * sigma)); r < std::min(height, int(mu + 6 * sigma) + 1); ++r) {
      auto& v = px[static_cast<std::size_t>(r) * width + c];
      v = static_cast<std::uint16_t>(std::min(65535.0, v + a * std::exp(-0.5 * std::pow((r - mu) / sigma, 2))));
    }
  };
  for (int c = 0; c < width; ++c) {
    const double mu = height / 2.0 + height / 8.0 * std::sin(2.0 * M_PI * c / 640.0) - 10.0 * (height <= 64);
    add(c, mu, 2.0, c % 8 == 0 ? 100000.0 : 0.6 * 65535);
    if (c % 10 == 0) add(c, mu + 20.0, 2.5, 0.8 * 65535);
  }
  return px;
}

void BM_Peaks(benchmark::State& state, int width, int height, st::PeakPolicy policy) {
  const auto px = stripe_image(width, height);
  const st::ImageView view{px.data(), width, height, width, 16};
  st::PeakParams params;
  params.policy = policy;
  st::PeakResult result;
  for (auto _ : state) {
    st::detect_peaks(view, params, result);
    benchmark::DoNotOptimize(result.chosen.data());
  }
  state.SetItemsProcessed(state.iterations());
  int found = 0;
  for (int c = 0; c < width; ++c) found += result.chosen[c] >= 0;
  state.counters["peaks_per_column"] = static_cast<double>(result.peaks.size()) / width;
  state.counters["found_fraction"] = static_cast<double>(found) / width;
}

const int registered = [] {
  for (const auto& [w, h] : {std::pair{1280, 64}, std::pair{1280, 1024}})
    for (auto policy : {st::PeakPolicy::strongest, st::PeakPolicy::continuous}) {
      const std::string name = "BM_Peaks/" + std::to_string(w) + "x" + std::to_string(h) + "/" +
                               std::string(st::to_string(policy));
      benchmark::RegisterBenchmark(name.c_str(), BM_Peaks, w, h, policy)->Unit(benchmark::kMicrosecond);
    }
  return 0;
}();

}  // namespace
