#pragma once
#include <CLI/CLI.hpp>

namespace vts::apps {

// `vts plot FILE.exr`: draws profiles of a vts EXR to a PNG. The callback
// stores its exit status in exit_code.
CLI::App* add_plot_command(CLI::App& app, int& exit_code);

}  // namespace vts::apps
