#pragma once
// Scene files: YAML describing workpieces, scanner and path
// (docs/SCENE_FORMAT.md).
#include <filesystem>
#include <stdexcept>
#include <string>

#include "sensor/cell.h"

namespace vts {

// what() reads "FILE:LINE: FIELD: message" (line 1-based).
struct SceneError : std::runtime_error {
  SceneError(const std::string& file, int line, const std::string& field,
             const std::string& message);
  std::string file, field;
  int line = 0;
};

// Whether mesh workpieces' files are read. Skip leaves each mesh workpiece's
// file_mesh empty (everything else as read, the file unchecked): for reading
// what a recording's stored scene says without its meshes.
enum class MeshFiles { Load, Skip };

// Relative mesh paths are resolved against the scene file's directory
// (parse_scene: file_name's). A mesh file that cannot be read is a SceneError
// at the workpiece's `mesh` key, quoting the MeshFileError.
Cell load_scene(const std::filesystem::path& path,
                MeshFiles meshes = MeshFiles::Load);  // throws SceneError
Cell parse_scene(const std::string& yaml_text, const std::string& file_name,
                 MeshFiles meshes = MeshFiles::Load);
// Mesh workpieces are written with their absolute mesh_file.
std::string scene_to_yaml(const Cell& cell);  // parse_scene(scene_to_yaml(c)) == c

}  // namespace vts
