#pragma once
#include <CLI/CLI.hpp>

namespace vts::apps {

// `vts sensors`: lists the sensor presets with their depth resolution at near
// and far range, and the material presets; `--plot FILE.png` draws one
// sensor's resolution against range. The callback stores its exit status in
// exit_code.
CLI::App* add_sensors_command(CLI::App& app, int& exit_code);

}  // namespace vts::apps
