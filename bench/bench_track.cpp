// Profiles per second of the seam tracker on ideal 512-point profiles of the
// built-in cells (generated once with the Embree reference along each cell's
// path; the groove cells too, vgroove-thick read with its fill). items_per_second = profiles. Target: at most 5 us per profile.
// BM_Track2048, BM_TrackNoisy2048: the same cells scanned with 2,048 columns
// over the same fan (a current profile sensor's resolution). Target: at most
// 20 us per profile (issue 24 point 3).
// BM_TrackNoisy: the same profiles through the error model (mspot, matte
// steel, seed 1), with surface_tol_mm set from the sensor's resolution as
// tests/sensor/tracker_noisy_test.cpp does.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "sensor/cell.h"
#include "sensor/error_model.h"
#include "sensor/reference_source.h"
#include "tracker/tracker.h"

namespace {

namespace tk = vts::tracker;

void BM_Track(benchmark::State& state, const std::string& cell_name, tk::JointType joint, bool noisy, int points) {
  auto cell = vts::builtin_cell(cell_name);
  cell->scanner.points = points;
  auto source = vts::make_reference_source(cell->scanner, cell->mesh());
  std::vector<vts::Profile> profiles(64);
  vts::ScanState noise;
  noise.seed = 1;
  double range_sum = 0.0;
  int range_count = 0;
  for (std::size_t i = 0; i < profiles.size(); ++i) {
    vts::Profile ideal;
    source->scan(cell->path.pose_at(static_cast<std::int64_t>(i)), ideal);
    ideal.index = static_cast<std::int64_t>(i);
    for (int k = 0; k < ideal.size(); ++k)
      if (ideal.valid[k]) range_sum += ideal.z_mm[k], ++range_count;
    if (noisy)
      vts::apply_error_model(cell->scanner, ideal, noise, profiles[i]);
    else
      profiles[i] = ideal;
  }

  tk::TrackerParams params;
  params.joint = joint;
  if (noisy && range_count > 0) {
    // 3 sigma of one point at the mean range: speckle and quantization.
    const double z = range_sum / range_count;
    const double noise_mm = vts::depth_noise_mm(cell->scanner, z), step_mm = vts::depth_step_mm(cell->scanner, z);
    params.surface_tol_mm = std::max(0.02, 3.0 * std::sqrt(noise_mm * noise_mm + step_mm * step_mm / 12.0));
  }
  if (joint == tk::JointType::Lap) params.lap.upper_thickness_mm = cell->workpieces.front().params.thickness_mm;
  params.groove.vgroove_fill = cell->workpieces.front().params.passes > 0;  // beads laid: --fill
  tk::Tracker tracker(params);
  tk::TrackResult result;
  std::size_t i = 0, ok = 0;
  for (auto _ : state) {
    const vts::Profile& p = profiles[i++ % profiles.size()];
    tracker.track(tk::ProfileView{p.y_mm, p.z_mm, p.valid}, result);
    ok += result.status == tk::TrackStatus::Ok;
    benchmark::DoNotOptimize(result.track_point);
  }
  state.SetItemsProcessed(state.iterations());
  state.counters["ok_fraction"] = static_cast<double>(ok) / static_cast<double>(state.iterations());
}

const int registered = [] {
  const std::pair<const char*, tk::JointType> cases[] = {{"fillet", tk::JointType::Fillet},
                                                         {"corner", tk::JointType::Corner},
                                                         {"lap", tk::JointType::Lap},
                                                         {"butt", tk::JointType::Butt},
                                                         {"vgroove", tk::JointType::VGroove},
                                                         {"static-B", tk::JointType::Fillet},
                                                         {"vgroove-thick", tk::JointType::VGroove},
                                                         {"bevel", tk::JointType::Bevel},
                                                         {"ugroove", tk::JointType::UGroove},
                                                         {"jgroove", tk::JointType::JGroove}};
  for (const auto& [cell, joint] : cases) {
    const std::string label = cell;
    for (int points : {512, 2048})
      for (bool noisy : {false, true}) {
        const std::string size = points == 512 ? "" : std::to_string(points);
        const std::string name = (noisy ? "BM_TrackNoisy" : "BM_Track") + size + "/" + label;
        benchmark::RegisterBenchmark(name.c_str(), BM_Track, std::string(cell), joint, noisy, points)
            ->Unit(benchmark::kMicrosecond);
      }
  }
  return 0;
}();

}  // namespace
