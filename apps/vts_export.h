#pragma once
#include <CLI/CLI.hpp>

namespace vts::apps {

// `vts export FILE.exr --out OUT [--format csv|ply|npz]`: a profile EXR as
// CSV (the columns `vts track` reads), a PLY point cloud (world frame) or a
// NumPy .npz (sensor/profile_export.h, docs/CLI.md). The callback stores its
// exit status in exit_code.
CLI::App* add_export_command(CLI::App& app, int& exit_code);

}  // namespace vts::apps
