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

Cell load_scene(const std::filesystem::path& path);        // throws SceneError
Cell parse_scene(const std::string& yaml_text, const std::string& file_name);
std::string scene_to_yaml(const Cell& cell);  // parse_scene(scene_to_yaml(c)) == c

}  // namespace vts
