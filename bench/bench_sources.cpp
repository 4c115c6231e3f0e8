// Profiles per second of the raster emulator and the Embree reference on the
// same built-in cells and the same rays, N = 512. items_per_second = profiles.
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <memory>
#include <string>

#include "render/raster_source.h"
#include "sensor/cell.h"
#include "sensor/reference_source.h"

namespace {

// With ->Threads(k) every thread builds its own source (its own OSMesa
// context or Embree scene), as a multi-threaded exporter would.
template <class Make>
void run(benchmark::State& state, const std::string& cell_name, Make make) {
  auto cell = vts::builtin_cell(cell_name);
  cell->scanner.points = 512;
  auto source = make(cell->scanner, cell->mesh());
  vts::Profile profile;
  std::int64_t i = 37 * state.thread_index();
  for (auto _ : state) {
    source->scan(cell->path.pose_at(i % 200), profile);
    benchmark::DoNotOptimize(profile.range_mm.data());
    ++i;
  }
  state.SetItemsProcessed(state.iterations());
  state.counters["triangles"] = benchmark::Counter(static_cast<double>(cell->mesh().triangle_count()),
                                                   benchmark::Counter::kAvgThreads);
}

void BM_Raster(benchmark::State& state, const std::string& cell) {
  run(state, cell, [](const auto& d, const auto& m) { return vts::make_raster_source(d, m); });
}
void BM_Reference(benchmark::State& state, const std::string& cell) {
  run(state, cell, [](const auto& d, const auto& m) { return vts::make_reference_source(d, m); });
}

const int registered = [] {
  for (const char* cell : {"fillet", "corner", "lap", "butt", "vgroove", "static-B"}) {
    for (int threads : {1, 2}) {
      benchmark::RegisterBenchmark((std::string("BM_Raster/") + cell).c_str(), BM_Raster, cell)
          ->Unit(benchmark::kMicrosecond)->Threads(threads)->UseRealTime();
      benchmark::RegisterBenchmark((std::string("BM_Reference/") + cell).c_str(), BM_Reference, cell)
          ->Unit(benchmark::kMicrosecond)->Threads(threads)->UseRealTime();
    }
  }
  return 0;
}();

}  // namespace

int main(int argc, char** argv) {
  ::setenv("LP_NUM_THREADS", "0", 0);  // as vts does: fastest for one-row targets
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
