// Profiles per second of the raster emulator and the Embree reference on the
// same built-in cells and the same rays, N = 512. items_per_second = profiles.
//
// Cells: the single-joint built-in cells (328-412 triangles) and fillet-1m
// (the built-in fillet, 600 mm long, meshed into about a million triangles).
//
// BM_Raster / BM_Reference: the full pipeline as an exporter runs it: batches
// of kBatch poses along the cell's path through the source (scan_batch: the
// raster draws a whole pass at once, the reference shoots 16-ray packets),
// the camera-shadow test, then the error model on every profile. With
// ->Threads(k) every benchmark thread owns one source (its own OSMesa context
// or Embree scene, scanning on that thread only) and its own ScanState.
// BM_RasterUnmerged/fillet-1m: the raster with its planar merge off
// (sensor/planar_merge.h), so every triangle is sliced, joined and
// shadow-tested as given: the cost on a mesh with no flat regions.
// saddle-1m (the pipe saddle, about a million triangles, curved: nothing
// to merge but its three end discs): BM_Raster, BM_RasterUnmerged and
// BM_Reference with the sensor on the bisector at 100 mm at 400 stations
// round the seam (sensor/saddle.h) instead of a straight path.
// BM_RasterSingle / BM_ReferenceSingle: one scan() per profile, no error model
// (what the viewer's sensor thread does at a sensor's rate).
// BM_RasterBatch / BM_ReferenceBatch: one source with its default threads (the
// thread limit, common/parallel.h: VTS_THREADS or every hardware thread)
// scanning batches of 512 poses, no error model: how vts scan splits a batch.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "render/raster_source.h"
#include "sensor/cell.h"
#include "sensor/error_model.h"
#include "sensor/reference_source.h"
#include "sensor/saddle.h"
#include "sensor/workpiece.h"

namespace {

constexpr int kBatch = 256;

std::unique_ptr<vts::ProfileSource> make_source(bool raster, const vts::Cell& cell, bool merge_planar = true) {
  if (raster)
    return vts::make_raster_source(cell.scanner, cell.mesh(), {.threads = 1, .merge_planar = merge_planar});
  return vts::make_reference_source(cell.scanner, cell.mesh(), 1);
}

vts::Cell bench_cell(const std::string& name) {
  auto cell = vts::builtin_cell(name);
  if (!cell) throw std::runtime_error("vts-bench: no built-in cell " + name);
  cell->scanner.points = 512;
  return *cell;
}

// The poses a benchmark cycles through: the cell's path, or round a saddle's seam.
constexpr int kPathPoses = 400;
std::vector<vts::Pose> bench_poses(const vts::Cell& cell) {
  std::vector<vts::Pose> poses;
  const vts::Workpiece& w = cell.workpieces.front();
  for (int k = 0; k < kPathPoses; ++k)
    poses.push_back(w.saddle ? vts::saddle_sensor_pose(*w.saddle, w.world_from_joint, 2.0 * std::numbers::pi * k / kPathPoses, 100.0)
                             : cell.path.pose_at(k));
  return poses;
}

void run_pipeline(benchmark::State& state, bool raster, const vts::Cell& cell, bool merge_planar) {
  const auto source = make_source(raster, cell, merge_planar);
  const std::vector<vts::Pose> path = bench_poses(cell);
  std::vector<vts::Pose> poses(kBatch);
  std::vector<vts::Profile> ideal(kBatch);
  vts::Profile measured;
  vts::ScanState scan_state;
  scan_state.seed = 7;
  std::int64_t i = 1000 * state.thread_index();
  for (auto _ : state) {
    for (int k = 0; k < kBatch; ++k) poses[k] = path[(i + k) % kPathPoses];
    source->scan_batch(poses, ideal);
    for (int k = 0; k < kBatch; ++k) {
      ideal[k].index = i + k;
      vts::apply_error_model(cell.scanner, ideal[k], scan_state, measured);
      benchmark::DoNotOptimize(measured.z_mm.data());
    }
    i += kBatch;
  }
  state.SetItemsProcessed(state.iterations() * kBatch);
  state.counters["triangles"] = benchmark::Counter(static_cast<double>(cell.mesh().triangle_count()),
                                                   benchmark::Counter::kAvgThreads);
  state.counters["columns"] = benchmark::Counter(cell.scanner.points, benchmark::Counter::kAvgThreads);
}

void BM_Pipeline(benchmark::State& state, bool raster, const std::string& cell_name, bool merge_planar) {
  run_pipeline(state, raster, bench_cell(cell_name), merge_planar);
}

// How cost grows (issue 24 point 5), one thread. BM_Columns: the v-groove
// with N columns (the mspot sensor's fan, N = 256 .. 4,096). BM_Triangles:
// the built-in fillet 600 mm long, every face a grid of about cell_mm x
// cell_mm quads (as fillet-1m), cell_mm chosen for the fewest triangles not
// below T (10^3 .. 10^7; the counter "triangles" holds the count), the raster with
// its planar merge off (every triangle sliced as given, as on a curved
// part) and the reference; the default path, N = 512.
void BM_Columns(benchmark::State& state, bool raster, int columns) {
  vts::Cell cell = bench_cell("vgroove");
  cell.scanner.points = columns;
  run_pipeline(state, raster, cell, true);
}

void BM_Triangles(benchmark::State& state, bool raster, double triangles) {
  vts::JointParams p = vts::default_params(vts::JointType::Fillet);
  p.length_mm = 600.0;
  // The grid (and the cuts along the seam) whose count comes nearest above
  // `triangles`, by bisection on the cell size.
  const vts::Workpiece plain = vts::build_workpiece(vts::JointType::Fillet, p);
  auto count = [&](double cell_mm) {
    std::int64_t n = 0;
    for (const vts::Plate& plate : plain.plates) n += vts::plate_triangle_count(plate, cell_mm, cell_mm);
    return static_cast<double>(n);
  };
  double lo = 0.01, hi = 1000.0;
  for (int i = 0; i < 60; ++i) {
    const double mid = std::sqrt(lo * hi);
    (count(mid) >= triangles ? lo : hi) = mid;
  }
  p.cell_mm = p.segment_mm = lo;
  vts::Cell cell;
  cell.name = "fillet-dense";
  cell.workpieces.push_back(vts::build_workpiece(vts::JointType::Fillet, p));
  cell.path = vts::default_path(cell.workpieces.front(), 100.0);
  cell.scanner.points = 512;
  run_pipeline(state, raster, cell, false);
}

void BM_Single(benchmark::State& state, bool raster, const std::string& cell_name) {
  const vts::Cell cell = bench_cell(cell_name);
  const auto source = make_source(raster, cell);
  vts::Profile profile;
  std::int64_t i = 37 * state.thread_index();
  for (auto _ : state) {
    source->scan(cell.path.pose_at(i % 400), profile);
    benchmark::DoNotOptimize(profile.range_mm.data());
    ++i;
  }
  state.SetItemsProcessed(state.iterations());
}

void BM_Batch(benchmark::State& state, bool raster, const std::string& cell_name) {
  const vts::Cell cell = bench_cell(cell_name);
  const auto source =
      raster ? vts::make_raster_source(cell.scanner, cell.mesh()) : vts::make_reference_source(cell.scanner, cell.mesh());
  constexpr int kJobBatch = 512;
  std::vector<vts::Pose> poses(kJobBatch);
  std::vector<vts::Profile> ideal(kJobBatch);
  std::int64_t i = 0;
  for (auto _ : state) {
    for (int k = 0; k < kJobBatch; ++k) poses[k] = cell.path.pose_at((i + k) % 400);
    source->scan_batch(poses, ideal);
    benchmark::DoNotOptimize(ideal.back().range_mm.data());
    i += kJobBatch;
  }
  state.SetItemsProcessed(state.iterations() * kJobBatch);
}

// The error model alone on a cell's ideal profiles (computed once).
void BM_ErrorModel(benchmark::State& state, const std::string& cell_name) {
  const vts::Cell cell = bench_cell(cell_name);
  const auto source = make_source(false, cell);
  std::vector<vts::Pose> poses(kBatch);
  std::vector<vts::Profile> ideal(kBatch);
  for (int k = 0; k < kBatch; ++k) poses[k] = cell.path.pose_at(k % 400);
  source->scan_batch(poses, ideal);
  vts::Profile measured;
  vts::ScanState scan_state;
  scan_state.seed = 7;
  std::int64_t i = 0;
  for (auto _ : state) {
    vts::Profile& p = ideal[i % kBatch];
    p.index = i;
    vts::apply_error_model(cell.scanner, p, scan_state, measured);
    benchmark::DoNotOptimize(measured.z_mm.data());
    ++i;
  }
  state.SetItemsProcessed(state.iterations());
  state.counters["lit"] = benchmark::Counter(static_cast<double>(scan_state.lit) / scan_state.profiles);
}

const int registered = [] {
  for (const char* cell : {"fillet", "static-B"})
    benchmark::RegisterBenchmark((std::string("BM_ErrorModel/") + cell).c_str(), BM_ErrorModel, std::string(cell))
        ->Unit(benchmark::kMicrosecond);
  for (const char* cell : {"fillet", "corner", "lap", "butt", "vgroove", "static-B", "fillet-1m", "saddle-1m"}) {
    for (int threads : {1, 2}) {
      for (bool raster : {true, false}) {
        const std::string name = std::string(raster ? "BM_Raster/" : "BM_Reference/") + cell;
        benchmark::RegisterBenchmark(name.c_str(), BM_Pipeline, raster, std::string(cell), true)
            ->Unit(benchmark::kMicrosecond)->Threads(threads)->UseRealTime();
      }
    }
  }
  // The raster source with the planar merge off: every one of fillet-1m's
  // triangles sliced as given, as on a mesh without flat regions.
  // saddle-1m: a curved mesh, where the merge finds nothing but the end discs.
  for (const char* cell : {"fillet-1m", "saddle-1m"})
    for (int threads : {1, 2})
      benchmark::RegisterBenchmark((std::string("BM_RasterUnmerged/") + cell).c_str(), BM_Pipeline, true,
                                   std::string(cell), false)
          ->Unit(benchmark::kMicrosecond)->Threads(threads)->UseRealTime();
  for (bool raster : {true, false})
    benchmark::RegisterBenchmark(raster ? "BM_RasterSingle/static-B" : "BM_ReferenceSingle/static-B",
                                 BM_Single, raster, std::string("static-B"))
        ->Unit(benchmark::kMicrosecond)->UseRealTime();
  for (int columns : {256, 512, 1024, 2048, 4096})
    for (bool raster : {true, false})
      benchmark::RegisterBenchmark(
          ((raster ? "BM_Columns/raster/" : "BM_Columns/reference/") + std::to_string(columns)).c_str(), BM_Columns,
          raster, columns)
          ->Unit(benchmark::kMicrosecond)->UseRealTime();
  for (int exponent = 3; exponent <= 7; ++exponent)
    for (bool raster : {true, false})
      benchmark::RegisterBenchmark(
          ((raster ? "BM_Triangles/raster-unmerged/1e" : "BM_Triangles/reference/1e") + std::to_string(exponent))
              .c_str(),
          BM_Triangles, raster, std::pow(10.0, exponent))
          ->Unit(benchmark::kMicrosecond)->UseRealTime();
  for (const char* cell : {"static-B", "fillet-1m"})
    for (bool raster : {true, false})
      benchmark::RegisterBenchmark((std::string(raster ? "BM_RasterBatch/" : "BM_ReferenceBatch/") + cell).c_str(),
                                   BM_Batch, raster, std::string(cell))
          ->Unit(benchmark::kMicrosecond)->UseRealTime();
  return 0;
}();

}  // namespace

int main(int argc, char** argv) {
  ::setenv("LP_NUM_THREADS", "0", 0);  // as vts does: fastest for our targets
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
