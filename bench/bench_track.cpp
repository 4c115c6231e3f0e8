// Profiles per second of the seam tracker on ideal 512-point profiles of the
// built-in cells (generated once with the Embree reference along each cell's
// path). items_per_second = profiles. Target: at most 5 us per profile.
#include <benchmark/benchmark.h>

#include <string>
#include <vector>

#include "sensor/cell.h"
#include "sensor/reference_source.h"
#include "tracker/tracker.h"

namespace {

namespace tk = vts::tracker;

void BM_Track(benchmark::State& state, const std::string& cell_name, tk::JointType joint) {
  auto cell = vts::builtin_cell(cell_name);
  cell->scanner.points = 512;
  auto source = vts::make_reference_source(cell->scanner, cell->mesh());
  std::vector<vts::Profile> profiles(64);
  for (std::size_t i = 0; i < profiles.size(); ++i)
    source->scan(cell->path.pose_at(static_cast<std::int64_t>(i)), profiles[i]);

  tk::TrackerParams params;
  params.joint = joint;
  if (joint == tk::JointType::Lap) params.lap.upper_thickness_mm = cell->workpieces.front().params.thickness_mm;
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
                                                         {"static-B", tk::JointType::Fillet}};
  for (const auto& [cell, joint] : cases) {
    const std::string label = std::string(cell) == "static-B" ? "static-B" : std::string(to_string(joint));
    const std::string name = "BM_Track/" + label;
    benchmark::RegisterBenchmark(name.c_str(), BM_Track, std::string(cell), joint)->Unit(benchmark::kMicrosecond);
  }
  return 0;
}();

}  // namespace
