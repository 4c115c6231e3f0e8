#include "sensor/cell.h"

#include <cmath>
#include <numbers>

#include "sensor/presets.h"
#include "sensor/saddle.h"

namespace vts {
namespace {

struct Builtin {
  std::string_view name;
  std::string_view description;
  bool large = false;  // benchmark-sized: not in CellSet::Small
};
constexpr Builtin kBuiltins[] = {
    {"fillet", "90-degree T fillet, sensor on the bisector at 100 mm"},
    {"corner", "90-degree outside corner, sensor straight above the edge at 100 mm"},
    {"lap", "lap joint, 4 mm upper plate, sensor straight above the edge at 100 mm"},
    {"butt", "square butt, 6 mm plates, 1 mm gap, sensor straight above at 100 mm"},
    {"vgroove", "60-degree v-groove, 12 mm plates, 1 mm gap, 1.5 mm root face, at 100 mm"},
    {"plate", "flat plate square to the optical axis at 100 mm (for measuring the sensor)"},
    {"static-A", "paper Table 2 A: 90-degree fillet, sensor at 45 degrees, 63 mm, gap 0"},
    {"static-B", "paper Table 2 B: 90-degree fillet, sensor at 45 degrees, 103 mm, gap 0"},
    {"static-C", "paper Table 2 C: 90-degree fillet, sensor at 45 degrees, 156 mm, gap 0"},
    {"static-D", "paper Table 2 D: 90-degree fillet, sensor at 45 degrees, 55 mm, gap 2 mm"},
    {"static-E", "paper Table 2 E: 90-degree fillet, sensor at 45 degrees, 98 mm, gap 2 mm"},
    {"static-F", "paper Table 2 F: 90-degree fillet, sensor at 45 degrees, 143 mm, gap 2 mm"},
    {"fillet-1m",
     "the fillet 600 mm long, every face a 0.78 mm grid: 1010888 triangles (benchmarks)", true},
    {"vgroove-thick",
     "60-degree v-groove in 40 mm plates, 2 mm gap and root face, 3 passes of 4 mm laid (crown 0.8), "
     "lps-1280-mid at 200 mm"},
    {"bevel", "single bevel, 45 degrees, 12 mm plates, 1 mm gap, 1.5 mm root face, lps-2048-short at 90 mm"},
    {"bevel-thick",
     "single bevel, 45 degrees, 30 mm plates, 2 passes of 4 mm laid (crown 0.8), lps-1280-mid at 200 mm"},
    {"ugroove", "U-groove, 16 degrees included, bottom radius 6 mm, 30 mm plates, 1 mm gap, lps-1280-mid at 200 mm"},
    {"ugroove-fill",
     "the ugroove with 4 passes of 3.5 mm laid (crown 0.6), lps-1280-mid at 200 mm"},
    {"jgroove",
     "J-groove, wall 20 degrees from vertical, bottom radius 6 mm, 25 mm plates, 1 mm gap, lps-1280-mid at 150 mm"},
    {"saddle",
     "pipe saddle: a 100 mm branch set on a 200 mm main pipe (outer diameters), fillet round the curved seam, "
     "4 mm mesh; sensor on the bisector at the flank, 100 mm"},
    {"saddle-1m",
     "the saddle meshed at 0.76 mm: 1006852 triangles, none coplanar with a neighbour but in the end discs (benchmarks)", true},
};

// The groove cells: a joint's defaults changed as listed, seen straight down
// its z by a sensor preset at a standoff from the root (docs/CELLS.md).
struct GrooveCell {
  std::string_view name;
  JointType type;
  double thickness_mm, angle_deg, radius_mm, gap_mm, root_face_mm;
  int passes;
  double layer_mm, crown_mm;
  std::string_view preset;
  double standoff_mm;
};
constexpr GrooveCell kGrooveCells[] = {
    {"vgroove-thick", JointType::VGroove, 40.0, 60.0, 5.0, 2.0, 2.0, 3, 4.0, 0.8, "lps-1280-mid", 200.0},
    {"bevel", JointType::Bevel, 12.0, 45.0, 5.0, 1.0, 1.5, 0, 3.0, 0.5, "lps-2048-short", 90.0},
    {"bevel-thick", JointType::Bevel, 30.0, 45.0, 5.0, 1.0, 1.5, 2, 4.0, 0.8, "lps-1280-mid", 200.0},
    {"ugroove", JointType::UGroove, 30.0, 16.0, 6.0, 1.0, 2.0, 0, 3.0, 0.5, "lps-1280-mid", 200.0},
    {"ugroove-fill", JointType::UGroove, 30.0, 16.0, 6.0, 1.0, 2.0, 4, 3.5, 0.6, "lps-1280-mid", 200.0},
    {"jgroove", JointType::JGroove, 25.0, 20.0, 6.0, 1.0, 2.0, 0, 3.0, 0.5, "lps-1280-mid", 150.0},
};

// fillet-1m: the built-in fillet, longer and densely meshed (docs/CELLS.md).
constexpr double kDenseLengthMm = 600.0;
constexpr double kDenseCellMm = 0.78;

constexpr double kDefaultStandoffMm = 100.0;

// saddle and saddle-1m (docs/CELLS.md "The pipe saddle").
constexpr double kSaddleCellMm = 4.0;
constexpr double kSaddleDenseCellMm = 0.76;
// The default path over a saddle: past the flank at t = 3 pi / 2 (y = -r),
// where the seam runs along +x, centred on it.
constexpr double kSaddleStepMm = 0.2;
constexpr int kSaddleProfiles = 100;

Cell single_workpiece_cell(std::string_view name, JointType type, const JointParams& params,
                           double standoff_mm) {
  Cell cell;
  cell.name = std::string(name);
  cell.workpieces.push_back(build_workpiece(type, params));
  cell.path = default_path(cell.workpieces.front(), standoff_mm);
  return cell;
}

}  // namespace

Pose ScanPath::pose_at(std::int64_t i) const {
  Pose p = start;
  p.translation() += static_cast<double>(i) * step_mm * direction;
  return p;
}

Mesh Cell::mesh() const {
  Mesh m;
  for (const auto& w : workpieces) m.append(w.mesh());
  return m;
}

Pose sensor_pose_looking_at(const Vec3& target_world, const Vec3& from_dir, double standoff_mm,
                            const Vec3& travel_world) {
  Pose pose = Pose::Identity();
  const Vec3 eye = target_world + standoff_mm * from_dir.normalized();
  pose_look_at(eye, target_world, travel_world, pose);
  return pose;
}

Vec3 default_view_direction(const Workpiece& w) {
  if (w.type == JointType::Fillet) {
    const double half = 0.5 * w.params.angle_deg * std::numbers::pi / 180.0;
    return Vec3(0.0, std::cos(half), std::sin(half));
  }
  return Vec3::UnitZ();
}

ScanPath default_path(const Workpiece& w, double standoff_mm, double start_mm) {
  ScanPath path;
  if (w.saddle) {
    path.start = saddle_sensor_pose(*w.saddle, w.world_from_joint, 1.5 * std::numbers::pi, standoff_mm);
    path.direction = w.world_from_joint.linear() * Vec3::UnitX();
    path.step_mm = kSaddleStepMm;
    path.profiles = kSaddleProfiles;
    path.start.translation() -= 0.5 * kSaddleStepMm * kSaddleProfiles * path.direction;
    return path;
  }
  const Vec3 dir = w.seam_direction();
  const Vec3 target = w.world_from_joint * Vec3(start_mm, w.truth.root_yz.x(), w.truth.root_yz.y());
  path.start = sensor_pose_looking_at(target, w.world_from_joint.linear() * default_view_direction(w),
                                      standoff_mm, dir);
  path.direction = dir;
  return path;
}

std::vector<std::string> builtin_cell_names(CellSet set) {
  std::vector<std::string> names;
  for (const auto& b : kBuiltins)
    if (set == CellSet::All || !b.large) names.emplace_back(b.name);
  return names;
}

std::string builtin_cell_description(std::string_view name) {
  for (const auto& b : kBuiltins)
    if (b.name == name) return std::string(b.description);
  return {};
}

std::optional<Cell> builtin_cell(std::string_view name) {
  for (const auto& s : kStaticSetups) {
    if (name == std::string("static-") + s.label) {
      JointParams p = default_params(JointType::Fillet);
      p.gap_mm = s.gap_mm;
      return single_workpiece_cell(name, JointType::Fillet, p, s.distance_mm);
    }
  }
  if (name == "plate" || name == "fillet" || name == "corner" || name == "lap" || name == "butt" ||
      name == "vgroove") {
    const JointType type = *joint_type_from_string(name);
    return single_workpiece_cell(name, type, default_params(type), kDefaultStandoffMm);
  }
  for (const GrooveCell& g : kGrooveCells) {
    if (name != g.name) continue;
    JointParams p = default_params(g.type);
    p.thickness_mm = g.thickness_mm;
    p.angle_deg = g.angle_deg;
    p.radius_mm = g.radius_mm;
    p.gap_mm = g.gap_mm;
    p.root_face_mm = g.root_face_mm;
    p.passes = g.passes;
    p.layer_mm = g.layer_mm;
    p.crown_mm = g.crown_mm;
    Cell cell = single_workpiece_cell(name, g.type, p, g.standoff_mm);
    cell.scanner = *sensor_preset(g.preset);
    return cell;
  }
  if (name == "saddle" || name == "saddle-1m") {
    SaddleParams p;
    p.cell_mm = name == "saddle" ? kSaddleCellMm : kSaddleDenseCellMm;
    Cell cell;
    cell.name = std::string(name);
    cell.workpieces.push_back(saddle_workpiece(p));
    cell.path = default_path(cell.workpieces.front(), kDefaultStandoffMm);
    return cell;
  }
  if (name == "fillet-1m") {
    JointParams p = default_params(JointType::Fillet);
    p.length_mm = kDenseLengthMm;
    p.cell_mm = kDenseCellMm;
    return single_workpiece_cell(name, JointType::Fillet, p, kDefaultStandoffMm);
  }
  return std::nullopt;
}

}  // namespace vts
