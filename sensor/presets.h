#pragma once
// Named scanner descriptions (sensors) and surface parameter sets (materials).
// A sensor preset sets every field of ScannerDesc except the surface fields,
// tool_from_laser and ideal; a material preset sets only the surface fields
// (material .. dropout_prob_grazing). docs/SENSOR_MODEL.md lists them.
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "sensor/scanner.h"

namespace vts {

inline constexpr std::string_view kDefaultSensor = "mspot";
inline constexpr std::string_view kDefaultMaterial = "matte-steel";

// mspot, lps-2048-short, lps-1280-mid
std::vector<std::string> sensor_preset_names();
// The preset with the default material; nullopt for an unknown name.
std::optional<ScannerDesc> sensor_preset(std::string_view name);
// One line saying what the preset models; empty for an unknown name.
std::string sensor_preset_description(std::string_view name);
// Copies the sensor fields (everything but the surface fields, tool_from_laser
// and ideal) of `preset` into `desc`.
void set_sensor_fields(ScannerDesc& desc, const ScannerDesc& preset);

// matte-steel, shiny-steel, aluminium, rough, lambertian
std::vector<std::string> material_names();
std::string material_description(std::string_view name);
// Sets desc's surface fields (and desc.material) to the named material;
// false (desc untouched) for an unknown name.
bool apply_material(ScannerDesc& desc, std::string_view name);

// "a, b, c" for messages.
std::string join_names(const std::vector<std::string>& names);

}  // namespace vts
