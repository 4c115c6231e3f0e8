#pragma once
#include <CLI/CLI.hpp>

namespace vts::apps {

// `vts peaks IMAGE`: the stripe peak detector (stripe/peaks.h) on a greyscale
// camera image; per column the chosen and the other peaks as CSV, and with
// --sensor the profile (docs/PEAKS.md). The callback stores its exit status
// in exit_code.
CLI::App* add_peaks_command(CLI::App& app, int& exit_code);

}  // namespace vts::apps
