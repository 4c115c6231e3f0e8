#pragma once
#include <CLI/CLI.hpp>

namespace vts::apps {

// `vts sim`: the paper's dynamic experiment, headless and faster than real
// time: the master welds the two seams of the box cell guided by the virtual
// sensor (docs/SIM.md). The callback stores its exit status in exit_code.
CLI::App* add_sim_command(CLI::App& app, int& exit_code);

}  // namespace vts::apps
