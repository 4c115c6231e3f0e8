#include "apps/vts_mesh.h"

#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <stdexcept>
#include <string>

#include "apps/cli.h"
#include "sensor/cell.h"
#include "sensor/mesh_file.h"

namespace vts::apps {
namespace {

namespace fs = std::filesystem;

struct MeshOptions {
  std::string cell;
  std::string scene;
  std::string out;
};

using InputError = cli::UsageError;

int run_mesh(const MeshOptions& o) {
  // Everything is checked before anything is written.
  if (o.out.empty()) throw InputError("--out: missing: give the mesh file to write (FILE.stl, FILE.ply or FILE.obj)");
  const fs::path out = fs::path(o.out);
  const std::string ext = out.extension().string();
  if (ext != ".stl" && ext != ".ply" && ext != ".obj" && ext != ".STL" && ext != ".PLY" && ext != ".OBJ")
    throw InputError("--out = '" + o.out + "': unsupported mesh file type '" + ext + "' (expected " +
                     std::string(kMeshFileTypes) + ")");
  std::error_code ec;
  if (fs::is_directory(out, ec)) throw InputError("--out = '" + o.out + "': is a directory, expected a file name");

  const auto [cell, label] = cli::load_cell(o.cell, o.scene);
  const Mesh mesh = cell.mesh();
  if (mesh.triangles.empty()) throw InputError(label + ": the cell has no triangles to write");
  if (const fs::path dir = out.parent_path(); !dir.empty()) {
    fs::create_directories(dir, ec);
    if (ec) throw std::runtime_error("--out: cannot create directory '" + dir.string() + "': " + ec.message());
  }
  write_mesh_file(out, mesh);  // MeshFileError is a runtime failure here (exit 1)
  const MeshLoadStats edges = mesh_edge_stats(mesh);
  std::printf("wrote %zu triangles, %zu vertices (world frame, mm) of %s to %s; %s\n", mesh.triangle_count(),
              mesh.vertices.size(), label.c_str(), out.c_str(),
              edges.closed() ? "closed" : (std::to_string(edges.open_edges) + " open edges, " +
                                           std::to_string(edges.nonmanifold_edges) + " non-manifold edges")
                                              .c_str());
  return cli::kExitOk;
}

}  // namespace

CLI::App* add_mesh_command(CLI::App& app, int& exit_code) {
  auto o = std::make_shared<MeshOptions>();
  CLI::App* cmd = app.add_subcommand(
      "mesh",
      "Write a cell's workpieces (world frame, mm) to a mesh file: binary STL, binary PLY or OBJ, by the "
      "extension of --out. A scene file can then scan it back as a mesh workpiece (docs/SCENE_FORMAT.md)");
  cmd->option_defaults()->always_capture_default(false);
  auto* cell = cmd->add_option("--cell", o->cell,
                               "Built-in cell (list: `vts cells`), e.g. fillet-1m (1,010,888 triangles). "
                               "Default: static-B")
                   ->type_name("NAME");
  auto* scene = cmd->add_option("--scene", o->scene, "Scene file instead of a built-in cell (YAML, docs/SCENE_FORMAT.md)")
                    ->type_name("FILE");
  cell->excludes(scene);
  scene->excludes(cell);
  cmd->add_option("--out", o->out,
                  "Mesh file to write: FILE.stl (binary STL), FILE.ply (binary little-endian PLY) or FILE.obj; "
                  "written whole or not at all; missing directories are created")
      ->type_name("FILE")
      ->required();
  cmd->callback([o, &exit_code] {
    try {
      exit_code = run_mesh(*o);
    } catch (const InputError& e) {
      std::cerr << "vts mesh: " << e.what() << "\n";
      exit_code = cli::kExitUsage;
    }
  });
  return cmd;
}

}  // namespace vts::apps
