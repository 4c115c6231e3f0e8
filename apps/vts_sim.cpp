#include "apps/vts_sim.h"

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <limits>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>

#include "apps/cli.h"
#include "pipeline/groove_passes.h"
#include "pipeline/scenario.h"
#include "pipeline/sim_run.h"
#include "robot/robots.h"
#include "sensor/presets.h"

namespace vts::apps {
namespace {

namespace fs = std::filesystem;
using cli::bad;
using Json = trackio::Json;

struct SimOptions : BoxOptions {
  std::string out_dir, replay, scenario;
  bool list_scenarios = false, all = false;
  std::string cell, scene, passes, first_pass, profiles;  // a multi-pass groove instead of the box
  std::string fill, fill_bias;                             // ... where its beads go
  bool json = false;
};

double parse_number(const std::string& option, const std::string& text, double lo, double hi,
                    const char* unit) {
  char* end = nullptr;
  const double v = text.empty() || std::isspace(static_cast<unsigned char>(text.front()))
                       ? std::numeric_limits<double>::quiet_NaN()
                       : std::strtod(text.c_str(), &end);
  if (!std::isfinite(v) || end != text.c_str() + text.size())
    bad(option, text, std::string("expected a number in ") + unit);
  if (v < lo || v > hi) {
    std::ostringstream s;
    s << "out of range: expected " << lo << " to " << hi << " " << unit;
    bad(option, text, s.str());
  }
  return v;
}

}  // namespace

// --sensor, --material and --ideal onto the scanner (the box's and a groove cell's alike).
void apply_sensor_options(const BoxOptions& o, ScannerDesc& sc) {
  if (!o.sensor.empty()) {
    const auto preset = sensor_preset(o.sensor);
    if (!preset)
      bad("--sensor", o.sensor, "unknown sensor; valid names: " + join_names(sensor_preset_names()));
    set_sensor_fields(sc, *preset);
  }
  if (!o.material.empty() && !apply_material(sc, o.material))
    bad("--material", o.material, "unknown material; valid names: " + join_names(material_names()));
  sc.ideal = o.ideal;
}

SimSpec box_spec(const BoxOptions& o) {
  SimSpec spec;
  if (!o.speed.empty()) spec.speed_mm_s = parse_number("--speed", o.speed, 0.1, 500.0, "mm/s");
  spec.seed = o.seed.empty() ? 1 : cli::parse_seed("--seed", o.seed);
  spec.cell.seed = spec.seed;
  if (!o.offset.empty()) spec.cell.offset_mm = parse_number("--offset", o.offset, 0.0, 20.0, "mm");
  if (!o.rotation.empty()) spec.cell.rotation_deg = parse_number("--rotation", o.rotation, 0.0, 10.0, "degrees");
  ScannerDesc& sc = spec.scanner;
  apply_sensor_options(o, sc);
  if (!o.rate.empty()) sc.rate_hz = parse_number("--rate", o.rate, 1.0, 10000.0, "Hz");
  spec.source = cli::parse_source("--source", o.source.empty() ? "raster" : o.source);
  spec.cell.standoff_mm = sim_standoff_mm(sc);
  if (const std::string why = validate(spec.cell); !why.empty()) throw cli::UsageError("cell: " + why);
  if (!o.robot.empty()) {
    if (!robot::is_robot_name(o.robot)) bad("--robot", o.robot, "expected one of " + join_names(robot::robot_names()));
    spec.robot = o.robot;
  }
  if (!o.robot_seed.empty()) {
    if (spec.robot == "perfect") bad("--robot-seed", o.robot_seed, "only with an arm (--robot irb2400 or kr16)");
    spec.robot_seed = cli::parse_seed("--robot-seed", o.robot_seed);
  }
  return spec;
}

void refuse_box_options(const BoxOptions& o, const std::string& with) {
  for (const auto& [opt, v] : {std::pair<const char*, const std::string*>{"--speed", &o.speed},
                               {"--rate", &o.rate}, {"--offset", &o.offset}, {"--rotation", &o.rotation},
                               {"--seed", &o.seed}, {"--sensor", &o.sensor}, {"--material", &o.material},
                               {"--robot", &o.robot}, {"--robot-seed", &o.robot_seed}})
    if (!v->empty()) bad(opt, *v, "a scenario sets it in its file; not with " + with);
}

void add_box_options(CLI::App* cmd, BoxOptions& o) {
  cmd->add_option("--speed", o.speed, "Weld (and search) speed, mm/s, 0.1..500 (default 10)")->type_name("MM_PER_S");
  cmd->add_option("--rate", o.rate, "Sensor profile rate, Hz, 1..10000 (default: the sensor's, 20 for mspot)")
      ->type_name("HZ");
  cmd->add_option("--seed", o.seed, "Seed of the workpiece displacement and the error model (default 1)")
      ->type_name("S");
  cmd->add_option("--offset", o.offset, "Largest workpiece translation from nominal, mm, 0..20 (default 10)")
      ->type_name("MM");
  cmd->add_option("--rotation", o.rotation, "Largest workpiece rotation from nominal, degrees, 0..10 (default 5)")
      ->type_name("DEG");
  cmd->add_option("--source", o.source, "Profile source: raster (OSMesa emulator, default) or reference (Embree)")
      ->type_name("raster|reference");
  cmd->add_option("--sensor", o.sensor, "Sensor preset (see `vts sensors`), default mspot")->type_name("NAME");
  cmd->add_option("--material", o.material, "Surface material preset, default matte-steel")->type_name("NAME");
  cmd->add_flag("--ideal", o.ideal, "Error model off: ideal geometric profiles");
  cmd->add_option("--threads", o.threads, cli::kThreadsHelp)->type_name("N");
  cmd->add_option("--robot", o.robot,
                  "The robot: perfect (the TCP where commanded, at once; default) or an arm, irb2400 or kr16, with "
                  "its joint servo, 3-cycle correction latency, limits and singularities (docs/ROBOT.md)")
      ->type_name("NAME");
  cmd->add_option("--robot-seed", o.robot_seed,
                  "With an arm: the absolute-accuracy errors of this seed (0.2-1 mm at the flange; default: none)")
      ->type_name("S");
}

namespace {

// Everything checked before anything is created.
struct SimPlan {
  SimSpec spec;
  fs::path out_dir;
};

// --out-dir as an absolute path; refused if it is a file.
fs::path out_dir_option(const std::string& dir) {
  std::error_code ec;
  fs::path out = fs::absolute(dir, ec).lexically_normal();
  if (ec) bad("--out-dir", dir, "cannot make an absolute path: " + ec.message());
  if (fs::exists(out, ec) && !fs::is_directory(out, ec)) bad("--out-dir", dir, "exists and is not a directory");
  return out;
}

SimPlan plan_sim(const SimOptions& o) {
  SimPlan plan;
  plan.spec = box_spec(o);
  SimSpec& spec = plan.spec;
  plan.out_dir = out_dir_option(o.out_dir.empty() ? std::string("sim") : o.out_dir);
  std::error_code ec;
  if (!o.replay.empty()) {
    spec.replay = o.replay;
    if (!fs::is_regular_file(spec.replay, ec)) bad("--replay", o.replay, "no such file");
  }
  cli::apply_thread_limit(o.threads);
  return plan;
}

// A multi-pass weld of a groove cell (issue 18; docs/SIM.md "Multi-pass"):
// the summary on stdout, nothing written.
int run_passes(const SimOptions& o) {
  for (const auto& [opt, v] : {std::pair<const char*, const std::string*>{"--speed", &o.speed},
                               {"--rate", &o.rate}, {"--offset", &o.offset}, {"--rotation", &o.rotation},
                               {"--replay", &o.replay}, {"--out-dir", &o.out_dir}})
    if (!v->empty()) bad(opt, *v, "only for the box experiment, not with --cell or --scene");
  GroovePassSpec spec;
  spec.cell = cli::load_cell(o.cell, o.scene).cell;
  apply_sensor_options(o, spec.cell.scanner);
  spec.source = cli::parse_source("--source", o.source.empty() ? "raster" : o.source);
  spec.seed = o.seed.empty() ? 1 : cli::parse_seed("--seed", o.seed);
  if (!o.passes.empty()) spec.last_pass = static_cast<int>(parse_number("--passes", o.passes, 0.0, 1000.0, "beads"));
  if (!o.first_pass.empty())
    spec.first_pass = static_cast<int>(parse_number("--first-pass", o.first_pass, 0.0, 1000.0, "beads"));
  if (!o.profiles.empty()) spec.profiles = static_cast<int>(parse_number("--profiles", o.profiles, 1.0, 100000.0, "profiles"));
  if (o.fill.empty() || o.fill == "adaptive") spec.fill = FillMode::Adaptive;
  else if (o.fill == "model") spec.fill = FillMode::Model;
  else bad("--fill", o.fill, "expected adaptive (each bead where the sensor said; default) or model (where the cell's model centres it)");
  if (!o.fill_bias.empty()) {
    if (spec.fill != FillMode::Adaptive) bad("--fill-bias", o.fill_bias, "only with the adaptive fill, not with --fill model");
    spec.bias_mm = parse_number("--fill-bias", o.fill_bias, -20.0, 20.0, "mm");
  }
  if (const std::string why = validate(spec); !why.empty()) throw cli::UsageError(why);
  cli::apply_thread_limit(o.threads);
  const GroovePassRun run = run_groove_passes(spec);
  if (o.json) std::cout << groove_passes_json(run).dump() << "\n";
  else std::cout << groove_passes_markdown(run) << "\n";
  bool all = run.stopped.empty();
  for (const GroovePass& p : run.passes) all = all && p.ok > 0;
  return all ? cli::kExitOk : cli::kExitRuntime;
}

// One run of `spec` with its outputs under out_dir (timeseries.csv,
// profiles.exr unless a replay, tracking_error.png), each written whole.
struct Simulated {
  SimRun run;
  double wall_s = 0.0;      // the whole: simulation and outputs
  double sim_wall_s = 0.0;  // the simulation alone (closed and open loop)
};
Simulated simulate(const SimSpec& spec, const fs::path& out_dir) {
  const auto wall0 = std::chrono::steady_clock::now();
  // The measured profiles go to a scratch file in the output directory as
  // they are taken; both appear only once the sensor delivers.
  std::unique_ptr<ProfileSpool> spool;
  Simulated sim;
  sim.run = run_sim(spec, [&](const Profile& p) {
    if (!spool) {
      fs::create_directories(out_dir);
      spool = std::make_unique<ProfileSpool>(out_dir / (".profiles.spool-" + std::to_string(::getpid())));
    }
    spool->add(p);
  });
  sim.sim_wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  const SimRun& run = sim.run;
  fs::create_directories(out_dir);
  cli::write_text_file(out_dir / "timeseries.csv", sim_timeseries_csv(run));
  if (spool) {
    ProfileFileInfo info;
    info.scanner = run.scanner;
    info.scene_name = "sim-box";
    info.error_model = !run.scanner.ideal;
    info.seed = spec.seed;
    if (spool->count() > 0) spool->write_exr(out_dir / "profiles.exr", info);
  }
  if (const std::string err = sim_error_figure(run).save_png(out_dir / "tracking_error.png"); !err.empty())
    throw std::runtime_error(err);
  sim.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  return sim;
}

// ", largest gap 0.87 mm" when the sensor measured one on the seam.
std::string gap_text(double max_gap_mm) {
  if (!(max_gap_mm > 0.0)) return {};
  char buf[64];
  std::snprintf(buf, sizeof buf, ", largest gap %.2f mm", max_gap_mm);
  return buf;
}

void print_text_summary(const SimSpec& spec, const Simulated& sim, const fs::path& out_dir) {
  const SimRun& run = sim.run;
  const ScannerDesc& scanner = run.scanner;
  const auto& metrics = run.metrics;
  std::printf("vts sim: box cell, workpiece displaced %.2f mm and turned %.2f deg from nominal (seed %llu)\n",
              run.offset_mm(), run.rotation_deg(), static_cast<unsigned long long>(spec.seed));
  std::printf("sensor %s, %s, error model %s, %s source, %.0f Hz, %.1f mm/s, robot %s\n", scanner.name.c_str(),
              scanner.material.c_str(), scanner.ideal ? "off" : "on", run.source_name.c_str(), scanner.rate_hz,
              spec.speed_mm_s, run.robot.c_str());
  for (std::size_t k = 0; k < metrics.size(); ++k) {
    const SeamMetrics& m = metrics[k];
    std::printf(
        "seam %zu: search %.1f mm, start error %.3f mm, rms lateral %.3f mm, rms vertical %.3f mm, max %.3f mm, "
        "end error %.3f mm, welded %.1f mm; sensor track points rms %.4f mm%s%s%s%s\n",
        k + 1, m.search_mm, m.start_error_mm, m.rms_lateral_mm, m.rms_vertical_mm, m.max_error_mm, m.end_error_mm,
        m.welded_mm, m.sensor_rms_mm, gap_text(m.sensor_max_gap_mm).c_str(), m.lost ? ", SEAM LOST" : "", m.failure.empty() ? "" : ", failed: ",
        m.failure.c_str());
    if (k < run.open_loop_metrics.size()) {
      const SeamMetrics& ol = run.open_loop_metrics[k];
      std::printf("        open loop (the same program without the sensor): rms lateral %.3f mm, rms vertical %.3f mm, "
                  "max %.3f mm\n",
                  ol.rms_lateral_mm, ol.rms_vertical_mm, ol.max_error_mm);
    }
  }
  if (!run.robot_fault.empty()) std::printf("robot: %s\n", run.robot_fault.c_str());
  std::printf("%lld profiles, %.1f s simulated in %.2f s; wrote %s/{timeseries.csv,%stracking_error.png}\n",
              static_cast<long long>(run.profiles), run.sim_time_s(), sim.wall_s, out_dir.c_str(),
              spec.replay.empty() ? "profiles.exr," : "");
}

// `--scenarios`, `--scenario NAME|FILE` and `--all`.
int run_scenarios(const SimOptions& o) {
  if (o.list_scenarios) {
    for (const std::string& name : scenario_names()) {
      const Scenario sc = builtin_scenario(name);
      std::printf("%-22s %-4s  %s\n", name.c_str(), sc.expect_pass ? "pass" : "fail", sc.description.c_str());
    }
    return cli::kExitOk;
  }
  refuse_box_options(o, "--scenario or --all");
  for (const auto& [opt, v] : {std::pair<const char*, const std::string*>{"--replay", &o.replay},
                               {"--cell", &o.cell}, {"--scene", &o.scene}})
    if (!v->empty()) bad(opt, *v, "a scenario sets it in its file; not with --scenario or --all");
  if (o.all && !o.scenario.empty()) bad("--scenario", o.scenario, "give --scenario or --all, not both");
  for (const auto& [opt, v] : {std::pair<const char*, const std::string*>{"--fill", &o.fill}, {"--fill-bias", &o.fill_bias}})
    if (!v->empty()) bad(opt, *v, "only with --cell or --scene (a multi-pass groove)");
  std::vector<Scenario> scenarios;
  try {
    if (o.all) {
      for (const std::string& name : scenario_names()) scenarios.push_back(builtin_scenario(name));
    } else {
      scenarios.push_back(find_scenario(o.scenario));
    }
  } catch (const ScenarioError& e) {
    throw cli::UsageError(e.what());
  }
  const fs::path base = out_dir_option(o.out_dir.empty() ? std::string("sim") : o.out_dir);
  cli::apply_thread_limit(o.threads);
  bool all_as_expected = true;
  Json list = Json::array();
  if (!o.json && o.all)
    std::printf("| scenario | expected | verdict | seam | tracked rms lat / vert (mm) | tracked max (mm) | "
                "open loop rms lat / max (mm) | sim time (s) | x real time | reason |\n|---|---|---|---|---|---|---|---|---|---|\n");
  for (Scenario& sc : scenarios) {
    if (!o.source.empty()) sc.spec.source = cli::parse_source("--source", o.source);
    const fs::path out = o.all ? base / sc.name : base;
    const Simulated sim = simulate(sc.spec, out);
    const std::string reason = scenario_failure(sim.run);
    const bool passed = reason.empty();
    const bool as_expected = scenario_as_expected(sc, reason);
    all_as_expected = all_as_expected && as_expected;
    if (o.json) {
      Json j = scenario_summary_json(sc, sim.run, sim.wall_s, sim.sim_wall_s);
      j["real_time_factor"] = sim.run.sim_time_s() / std::max(sim.sim_wall_s, 1e-9);
      j["out_dir"] = out.string();
      if (o.all) list.push_back(j);
      else std::cout << j.dump() << "\n";
    } else if (o.all) {
      const SimRun& run = sim.run;
      for (std::size_t k = 0; k < run.metrics.size(); ++k) {
        const SeamMetrics& m = run.metrics[k];
        const SeamMetrics ol = k < run.open_loop_metrics.size() ? run.open_loop_metrics[k] : SeamMetrics{};
        std::printf("| %s | %s | %s%s | %zu | %.3f / %.3f | %.3f | %.2f / %.2f | %.1f | %.0f | %s |\n",
                    k == 0 ? sc.name.c_str() : "", k == 0 ? (sc.expect_pass ? "pass" : "fail") : "",
                    k == 0 ? (passed ? "pass" : "fail") : "", k == 0 && !as_expected ? " (UNEXPECTED)" : "", k + 1,
                    m.rms_lateral_mm, m.rms_vertical_mm, m.max_error_mm, ol.rms_lateral_mm, ol.max_error_mm,
                    run.sim_time_s(), run.sim_time_s() / std::max(sim.sim_wall_s, 1e-9), k == 0 ? reason.c_str() : "");
      }
    } else {
      std::printf("scenario %s: %s\n", sc.name.c_str(), sc.description.c_str());
      print_text_summary(sc.spec, sim, out);
      std::printf("verdict: %s%s%s (expected %s)\n", passed ? "pass" : "fail", passed ? "" : ": ", reason.c_str(),
                  sc.expect_pass ? "pass" : "fail");
    }
    std::fflush(stdout);
  }
  if (o.json && o.all) std::cout << list.dump() << "\n";
  return all_as_expected ? cli::kExitOk : cli::kExitRuntime;
}

int run_sim(const SimOptions& o) {
  if (o.list_scenarios || o.all || !o.scenario.empty()) return run_scenarios(o);
  if (!o.cell.empty() || !o.scene.empty()) return run_passes(o);
  for (const auto& [opt, v] : {std::pair<const char*, const std::string*>{"--fill", &o.fill}, {"--fill-bias", &o.fill_bias}})
    if (!v->empty()) bad(opt, *v, "only with --cell or --scene (a multi-pass groove)");
  const SimPlan plan = plan_sim(o);  // throws UsageError; nothing created yet
  const SimSpec& spec = plan.spec;
  const Simulated sim = simulate(spec, plan.out_dir);
  const SimRun& run = sim.run;
  if (o.json) {
    Json j = sim_summary_json(spec, run, sim.wall_s, sim.sim_wall_s);
    j["out_dir"] = plan.out_dir.string();
    std::cout << j.dump() << "\n";
  } else {
    print_text_summary(spec, sim, plan.out_dir);
  }
  std::fflush(stdout);
  return run.completed() ? cli::kExitOk : cli::kExitRuntime;
}

}  // namespace

CLI::App* add_sim_command(CLI::App& app, int& exit_code) {
  auto o = std::make_shared<SimOptions>();
  CLI::App* cmd = app.add_subcommand(
      "sim",
      "The paper's dynamic experiment, headless: a master welds two fillet seams of a box displaced from its\n"
      "nominal pose, guided by the virtual sensor (start search, tracking, end of seam, re-calibration).\n"
      "Writes timeseries.csv, profiles.exr and tracking_error.png to --out-dir (docs/SIM.md).");
  cmd->option_defaults()->always_capture_default(false);
  add_box_options(cmd, *o);
  cmd->add_option("--out-dir", o->out_dir, "Directory for the outputs (created if missing), default sim/")
      ->type_name("DIR");
  cmd->add_option("--replay", o->replay,
                  "Run the master on a recorded sensor instead: the profiles.exr of an earlier run. The master must "
                  "move as it did then (same --speed); errors are measured against the cell of --seed, --offset and "
                  "--rotation, so give the recorded run's (no profiles.exr is written)")
      ->type_name("FILE.exr");
  cmd->add_flag("--json", o->json, "Print the summary as one JSON object (with --all: a JSON array of them)");
  cmd->add_option("--scenario", o->scenario,
                  "Run a scenario: a built-in one by name (`--scenarios` lists them) or a scenario file "
                  "(docs/SIM.md): cell disturbances, robot, sensor, program and the expected verdict. Outputs go "
                  "to --out-dir; exit 0 when the verdict is the expected one")
      ->type_name("NAME|FILE.yaml");
  cmd->add_flag("--scenarios", o->list_scenarios, "List the built-in scenarios with their expected verdicts");
  cmd->add_flag("--all", o->all,
                "Run every built-in scenario (outputs under --out-dir/NAME/); prints a table, or with --json an "
                "array; exit 0 when every verdict is the expected one");
  cmd->add_option("--cell", o->cell,
                  "Instead of the box: a multi-pass weld of a groove cell (vgroove-thick, bevel-thick, "
                  "ugroove-fill, ...): beads laid pass after pass, the sensor asked between them, each bead laid "
                  "where the sensor said (--fill); prints per pass the measured and true depth and area left, the "
                  "next bead's place and where it was laid against the model's centre (docs/SIM.md)")
      ->type_name("NAME");
  cmd->add_option("--scene", o->scene, "As --cell, from a scene file with one groove workpiece")->type_name("FILE");
  cmd->add_option("--passes", o->passes, "With --cell: beads laid before the last scan (default: the cell's)")
      ->type_name("N");
  cmd->add_option("--first-pass", o->first_pass, "With --cell: beads laid before the first scan (default 0)")
      ->type_name("N");
  cmd->add_option("--profiles", o->profiles, "With --cell: profiles per pass along the cell's path (default 10)")
      ->type_name("N");
  cmd->add_option("--fill", o->fill,
                  "With --cell: where each bead goes. adaptive (default): where the sensor said between the passes "
                  "(the tracker's next-bead point, median over the accepted profiles, in the part frame), with the "
                  "bead model's deposit, the geometry rebuilt with the bead there; the run stops when a pass has no "
                  "accepted profile. model: where the cell's model centres it, whatever the sensor said")
      ->type_name("adaptive|model");
  cmd->add_option("--fill-bias", o->fill_bias,
                  "With --cell and the adaptive fill: add MM (-20..20) along the laser line to every reported "
                  "next-bead point, as a sensor mounted that far off across the seam would report (default 0)")
      ->type_name("MM");
  cmd->callback([o, &exit_code] {
    try {
      exit_code = run_sim(*o);
    } catch (const cli::UsageError& e) {
      std::cerr << "vts sim: " << e.what() << "\n";
      exit_code = cli::kExitUsage;
    } catch (const std::invalid_argument& e) {
      std::cerr << "vts sim: " << e.what() << "\n";
      exit_code = cli::kExitUsage;
    } catch (const ExrError& e) {
      std::cerr << "vts sim: " << e.what() << "\n";
      exit_code = cli::kExitUsage;
    } catch (const std::exception& e) {
      std::cerr << "vts sim: error: " << e.what() << "\n";
      exit_code = cli::kExitRuntime;
    }
  });
  return cmd;
}

}  // namespace vts::apps
