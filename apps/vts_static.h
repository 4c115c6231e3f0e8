#pragma once
#include <CLI/CLI.hpp>

namespace vts::apps {

// `vts static`: the paper's static experiment (docs/STATIC.md). Scans the
// built-in setups static-A .. static-F, tracks them with the fillet template
// and writes the paper's Table 3 (CSV and Markdown) and one PNG per setup
// (the paper's Figure 7) to --out-dir. The callback stores its exit status in
// exit_code.
CLI::App* add_static_command(CLI::App& app, int& exit_code);

}  // namespace vts::apps
