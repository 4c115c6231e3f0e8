#pragma once
// Scenarios of `vts sim` (issue 19, docs/SIM.md): a scenario file names a
// box cell with its disturbances (fixture error, a curved seam, a gap that
// opens, tack welds), the robot, the sensor and the program (speed,
// weaving, search margin), and the verdict the suite expects. The files
// under examples/scenarios/ are compiled in (`vts sim --scenarios`); any
// other file is read by path.
//
//     name: arm-tacks                 # defaults to the file's stem
//     description: "..."
//     expect: pass                    # pass | fail
//     expect_reason: "seam lost"      # with fail: a part of the reason
//     seed: 3                          # workpiece displacement and error model
//     offset_mm: 10                    # SimCellParams ...
//     rotation_deg: 5
//     seam1_bow_mm: 0
//     seam1_gap_rise_mm: 0
//     seam1_short_mm: 0
//     tack_spacing_mm: 0               # tack_first_mm, tack_length_mm, tack_leg_mm
//     workpiece: box                   # box | saddle (main_radius_mm, branch_radius_mm, main_length_mm,
//                                      #   branch_height_mm, cell_mm: sensor/saddle.h)
//     lookahead_mm: 50                 # the laser plane ahead of the TCP
//     robot: kr16                      # perfect | irb2400 | kr16
//     robot_seed: 3
//     sensor: mspot                    # a `vts sensors` preset; material, ideal, rate_hz
//     source: reference                # raster | reference (default reference)
//     speed_mm_s: 10
//     search_margin_mm: 20             # the program's first search (default: the cell's largest displacement)
//     weave_amplitude_mm: 0            # weave_frequency_hz, weave_dwell_s
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "pipeline/sim_run.h"

namespace vts {

// what() reads "FILE:LINE: FIELD: message".
struct ScenarioError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// A tracked weld passes when every seam was found, welded and ended, the
// robot did not stop, and each seam's rms lateral and vertical error stays
// under kScenarioRmsMm and its largest error under kScenarioMaxMm.
inline constexpr double kScenarioRmsMm = 0.2;
inline constexpr double kScenarioMaxMm = 0.5;

struct Scenario {
  std::string name, description, file;
  bool expect_pass = true;
  std::string expect_reason;  // with expect_pass false: a part of the reason the run must give
  SimSpec spec;
};

// Throws ScenarioError (a bad value names the file, line and key).
Scenario parse_scenario(const std::string& yaml_text, const std::string& file_name);
Scenario load_scenario(const std::filesystem::path& path);
// The compiled-in scenarios, by name (sorted); a name not among them throws
// ScenarioError listing them.
std::vector<std::string> scenario_names();
Scenario builtin_scenario(const std::string& name);
// What a front-end's --scenario names: a file when it has a '/' or ends in
// .yaml, else a built-in scenario.
Scenario find_scenario(const std::string& name_or_file);

// The verdict on a run: empty when it passes, else why not ("seam 1: seam
// lost", "seam 2: rms lateral 0.31 mm > 0.2 mm", "the robot stopped: ...").
std::string scenario_failure(const SimRun& run);
// Whether a run failing for `reason` (empty: passed) is what the file expects.
bool scenario_as_expected(const Scenario& scenario, const std::string& reason);
// The run's summary (sim_summary_json) with the scenario's name,
// description, expected verdict, the verdict, its reason and as_expected.
trackio::Json scenario_summary_json(const Scenario& scenario, const SimRun& run, double wall_time_s,
                                    double sim_wall_time_s);

}  // namespace vts
