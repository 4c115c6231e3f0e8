#include "pipeline/scenario.h"

#include <algorithm>
#include <cstdio>
#include <utility>

#include "robot/robots.h"
#include "sensor/presets.h"
#include "sensor/yaml_io.h"

namespace vts {

// examples/scenarios/*.yaml, generated at build time (pipeline/CMakeLists.txt).
std::vector<std::pair<std::string, std::string>> embedded_scenario_files();

namespace {

using yaml_io::Field;

class Parser : public yaml_io::Reader {
 public:
  using Reader::Reader;
  void raise(int line, const std::string& field, const std::string& msg) const override {
    throw ScenarioError(yaml_io::error_text(file_, line, field, msg));
  }
};

struct NumberKey {
  const char* key;
  double SimCellParams::*member;
};
constexpr NumberKey kCellKeys[] = {
    {"offset_mm", &SimCellParams::offset_mm},
    {"rotation_deg", &SimCellParams::rotation_deg},
    {"seam1_bow_mm", &SimCellParams::seam1_bow_mm},
    {"seam1_wave_mm", &SimCellParams::seam1_wave_mm},
    {"seam1_wavelength_mm", &SimCellParams::seam1_wavelength_mm},
    {"seam1_gap_rise_mm", &SimCellParams::seam1_gap_rise_mm},
    {"seam1_short_mm", &SimCellParams::seam1_short_mm},
    {"tack_spacing_mm", &SimCellParams::tack_spacing_mm},
    {"tack_first_mm", &SimCellParams::tack_first_mm},
    {"tack_length_mm", &SimCellParams::tack_length_mm},
    {"tack_leg_mm", &SimCellParams::tack_leg_mm},
    {"distortion_deg_per_100mm", &SimCellParams::distortion_deg_per_100mm},
    {"distortion_lift_deg_per_100mm", &SimCellParams::distortion_lift_deg_per_100mm},
    {"lookahead_mm", &SimCellParams::lookahead_mm},
};

}  // namespace

Scenario parse_scenario(const std::string& yaml_text, const std::string& file_name) {
  const Parser p(file_name);
  const YAML::Node root = p.load(yaml_text);
  if (root.IsNull()) p.fail(1, "", "empty scenario (expected a map; docs/SIM.md \"Scenarios\")");
  std::vector<std::string> allowed = {"name", "description", "expect", "expect_reason", "seed", "robot",
                                      "robot_seed", "sensor", "material", "ideal", "rate_hz", "source",
                                      "speed_mm_s", "search_margin_mm", "weave_amplitude_mm",
                                      "weave_frequency_hz", "weave_dwell_s", "workpiece"};
  for (const auto& k : kCellKeys) allowed.emplace_back(k.key);
  for (const auto& k : kSaddleParamNumbers) allowed.emplace_back(k.key);
  const Parser::Map m(p, Field{root, "", 1}, allowed);
  Scenario sc;
  sc.file = file_name;
  sc.name = std::filesystem::path(file_name).stem().string();
  if (auto x = m.get("name")) sc.name = p.string(*x);
  if (auto x = m.get("description")) sc.description = p.string(*x);
  if (auto x = m.get("expect")) {
    const std::string v = p.string(*x);
    if (v != "pass" && v != "fail") p.fail(*x, "expect = '" + v + "': expected pass or fail");
    sc.expect_pass = v == "pass";
  }
  if (auto x = m.get("expect_reason")) sc.expect_reason = p.string(*x);

  SimSpec& s = sc.spec;
  s.source = SourceKind::Reference;
  if (auto x = m.get("seed")) {
    const long long v = p.integer(*x);
    if (v < 0) p.fail(*x, "seed = " + std::to_string(v) + ": must be >= 0");
    s.seed = static_cast<std::uint64_t>(v);
  }
  s.cell.seed = s.seed;
  for (const auto& k : kCellKeys)
    if (auto x = m.get(k.key)) s.cell.*k.member = p.number(*x);
  if (auto x = m.get("workpiece")) {
    const std::string v = p.string(*x);
    if (v == "box") s.cell.workpiece = SimWorkpiece::Box;
    else if (v == "saddle") s.cell.workpiece = SimWorkpiece::Saddle;
    else p.fail(*x, "workpiece = '" + v + "': expected box or saddle");
  }
  for (const auto& k : kSaddleParamNumbers)
    if (auto x = m.get(k.key)) {
      if (s.cell.workpiece != SimWorkpiece::Saddle) p.fail(*x, std::string(k.key) + ": only with workpiece: saddle");
      s.cell.saddle.*k.member = p.number(*x);
    }
  if (auto x = m.get("sensor")) {
    const std::string name = p.string(*x);
    const auto preset = sensor_preset(name);
    if (!preset) p.fail(*x, "unknown sensor '" + name + "' (expected one of: " + join_names(sensor_preset_names()) + ")");
    set_sensor_fields(s.scanner, *preset);
  }
  if (auto x = m.get("material")) {
    const std::string name = p.string(*x);
    if (!apply_material(s.scanner, name))
      p.fail(*x, "unknown material '" + name + "' (expected one of: " + join_names(material_names()) + ")");
  }
  if (auto x = m.get("ideal")) s.scanner.ideal = p.boolean(*x);
  if (auto x = m.get("rate_hz")) {
    s.scanner.rate_hz = p.number(*x);
    if (s.scanner.rate_hz < 1.0 || s.scanner.rate_hz > 10000.0) p.fail(*x, "rate_hz must be between 1 and 10000");
  }
  if (auto x = m.get("source")) {
    const std::string v = p.string(*x);
    if (v == "raster") s.source = SourceKind::Raster;
    else if (v == "reference") s.source = SourceKind::Reference;
    else p.fail(*x, "source = '" + v + "': expected raster or reference");
  }
  if (auto x = m.get("robot")) {
    s.robot = p.string(*x);
    if (!robot::is_robot_name(s.robot))
      p.fail(*x, "robot = '" + s.robot + "': expected one of " + join_names(robot::robot_names()));
  }
  if (auto x = m.get("robot_seed")) {
    const long long v = p.integer(*x);
    if (v < 0) p.fail(*x, "robot_seed = " + std::to_string(v) + ": must be >= 0");
    s.robot_seed = static_cast<std::uint64_t>(v);
  }
  if (auto x = m.get("speed_mm_s")) {
    s.speed_mm_s = p.number(*x);
    if (s.speed_mm_s < 0.1 || s.speed_mm_s > 500.0) p.fail(*x, "speed_mm_s must be between 0.1 and 500");
  }
  if (auto x = m.get("search_margin_mm")) {
    s.search_margin_mm = p.number(*x);
    if (*s.search_margin_mm < 1.0 || *s.search_margin_mm > 100.0) p.fail(*x, "search_margin_mm must be between 1 and 100");
  }
  auto& w = s.weave;
  if (auto x = m.get("weave_amplitude_mm")) {
    w.amplitude_mm = p.number(*x);
    if (w.amplitude_mm < 0.0 || w.amplitude_mm > 10.0) p.fail(*x, "weave_amplitude_mm must be between 0 and 10");
  }
  if (auto x = m.get("weave_frequency_hz")) {
    w.frequency_hz = p.number(*x);
    if (w.frequency_hz <= 0.0 || w.frequency_hz > 10.0) p.fail(*x, "weave_frequency_hz must be > 0 and <= 10");
  }
  if (auto x = m.get("weave_dwell_s")) {
    w.dwell_s = p.number(*x);
    if (w.dwell_s < 0.0 || 2.0 * w.dwell_s >= 1.0 / w.frequency_hz)
      p.fail(*x, "weave_dwell_s must be >= 0 and leave time to move: 2 dwell < 1 / weave_frequency_hz");
  }
  s.cell.standoff_mm = sim_standoff_mm(s.scanner);
  if (const std::string why = validate(s.cell); !why.empty()) p.fail_validation(m, why);
  if (const std::string why = validate(s.scanner); !why.empty()) p.fail(1, "sensor", why);
  return sc;
}

Scenario load_scenario(const std::filesystem::path& path) {
  const Parser p(path.string());
  return parse_scenario(p.read_file(path, "scenario"), path.string());
}

std::vector<std::string> scenario_names() {
  std::vector<std::string> names;
  for (const auto& [name, text] : embedded_scenario_files()) names.push_back(name);
  std::sort(names.begin(), names.end());
  return names;
}

Scenario builtin_scenario(const std::string& name) {
  for (const auto& [n, text] : embedded_scenario_files())
    if (n == name) return parse_scenario(text, "examples/scenarios/" + n + ".yaml");
  throw ScenarioError("no scenario '" + name + "' (built in: " + join_names(scenario_names()) + ")");
}

Scenario find_scenario(const std::string& name_or_file) {
  if (name_or_file.find('/') != std::string::npos || name_or_file.ends_with(".yaml"))
    return load_scenario(name_or_file);
  return builtin_scenario(name_or_file);
}

bool scenario_as_expected(const Scenario& sc, const std::string& reason) {
  const bool passed = reason.empty();
  return passed == sc.expect_pass &&
         (passed || sc.expect_reason.empty() || reason.find(sc.expect_reason) != std::string::npos);
}

trackio::Json scenario_summary_json(const Scenario& sc, const SimRun& run, double wall_time_s,
                                    double sim_wall_time_s) {
  trackio::Json j = sim_summary_json(sc.spec, run, wall_time_s, sim_wall_time_s);
  const std::string reason = scenario_failure(run);
  j["scenario"] = sc.name;
  j["description"] = sc.description;
  j["expect"] = sc.expect_pass ? "pass" : "fail";
  j["verdict"] = reason.empty() ? "pass" : "fail";
  j["reason"] = reason;
  j["as_expected"] = scenario_as_expected(sc, reason);
  return j;
}

std::string scenario_failure(const SimRun& run) {
  if (!run.robot_fault.empty()) return run.robot_fault;
  char buf[256];
  for (std::size_t k = 0; k < run.metrics.size(); ++k) {
    const SeamMetrics& m = run.metrics[k];
    const std::string seam = "seam " + std::to_string(k + 1) + ": ";
    if (!m.failure.empty()) return seam + m.failure;
    if (m.lost) return seam + "the sensor lost the seam after " + std::to_string(static_cast<int>(m.welded_mm)) + " mm";
    if (!m.start_found) return seam + "no start found";
    if (!m.end_found) return seam + "no end found";
    const std::pair<const char*, double> rms[] = {{"rms lateral", m.rms_lateral_mm}, {"rms vertical", m.rms_vertical_mm}};
    for (const auto& [what, v] : rms)
      if (!(v < kScenarioRmsMm)) {
        std::snprintf(buf, sizeof buf, "%s %.3f mm >= %.1f mm", what, v, kScenarioRmsMm);
        return seam + buf;
      }
    if (!(m.max_error_mm < kScenarioMaxMm)) {
      std::snprintf(buf, sizeof buf, "max error %.3f mm >= %.1f mm", m.max_error_mm, kScenarioMaxMm);
      return seam + buf;
    }
  }
  if (run.metrics.empty()) return "no seam welded";
  return {};
}

}  // namespace vts
