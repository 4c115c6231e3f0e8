#pragma once
#include <CLI/CLI.hpp>

namespace vts::apps {

// `vts serve`: the box cell with its virtual robot and sensor on a TCP port
// (server/, docs/PROTOCOL.md). The callback stores its exit status in exit_code.
CLI::App* add_serve_command(CLI::App& app, int& exit_code);

}  // namespace vts::apps
