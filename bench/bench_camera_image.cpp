// BM_CameraImage/<mode>: the v-groove cell at 100 mm scanned through the one
// scan pipeline (pipeline/scan_session.h), 64 profiles a batch, in each
// mode: `geometric` (the error model: the peer), `image-roi64` (the camera
// image with a 64-row region of interest around the stripe) and
// `image-full` (the whole 1280 x 1024 frame). items_per_second = profiles.
#include <benchmark/benchmark.h>

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "pipeline/scan_session.h"
#include "sensor/cell.h"
#include "sensor/error_model.h"

namespace {

void BM_CameraImage(benchmark::State& state, const std::string& mode) {
  auto cell = vts::builtin_cell("vgroove");
  if (!cell) throw std::runtime_error("vts-bench: no built-in cell vgroove");
  vts::ScannerDesc d = cell->scanner;
  if (mode != "geometric") d.camera_image = true;
  if (mode == "image-roi64") {
    // 64 rows from 8 above the plate tops' row (the groove is 12 mm deep
    // at 100 mm: about 45 rows).
    const vts::CameraModel cam = vts::camera_model(d);
    const double top = vts::image_row_px(cam, 100.0 - 12.0) + 0.5 * (d.image_height_px - 1);
    d.image_roi_first_row = static_cast<int>(std::floor(top)) - 8;
    d.image_roi_rows = 64;
  }
  vts::ScanSession session(d, cell->mesh(), vts::SourceKind::Raster, false, 1);
  std::vector<vts::ScanRequest> requests(64);
  vts::ScanResults results;
  std::int64_t next = 0;
  for (auto _ : state) {
    for (auto& r : requests) {
      r.world_from_sensor = cell->path.pose_at(next % 200);
      r.index = next++;
    }
    session.scan(requests, results);
    benchmark::DoNotOptimize(results.output()[0].valid.data());
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * 64);
}

BENCHMARK_CAPTURE(BM_CameraImage, geometric, std::string("geometric"))->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_CameraImage, image_roi64, std::string("image-roi64"))->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_CameraImage, image_full, std::string("image-full"))->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
