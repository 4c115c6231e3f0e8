#include "viewer/sim_view.h"

#include <cstdio>
#include <numbers>

#include "pipeline/sim_run.h"
#include "sensor/presets.h"

namespace vts::viewer {

SimView run_sim_for_view(std::uint64_t seed, const std::string& sensor, const std::string& material, bool ideal) {
  SimSpec spec;
  if (!sensor.empty()) set_sensor_fields(spec.scanner, *sensor_preset(sensor));
  if (!material.empty()) apply_material(spec.scanner, material);
  spec.scanner.ideal = ideal;
  spec.seed = spec.cell.seed = seed;
  spec.cell.standoff_mm = sim_standoff_mm(spec.scanner);
  spec.source = SourceKind::Reference;
  SimRun run = run_sim(spec);
  const SimCell& sim = run.cell;
  const SimCellParams& params = spec.cell;

  auto cell = std::make_shared<Cell>();
  cell->name = "sim-box";
  cell->scanner = run.scanner;
  const double h = 0.5 * params.box_side_mm, ph = 0.5 * params.plate_side_mm;
  auto block = [](double x0, double x1, double y0, double y1, double z0, double z1) {
    return Plate{{{y0, z0}, {y1, z0}, {y1, z1}, {y0, z1}}, x0, x1};
  };
  // Seam 1's workpiece: the joint frame at seam 1's start, x along it.
  Workpiece w1;
  w1.params.length_mm = sim.truth[0].length();
  w1.world_from_joint = sim.actual_world_from_workpiece * Eigen::Translation3d(-h, -h, 0.0);
  w1.plates = {block(h - ph, h + ph, h - ph, h + ph, -params.plate_thickness_mm, 0.0),
               block(0.0, 2.0 * h, 0.0, 2.0 * h, 0.0, params.box_height_mm)};
  // Seam 2's: no plates, only its seam line.
  Workpiece w2;
  w2.params.length_mm = sim.truth[1].length();
  w2.world_from_joint = sim.actual_world_from_workpiece * Eigen::Translation3d(h, -h, 0.0) *
                        Eigen::AngleAxisd(0.5 * std::numbers::pi, Vec3::UnitZ());
  cell->workpieces = {w1, w2};
  SimView view;
  view.samples = std::move(run.result.samples);
  view.dt_s = 1.0 / run.scanner.rate_hz;
  cell->path.start = view.samples.front().world_from_tool * run.scanner.tool_from_laser;
  cell->path.direction = (sim.truth[0].end - sim.truth[0].start).normalized();
  view.cell = cell;
  char line[256];
  std::snprintf(line, sizeof line, "sim (seed %llu): rms lateral %.4f / %.4f mm, max %.4f / %.4f mm",
                static_cast<unsigned long long>(seed), run.metrics[0].rms_lateral_mm, run.metrics[1].rms_lateral_mm,
                run.metrics[0].max_error_mm, run.metrics[1].max_error_mm);
  view.summary = line;
  return view;
}

}  // namespace vts::viewer
