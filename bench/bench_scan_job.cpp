// vts scan end to end (issue 24): run_scan_job over the v-groove's seam with
// the raster source, the error model and the EXR written to a file, as
// `vts scan --cell vgroove --step S --profiles P [--sensor lps-2048-short]
// [--compression C] --out FILE` does, on the threads the thread limit allows
// (VTS_THREADS, else every hardware thread). items_per_second = profiles;
// bytes_per_profile = the file's size / profiles.
//
// BM_ScanJob/<columns>/<compression>: 512 columns (mspot) or 2,048
// (lps-2048-short), every lossless compression. BM_ScanJob/<columns>/discard:
// the same job into a sink that drops the batches: the scan and error model
// alone, the peer the EXR's cost is read against.
//
// Each iteration is a whole job (the source built, the file created,
// written and renamed; its removal is not timed). The path runs along the seam, so every
// profile hits the part (the default step leaves a long scan off it, where
// the zeros compress fast).
#include <benchmark/benchmark.h>
#include <unistd.h>

#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>

#include "pipeline/scan_job.h"
#include "pipeline/sinks.h"
#include "sensor/cell.h"
#include "sensor/presets.h"

namespace {

namespace fs = std::filesystem;

vts::ScanSpec seam_spec(int columns) {
  auto cell = vts::builtin_cell("vgroove");
  if (!cell) throw std::runtime_error("vts-bench: no built-in cell vgroove");
  if (columns == 2048) {
    const auto preset = vts::sensor_preset("lps-2048-short");
    if (!preset) throw std::runtime_error("vts-bench: no sensor lps-2048-short");
    vts::set_sensor_fields(cell->scanner, *preset);
  } else {
    cell->scanner.points = columns;
  }
  // 150 mm of the 200 mm seam from the path's start at 20 mm.
  cell->path.profiles = columns >= 2048 ? 4096 : 16384;
  cell->path.step_mm = 150.0 / cell->path.profiles;
  vts::ScanSpec spec;
  spec.cell = std::move(*cell);
  return spec;
}

// compression: a name of vts::exr_compression_names(), or "discard".
void BM_ScanJob(benchmark::State& state, int columns, const std::string& compression) {
  const vts::ScanSpec spec = seam_spec(columns);
  const fs::path file = fs::temp_directory_path() / ("vts-bench-scan-" + std::to_string(::getpid()) + ".exr");
  const bool discard = compression == "discard";
  const auto method = vts::exr_compression_from_string(compression);
  if (!discard && !method) throw std::runtime_error("vts-bench: no compression " + compression);
  double bytes = 0.0;
  for (auto _ : state) {
    std::unique_ptr<vts::ScanSink> sink;
    if (discard)
      sink = std::make_unique<vts::CallbackSink>([](const vts::ScanBatch& b) { benchmark::DoNotOptimize(b.first); });
    else
      sink = std::make_unique<vts::ExrSink>(file, *method);
    const vts::ScanStats stats = vts::run_scan_job(spec, *sink);
    benchmark::DoNotOptimize(stats.valid);
    if (!discard) {
      // Not timed: deleting a file of 270 MB from the page cache costs the
      // kernel about as much as a tenth of writing it, and is no part of a scan.
      state.PauseTiming();
      bytes = static_cast<double>(fs::file_size(file));
      fs::remove(file);
      state.ResumeTiming();
    }
  }
  state.SetItemsProcessed(state.iterations() * spec.cell.path.profiles);
  state.counters["bytes_per_profile"] = bytes / spec.cell.path.profiles;
}

const int registered = [] {
  for (int columns : {512, 2048}) {
    std::vector<std::string> methods = vts::exr_compression_names();
    methods.push_back("discard");
    for (const std::string& c : methods)
      benchmark::RegisterBenchmark(("BM_ScanJob/" + std::to_string(columns) + "/" + c).c_str(), BM_ScanJob,
                                   columns, c)
          ->Unit(benchmark::kMillisecond)->UseRealTime();
  }
  return 0;
}();

}  // namespace
