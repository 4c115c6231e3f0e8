#include "viewer/sim_view.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <stdexcept>

#include "pipeline/scenario.h"
#include "pipeline/sim_run.h"
#include "sensor/presets.h"
#include "viewer/geometry.h"

namespace vts::viewer {
namespace {

Eigen::Vector3f f3(const Vec3& v) { return v.cast<float>(); }

// Link i's solid in its own frame (after axis i): from the previous frame's
// origin along the previous z by d, then along this x by a (both fixed in
// this frame: T^-1 = Rx(-alpha) Tx(-a) Tz(-d) Rz(-q)).
Mesh link_mesh(const robot::Axis& axis, float width) {
  const Eigen::Matrix3d back = Eigen::AngleAxisd(-axis.alpha_rad, Vec3::UnitX()).toRotationMatrix();
  const Vec3 p0 = back * Vec3(-axis.a_mm, 0.0, -axis.d_mm), p1 = back * Vec3(-axis.a_mm, 0.0, 0.0);
  Mesh m;
  if ((p1 - p0).norm() > 1.0) m.append(beam(f3(p0), f3(p1), width));
  if (p1.norm() > 1.0) m.append(beam(f3(p1), Eigen::Vector3f::Zero(), width));
  if (m.triangles.empty()) m.append(beam(Eigen::Vector3f(0, 0, -0.5f * width), Eigen::Vector3f(0, 0, 0.5f * width), width));
  return m;
}

}  // namespace

SimView run_sim_for_view(std::uint64_t seed, const std::string& sensor, const std::string& material, bool ideal,
                         const std::string& scenario) {
  SimSpec spec;
  std::string label = "sim-box";
  if (!scenario.empty()) {
    try {
      const Scenario sc = find_scenario(scenario);
      spec = sc.spec;
      label = "scenario " + sc.name;
    } catch (const ScenarioError& e) {
      throw std::runtime_error(std::string("--scenario: ") + e.what());
    }
  } else {
    if (!sensor.empty()) set_sensor_fields(spec.scanner, *sensor_preset(sensor));
    if (!material.empty()) apply_material(spec.scanner, material);
    spec.scanner.ideal = ideal;
    spec.seed = spec.cell.seed = seed;
    spec.cell.standoff_mm = sim_standoff_mm(spec.scanner);
  }
  spec.source = SourceKind::Reference;
  spec.open_loop = false;
  SimRun run = run_sim(spec);
  const SimCell& sim = run.cell;
  const double h = 0.5 * spec.cell.box_side_mm;

  auto cell = std::make_shared<Cell>();
  cell->name = spec.cell.workpiece == SimWorkpiece::Saddle ? "sim-saddle" : "sim-box";
  cell->scanner = run.scanner;
  // The part as built (bowed wall, tacks), a mesh workpiece in world.
  Workpiece part;
  part.file_mesh = std::make_shared<const Mesh>(sim.mesh);
  // One line-only workpiece per seam, its joint frame at the seam's start,
  // x along it (a curved seam is drawn from its path instead).
  SimView view;
  Workpiece w1;
  w1.params.length_mm = sim.truth[0].path.empty() ? sim.truth[0].length() : 0.0;
  w1.world_from_joint = sim.actual_world_from_workpiece * Eigen::Translation3d(-h, -h, 0.0);
  Workpiece w2;
  w2.params.length_mm = sim.truth[1].length();
  w2.world_from_joint = sim.actual_world_from_workpiece * Eigen::Translation3d(h, -h, 0.0) *
                        Eigen::AngleAxisd(0.5 * std::numbers::pi, Vec3::UnitZ());
  cell->workpieces = {w1, w2, part};
  if (spec.cell.workpiece == SimWorkpiece::Saddle) cell->workpieces = {part};  // its seams: the paths below
  for (const SimSeamTruth& t : sim.truth)
    if (!t.path.empty()) view.seam_paths.push_back(t.path);
  view.samples = std::move(run.result.samples);
  view.tcp = run.actual_tcp;
  view.dt_s = 1.0 / run.scanner.rate_hz;
  cell->path.start = view.samples.front().world_from_tool * run.scanner.tool_from_laser;
  cell->path.direction = (sim.truth[0].end - sim.truth[0].start).normalized();
  view.cell = cell;
  view.label = label;

  if (run.arm) {
    // Links 1-3 as 140 mm beams, the wrist as 90 mm, a pedestal under the base.
    const auto& arm = *run.arm;
    const Rgba colour = arm.as_built.name.find("kr") != std::string::npos ? Rgba{0.95f, 0.45f, 0.05f, 1.0f}
                                                                          : Rgba{0.85f, 0.85f, 0.82f, 1.0f};
    view.arm_links.push_back({beam(Eigen::Vector3f(0, 0, -300.0f), Eigen::Vector3f::Zero(), 220.0f),
                              {0.35f, 0.35f, 0.38f, 1.0f}});
    for (int i = 0; i < 6; ++i)
      view.arm_links.push_back({link_mesh(arm.as_built.axes[static_cast<std::size_t>(i)], i < 3 ? 140.0f : 90.0f), colour});
    // The torch's mount: from the flange to where the viewer's torch body ends.
    const float body_top = static_cast<float>(arm.flange_from_tool.translation().z() - 260.0);
    view.arm_links.push_back({beam(Eigen::Vector3f::Zero(), Eigen::Vector3f(0.0f, 0.0f, std::max(body_top, 1.0f)), 50.0f),
                              {0.25f, 0.25f, 0.28f, 1.0f}});
    for (const robot::Joints& q : arm.joints) {
      const auto f = robot::frames(arm.as_built, q);
      std::vector<Pose> poses{arm.world_from_base};
      for (int i = 1; i <= 6; ++i) poses.push_back(arm.world_from_base * f[static_cast<std::size_t>(i)]);
      poses.push_back(poses.back());  // the mount, on the flange
      view.arm_poses.push_back(std::move(poses));
    }
  }

  char line[320];
  std::snprintf(line, sizeof line, "%s (seed %llu, robot %s): rms lateral %.4f / %.4f mm, max %.4f / %.4f mm%s%s",
                label.c_str(), static_cast<unsigned long long>(spec.seed), run.robot.c_str(),
                run.metrics[0].rms_lateral_mm, run.metrics[1].rms_lateral_mm, run.metrics[0].max_error_mm,
                run.metrics[1].max_error_mm, run.robot_fault.empty() ? "" : ": ", run.robot_fault.c_str());
  view.summary = line;
  return view;
}

std::size_t sample_at(const SimView& view, double t) {
  // Sample k is the master's cycle k + 1, at time (k + 1) dt.
  const long k = std::lround(t / view.dt_s) - 1;
  return static_cast<std::size_t>(std::clamp(k, 0L, static_cast<long>(view.samples.size()) - 1));
}

}  // namespace vts::viewer
