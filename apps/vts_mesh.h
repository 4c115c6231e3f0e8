#pragma once
#include <CLI/CLI.hpp>

namespace vts::apps {

// `vts mesh`: writes a built-in cell's or a scene's workpieces, world frame,
// mm, to a mesh file (binary STL, binary PLY or OBJ by the extension), e.g.
// the 1,010,888-triangle fillet-1m to scan back through a scene file
// (docs/CLI.md). The callback stores its exit status in exit_code.
CLI::App* add_mesh_command(CLI::App& app, int& exit_code);

}  // namespace vts::apps
