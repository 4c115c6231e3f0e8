#pragma once
#include <string>

#include <CLI/CLI.hpp>

#include "pipeline/sim_run.h"

namespace vts::apps {

// `vts sim`: the paper's dynamic experiment, headless and faster than real
// time: the master welds the two seams of the box cell guided by the virtual
// sensor (docs/SIM.md). The callback stores its exit status in exit_code.
CLI::App* add_sim_command(CLI::App& app, int& exit_code);

// The box cell's options, shared by `vts sim` and `vts serve`: the cell's
// displacement and seed, the sensor, the source, the speed, --threads.
struct BoxOptions {
  std::string speed, rate, seed, offset, rotation, source, sensor, material, threads, robot, robot_seed;
  bool ideal = false;
};
void add_box_options(CLI::App* cmd, BoxOptions& options);
// The experiment's spec from them; throws cli::UsageError naming the option
// and the value.
SimSpec box_spec(const BoxOptions& options);
// With a scenario, whose file sets them, the box's options are refused:
// UsageError "--seed = '4': a scenario sets it in its file; not with WITH".
void refuse_box_options(const BoxOptions& options, const std::string& with);
// --sensor, --material and --ideal onto a scanner.
void apply_sensor_options(const BoxOptions& options, ScannerDesc& scanner);

}  // namespace vts::apps
