#pragma once
// A cell: workpieces, the scanner and a straight scan path. Built in by name
// or read from a scene file (sensor/scene_file.h).
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "sensor/mesh.h"
#include "sensor/scanner.h"
#include "sensor/workpiece.h"

namespace vts {

// A straight path: profile i is taken at start translated by i * step_mm
// along direction (orientation fixed), at time i / rate_hz.
struct ScanPath {
  Pose start = Pose::Identity();   // world_from_sensor at profile 0
  Vec3 direction = Vec3::UnitX();  // world, unit
  double step_mm = 0.5;
  int profiles = 100;

  Pose pose_at(std::int64_t i) const;
};

struct Cell {
  std::string name;          // "static-B", or the scene file's name
  std::vector<Workpiece> workpieces;
  ScannerDesc scanner;
  ScanPath path;

  Mesh mesh() const;  // all workpieces, world frame
};

// The default path over a workpiece: the optical axis looks at the seam
// start (x = start_mm along the seam) from the joint's natural viewing
// direction (fillet: the open angle's bisector; corner, lap, butt, v-groove,
// plate: straight down the joint's z) at standoff_mm, travelling along the seam.
// A saddle (sensor/saddle.h): on the bisector at its flank t = 3 pi / 2,
// travelling along the main pipe's axis (the seam's tangent there) in 100
// steps of 0.2 mm centred on the flank; start_mm is not used.
// A mesh workpiece has no seam: the path then looks at its joint frame's x
// axis, which means nothing (scene files require path.start for it).
ScanPath default_path(const Workpiece& workpiece, double standoff_mm, double start_mm = 20.0);
// Unit vector (joint frame) from the root towards the sensor for default_path.
Vec3 default_view_direction(const Workpiece& workpiece);

// Which built-in cells builtin_cell_names() lists. Small leaves out the
// benchmark-sized ones (fillet-1m, saddle-1m), for loops that build or scan every cell.
enum class CellSet { All, Small };

// fillet, corner, lap, butt, vgroove, plate, static-A .. static-F, fillet-1m,
// vgroove-thick, bevel, bevel-thick, ugroove, ugroove-fill, jgroove, saddle, saddle-1m
std::vector<std::string> builtin_cell_names(CellSet set = CellSet::All);
inline constexpr std::string_view kDefaultCell = "static-B";
std::optional<Cell> builtin_cell(std::string_view name);
// One line saying what the built-in cell is; empty for an unknown name.
std::string builtin_cell_description(std::string_view name);

// Sensor pose with the optical axis looking at target_world along -from_dir
// (from_dir: unit, world, pointing from target to sensor), at standoff_mm from
// the target, travel (x) along travel_world.
Pose sensor_pose_looking_at(const Vec3& target_world, const Vec3& from_dir,
                            double standoff_mm, const Vec3& travel_world);

// The paper's Table 2 (static experiment, 90-degree fillet, optical axis at
// 45 degrees to both plates). Distance: laser origin to the joint root along
// the optical axis. Gap: web plate lifted off the flange. See docs/CELLS.md.
struct StaticSetup {
  char label;
  double distance_mm;
  double gap_mm;
};
inline constexpr StaticSetup kStaticSetups[] = {
    {'A', 63.0, 0.0}, {'B', 103.0, 0.0}, {'C', 156.0, 0.0},
    {'D', 55.0, 2.0}, {'E', 98.0, 2.0},  {'F', 143.0, 2.0}};

}  // namespace vts
