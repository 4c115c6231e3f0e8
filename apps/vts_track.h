#pragma once
#include <CLI/CLI.hpp>

namespace vts::apps {

// `vts track FILE`: runs the seam tracker on every profile of a vts EXR or a
// CSV file and writes one JSON object per profile (JSON Lines) to stdout or
// --out (docs/CLI.md). The callback stores its exit status in exit_code.
CLI::App* add_track_command(CLI::App& app, int& exit_code);

}  // namespace vts::apps
