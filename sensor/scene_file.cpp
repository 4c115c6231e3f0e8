#include "sensor/scene_file.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <sstream>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

#include "sensor/mesh_file.h"
#include "sensor/presets.h"
#include "sensor/saddle.h"
#include "sensor/yaml_io.h"

namespace vts {

namespace {

// Scanner fields read and written by name beyond the special ones (name,
// preset, material, points, tool_from_laser, ideal); docs/SCENE_FORMAT.md.
struct NumberKey {
  const char* key;
  double ScannerDesc::*member;
};
struct IntKey {
  const char* key;
  int ScannerDesc::*member;
};
constexpr NumberKey kScannerNumbers[] = {
    {"fan_deg", &ScannerDesc::fan_deg},
    {"rate_hz", &ScannerDesc::rate_hz},
    {"min_range_mm", &ScannerDesc::min_range_mm},
    {"max_range_mm", &ScannerDesc::max_range_mm},
    {"max_hit_mm", &ScannerDesc::max_hit_mm},
    {"max_incidence_deg", &ScannerDesc::max_incidence_deg},
    {"baseline_mm", &ScannerDesc::baseline_mm},
    {"triangulation_deg", &ScannerDesc::triangulation_deg},
    {"focal_length_mm", &ScannerDesc::focal_length_mm},
    {"pixel_pitch_um", &ScannerDesc::pixel_pitch_um},
    {"subpixel_step_px", &ScannerDesc::subpixel_step_px},
    {"intensity_ref_range_mm", &ScannerDesc::intensity_ref_range_mm},
    {"speckle_px", &ScannerDesc::speckle_px},
    {"reflectivity", &ScannerDesc::reflectivity},
    {"shiny_cluster_prob", &ScannerDesc::shiny_cluster_prob},
    {"shiny_offset_min_mm", &ScannerDesc::shiny_offset_min_mm},
    {"shiny_offset_max_mm", &ScannerDesc::shiny_offset_max_mm},
    {"rough_outlier_prob", &ScannerDesc::rough_outlier_prob},
    {"rough_offset_min_mm", &ScannerDesc::rough_offset_min_mm},
    {"rough_offset_max_mm", &ScannerDesc::rough_offset_max_mm},
    {"dropout_prob_normal", &ScannerDesc::dropout_prob_normal},
    {"dropout_prob_grazing", &ScannerDesc::dropout_prob_grazing},
    {"scheimpflug_deg", &ScannerDesc::scheimpflug_deg},
    {"f_number", &ScannerDesc::f_number},
    {"wavelength_nm", &ScannerDesc::wavelength_nm},
    {"psf_sigma_px", &ScannerDesc::psf_sigma_px},
    {"laser_power_mw", &ScannerDesc::laser_power_mw},
    {"sheet_waist_mm", &ScannerDesc::sheet_waist_mm},
    {"sheet_focus_mm", &ScannerDesc::sheet_focus_mm},
    {"sheet_m2", &ScannerDesc::sheet_m2},
    {"exposure_us", &ScannerDesc::exposure_us},
    {"gain", &ScannerDesc::gain},
    {"quantum_efficiency", &ScannerDesc::quantum_efficiency},
    {"full_well_e", &ScannerDesc::full_well_e},
    {"read_noise_e", &ScannerDesc::read_noise_e},
    {"dark_offset_dn", &ScannerDesc::dark_offset_dn},
    {"ambient_w_m2", &ScannerDesc::ambient_w_m2},
    {"specular_reflectance", &ScannerDesc::specular_reflectance},
    {"specular_lobe_deg", &ScannerDesc::specular_lobe_deg},
    {"speckle_contrast", &ScannerDesc::speckle_contrast},
    {"peak_threshold_dn", &ScannerDesc::peak_threshold_dn},
};
constexpr IntKey kScannerInts[] = {
    {"roi_first_column", &ScannerDesc::roi_first_column},
    {"roi_last_column", &ScannerDesc::roi_last_column},
    {"image_width_px", &ScannerDesc::image_width_px},
    {"image_height_px", &ScannerDesc::image_height_px},
    {"shiny_cluster_max_points", &ScannerDesc::shiny_cluster_max_points},
    {"image_bits", &ScannerDesc::image_bits},
    {"image_roi_first_row", &ScannerDesc::image_roi_first_row},
    {"image_roi_rows", &ScannerDesc::image_roi_rows},
    {"peak_window_px", &ScannerDesc::peak_window_px},
};

using yaml_io::describe;
using yaml_io::Field;
using yaml_io::join;
using yaml_io::num;
const auto yaml_quoted = yaml_io::quoted;

class Parser : public yaml_io::Reader {
 public:
  Parser(std::string file, MeshFiles meshes)
      : Reader(std::move(file)), dir_(std::filesystem::path(file_).parent_path()), meshes_(meshes) {}

  void raise(int line, const std::string& field, const std::string& msg) const override {
    throw SceneError(file_, line, field, msg);
  }

  Pose pose(const Field& f) const {
    const Map m(*this, f, {"position_mm", "rpy_deg"});
    Vec3 p = Vec3::Zero(), rpy = Vec3::Zero();
    if (auto x = m.get("position_mm")) p = vec3(*x);
    if (auto x = m.get("rpy_deg")) rpy = vec3(*x);
    return pose_from_xyz_rpy(p, rpy);
  }

  // Order: the sensor preset (all sensor fields), then the material preset
  // (all surface fields), then each field given.
  ScannerDesc scanner(const Field& f) const {
    std::vector<std::string> allowed = {"name", "preset", "material", "points", "tool_from_laser",
                                        "ideal"};
    for (const auto& k : kScannerNumbers) allowed.emplace_back(k.key);
    for (const auto& k : kScannerInts) allowed.emplace_back(k.key);
    const Map m(*this, f, allowed);
    ScannerDesc d;
    if (auto x = m.get("preset")) {
      const std::string name = string(*x);
      const auto preset = sensor_preset(name);
      if (!preset)
        fail(*x, "unknown sensor preset '" + name + "' (expected one of: " +
                     join_names(sensor_preset_names()) + "; see `vts sensors`)");
      set_sensor_fields(d, *preset);
    }
    if (auto x = m.get("material")) {
      const std::string name = string(*x);
      if (!apply_material(d, name))
        fail(*x, "unknown material '" + name + "' (expected one of: " +
                     join_names(material_names()) + ")");
    }
    if (auto x = m.get("name")) d.name = string(*x);
    if (auto x = m.get("points")) {
      const long long n = integer(*x);
      if (n < kMinPoints || n > kMaxPoints)
        fail(*x, "points = " + std::to_string(n) + ": must be between 16 and 4096");
      d.points = static_cast<int>(n);
    }
    for (const auto& k : kScannerNumbers)
      if (auto x = m.get(k.key)) d.*k.member = number(*x);
    for (const auto& k : kScannerInts)
      if (auto x = m.get(k.key)) d.*k.member = int_field(*x, k.key);
    if (auto x = m.get("tool_from_laser")) d.tool_from_laser = pose(*x);
    if (auto x = m.get("ideal")) d.ideal = boolean(*x);
    if (const std::string err = validate(d); !err.empty()) fail_validation(m, err);
    return d;
  }

  JointType joint_type(const Field& f) const {
    const std::string name = string(f);
    const auto type = joint_type_from_string(name);
    if (!type)
      fail(f, "unknown joint '" + name +
                  "' (expected one of: fillet, corner, lap, butt, vgroove, bevel, ugroove, jgroove, plate)");
    return *type;
  }

  // `unit`: a name, or a number of mm per file unit.
  double mesh_unit(const Field& f) const {
    static const std::string kExpected = "mm, cm, m, in, or a number: mm per file unit";
    if (!f.node.IsScalar()) fail(f, "expected " + kExpected + ", got " + describe(f.node));
    const std::string s = f.node.Scalar();
    if (const auto mm = mesh_unit_mm(s)) return *mm;
    const auto v = try_number(f);
    if (!v) fail(f, "unknown unit '" + s + "' (expected " + kExpected + ")");
    if (!std::isfinite(*v)) fail(f, "must be a finite number, got '" + s + "'");
    if (*v <= 0.0) fail(f, "unit = " + s + ": must be > 0 (mm per file unit)");
    return *v;
  }

  // A mesh workpiece: mesh, unit, joint, pose.
  Workpiece mesh_workpiece_item(const Field& f) const {
    const Map m(*this, f, {"mesh", "unit", "joint", "pose"});
    const Field mf = m.require("mesh");
    if (!mf.node.IsScalar()) fail(mf, "expected a mesh file name, got " + describe(mf.node));
    const std::string given = mf.node.Scalar();
    if (given.empty()) fail(mf, "expected a mesh file name, got ''");
    double unit_mm = 1.0;
    if (auto x = m.get("unit")) unit_mm = mesh_unit(*x);
    std::optional<JointType> joint;
    if (auto x = m.get("joint")) joint = joint_type(*x);
    Pose world_from_joint = Pose::Identity();
    if (auto x = m.get("pose")) world_from_joint = pose(*x);

    // Relative to the scene file's directory; messages name it that way.
    const std::filesystem::path file =
        std::filesystem::path(given).is_relative() ? dir_ / given : std::filesystem::path(given);
    std::shared_ptr<const Mesh> mesh;
    MeshLoadStats stats;
    if (meshes_ == MeshFiles::Load) {
      try {
        mesh = std::make_shared<const Mesh>(load_mesh_file(file, unit_mm, &stats));
      } catch (const MeshFileError& e) {
        fail(mf, e.what());
      }
    }
    stats.file = file.string();
    Workpiece w = mesh_workpiece(mesh, world_from_joint, joint, &stats);
    std::error_code ec;
    const std::filesystem::path absolute = std::filesystem::absolute(file, ec);
    w.mesh_file = (ec ? file : absolute).lexically_normal().string();
    w.mesh_unit_mm = unit_mm;
    return w;
  }

  // A pipe saddle: saddle (its parameters), pose.
  Workpiece saddle_item(const Field& f) const {
    const Map m(*this, f, {"saddle", "pose"});
    std::vector<std::string> allowed;
    for (const auto& k : kSaddleParamNumbers) allowed.emplace_back(k.key);
    const Map sm(*this, m.require("saddle"), allowed);
    SaddleParams p;
    for (const auto& k : kSaddleParamNumbers)
      if (auto x = sm.get(k.key)) p.*k.member = number(*x);
    if (const std::string err = validate(p); !err.empty()) fail_validation(sm, err);
    Pose world_from_saddle = Pose::Identity();
    if (auto x = m.get("pose")) world_from_saddle = pose(*x);
    return saddle_workpiece(p, world_from_saddle);
  }

  Workpiece workpiece(const Field& f) const {
    if (has_key(f.node, "saddle")) return saddle_item(f);
    if (has_key(f.node, "mesh")) return mesh_workpiece_item(f);
    std::vector<std::string> allowed = {"joint", "pose"};
    for (const auto& k : kJointParamNumbers) allowed.emplace_back(k.key);
    allowed.emplace_back("passes");
    allowed.emplace_back("mesh");
    const Map m(*this, f, allowed);

    const JointType type = joint_type(m.require("joint"));
    JointParams p = default_params(type);
    for (const auto& k : kJointParamNumbers)
      if (auto x = m.get(k.key)) p.*k.member = number(*x);
    if (auto x = m.get("passes")) p.passes = int_field(*x, "passes");
    if (const std::string err = validate(type, p); !err.empty()) fail_validation(m, err);

    Pose world_from_joint = Pose::Identity();
    if (auto x = m.get("pose")) world_from_joint = pose(*x);
    return build_workpiece(type, p, world_from_joint);
  }

  // first_mesh_line: the line of workpieces[0].mesh, 0 if it is a joint.
  ScanPath path(const std::optional<Field>& f, const Workpiece& first, const ScannerDesc& scanner,
                int first_mesh_line) const {
    constexpr double kDefaultStandoffMm = 100.0;
    static const char* const kNeedsStart =
        "missing (required when workpieces[0] is a mesh: a mesh has no seam to derive the default path from)";
    if (!f) {
      if (first.is_mesh() && !first.saddle) fail(first_mesh_line, "path.start", kNeedsStart);
      return default_path(first, kDefaultStandoffMm);
    }
    const Map m(*this, *f, {"start", "standoff_mm", "direction", "step_mm", "speed_mm_s", "profiles"});
    if (first.is_mesh() && !first.saddle && !m.get("start")) fail(m.self().line(), "path.start", kNeedsStart);

    double standoff_mm = kDefaultStandoffMm;
    if (auto x = m.get("standoff_mm")) {
      if (auto s = m.get("start"))
        fail(*x, "give either start or standoff_mm, not both (start is on line " +
                     std::to_string(s->key_line) + ")");
      standoff_mm = number(*x);
      if (standoff_mm <= 0.0) fail(*x, "standoff_mm = " + num(standoff_mm) + ": must be > 0");
    }
    ScanPath path = default_path(first, standoff_mm);

    if (auto x = m.get("direction")) {
      const Vec3 d = vec3(*x);
      if (d.norm() < 1e-12) fail(*x, "direction must not be zero");
      path.direction = d.normalized();
    }

    if (auto x = m.get("step_mm")) {
      if (auto s = m.get("speed_mm_s"))
        fail(*s, "give either step_mm or speed_mm_s, not both (step_mm is on line " +
                     std::to_string(x->key_line) + ")");
      path.step_mm = number(*x);
      if (path.step_mm <= 0.0) fail(*x, "step_mm = " + num(path.step_mm) + ": must be > 0");
    } else if (auto s = m.get("speed_mm_s")) {
      const double speed = number(*s);
      if (speed <= 0.0) fail(*s, "speed_mm_s = " + num(speed) + ": must be > 0");
      path.step_mm = speed / scanner.rate_hz;
    }

    if (auto x = m.get("profiles")) {
      const long long n = integer(*x);
      if (n < 1 || n > std::numeric_limits<int>::max())
        fail(*x, "profiles = " + std::to_string(n) + ": must be between 1 and " +
                     std::to_string(std::numeric_limits<int>::max()));
      path.profiles = static_cast<int>(n);
    }

    if (auto x = m.get("start")) path.start = start_pose(*x, path.direction);
    return path;
  }

  Pose start_pose(const Field& f, const Vec3& path_direction) const {
    const Map m(*this, f, {"position_mm", "rpy_deg", "look_at_mm", "travel"});
    const Vec3 position = vec3(m.require("position_mm"));
    const auto rpy = m.get("rpy_deg");
    const auto look = m.get("look_at_mm");
    const auto travel = m.get("travel");
    if (rpy && look)
      fail(*look, "give either rpy_deg or look_at_mm, not both (rpy_deg is on line " +
                      std::to_string(rpy->key_line) + ")");
    if (travel && !look) fail(*travel, "travel is only used with look_at_mm");
    if (rpy) return pose_from_xyz_rpy(position, vec3(*rpy));
    if (!look) fail(m.self().line(), m.self().path, "needs rpy_deg or look_at_mm");
    const Vec3 target = vec3(*look);
    Vec3 travel_dir = path_direction;
    if (travel) {
      travel_dir = vec3(*travel);
      if (travel_dir.norm() < 1e-12) fail(*travel, "travel must not be zero");
    }
    Pose pose;
    if ((target - position).norm() < 1e-9) fail(*look, "look_at_mm must differ from position_mm");
    if (!pose_look_at(position, target, travel_dir, pose))
      fail(travel ? *travel : *look,
           "travel direction is parallel to the viewing direction (position_mm -> look_at_mm); "
           "give a travel that is not");
    return pose;
  }

  Cell cell(const YAML::Node& root, const std::string& default_name) const {
    if (root.IsNull()) fail(1, "", "empty scene (expected a map with workpieces)");
    const Map m(*this, Field{root, "", 1}, {"name", "scanner", "workpieces", "path"});
    Cell cell;
    cell.name = default_name;
    if (auto x = m.get("name")) {
      cell.name = string(*x);
      if (cell.name.empty()) fail(*x, "name must not be empty");
    }
    if (auto x = m.get("scanner")) cell.scanner = scanner(*x);

    const Field wf = m.require("workpieces");
    if (!wf.node.IsSequence()) fail(wf, "expected a list of workpieces, got " + describe(wf.node));
    if (wf.node.size() == 0) fail(wf, "needs at least one workpiece");
    for (std::size_t i = 0; i < wf.node.size(); ++i) {
      const YAML::Node n = wf.node[i];
      cell.workpieces.push_back(
          workpiece(Field{n, "workpieces[" + std::to_string(i) + "]", 0, wf.line()}));
    }
    int first_mesh_line = 0;
    if (cell.workpieces.front().is_mesh())
      for (const auto& kv : wf.node[0])
        if (kv.first.IsScalar() && kv.first.Scalar() == "mesh") first_mesh_line = kv.first.Mark().line + 1;
    cell.path = path(m.get("path"), cell.workpieces.front(), cell.scanner, first_mesh_line);
    return cell;
  }

 private:
  std::filesystem::path dir_;  // the scene file's directory: relative mesh paths start here
  MeshFiles meshes_;
};

void write_vec3(std::ostringstream& out, const Vec3& v) {
  out << "[" << num(v.x()) << ", " << num(v.y()) << ", " << num(v.z()) << "]";
}

void write_pose(std::ostringstream& out, const std::string& indent, const Pose& pose) {
  out << indent << "position_mm: ";
  write_vec3(out, pose.translation());
  out << "\n" << indent << "rpy_deg: ";
  write_vec3(out, rpy_deg_of(pose));
  out << "\n";
}

}  // namespace

SceneError::SceneError(const std::string& file_, int line_, const std::string& field_,
                       const std::string& message)
    : std::runtime_error(yaml_io::error_text(file_, line_, field_, message)),
      file(file_),
      field(field_),
      line(line_) {}

Cell parse_scene(const std::string& yaml_text, const std::string& file_name, MeshFiles meshes) {
  const Parser parser(file_name, meshes);
  const YAML::Node root = parser.load(yaml_text);
  try {
    return parser.cell(root, std::filesystem::path(file_name).stem().string());
  } catch (const SceneError&) {
    throw;
  } catch (const YAML::Exception& e) {
    // Should not happen (every node is type-checked first); keep the boundary clean.
    throw SceneError(file_name, e.mark.line + 1, "", std::string("YAML error: ") + e.what());
  }
}

Cell load_scene(const std::filesystem::path& path, MeshFiles meshes) {
  const Parser parser(path.string(), meshes);
  return parse_scene(parser.read_file(path, "scene"), path.string(), meshes);
}

std::string scene_to_yaml(const Cell& cell) {
  std::ostringstream out;
  out << "# vts scene (docs/SCENE_FORMAT.md)\n";
  out << "name: " << yaml_quoted(cell.name) << "\n";

  const ScannerDesc& s = cell.scanner;
  out << "scanner:\n";
  // The material name selects a preset when read back, so it is written only
  // when it names one; every surface field follows explicitly anyway.
  const auto materials = material_names();
  if (std::find(materials.begin(), materials.end(), s.material) != materials.end())
    out << "  material: " << s.material << "\n";
  out << "  name: " << yaml_quoted(s.name) << "\n";
  out << "  points: " << s.points << "\n";
  for (const auto& k : kScannerNumbers) out << "  " << k.key << ": " << num(s.*k.member) << "\n";
  for (const auto& k : kScannerInts) out << "  " << k.key << ": " << s.*k.member << "\n";
  out << "  ideal: " << (s.ideal ? "true" : "false") << "\n";
  out << "  tool_from_laser:\n";
  write_pose(out, "    ", s.tool_from_laser);

  out << "workpieces:\n";
  for (const Workpiece& w : cell.workpieces) {
    if (w.saddle) {
      out << "  - saddle:\n";
      for (const auto& k : kSaddleParamNumbers) out << "      " << k.key << ": " << num((*w.saddle).*k.member) << "\n";
      out << "    pose:\n";
      write_pose(out, "      ", w.world_from_joint);
      continue;
    }
    if (w.is_mesh()) {
      out << "  - mesh: " << yaml_quoted(w.mesh_file) << "\n";
      const std::string unit = mesh_unit_name(w.mesh_unit_mm);
      out << "    unit: " << (unit.empty() ? num(w.mesh_unit_mm) : unit) << "\n";
      if (w.mesh_joint) out << "    joint: " << to_string(w.type) << "\n";
      out << "    pose:\n";
      write_pose(out, "      ", w.world_from_joint);
      continue;
    }
    const JointParams& p = w.params;
    out << "  - joint: " << to_string(w.type) << "\n";
    out << "    length_mm: " << num(p.length_mm) << "\n";
    out << "    width_mm: " << num(p.width_mm) << "\n";
    out << "    thickness_mm: " << num(p.thickness_mm) << "\n";
    out << "    height_mm: " << num(p.height_mm) << "\n";
    out << "    gap_mm: " << num(p.gap_mm) << "\n";
    out << "    angle_deg: " << num(p.angle_deg) << "\n";
    out << "    mismatch_mm: " << num(p.mismatch_mm) << "\n";
    out << "    root_face_mm: " << num(p.root_face_mm) << "\n";
    out << "    segment_mm: " << num(p.segment_mm) << "\n";
    out << "    cell_mm: " << num(p.cell_mm) << "\n";
    // The groove keys, where they apply; the v-groove's only when not the
    // defaults (its scenes read as they did before the beads).
    const JointParams d = default_params(w.type);
    const bool beads = w.type != JointType::VGroove || p.passes != d.passes || p.layer_mm != d.layer_mm ||
                       p.crown_mm != d.crown_mm;
    if (is_groove(w.type) && beads) {
      out << "    passes: " << p.passes << "\n";
      out << "    layer_mm: " << num(p.layer_mm) << "\n";
      out << "    crown_mm: " << num(p.crown_mm) << "\n";
    }
    if (w.type == JointType::UGroove || w.type == JointType::JGroove)
      out << "    radius_mm: " << num(p.radius_mm) << "\n";
    out << "    pose:\n";
    write_pose(out, "      ", w.world_from_joint);
  }

  const ScanPath& path = cell.path;
  out << "path:\n";
  out << "  start:\n";
  write_pose(out, "    ", path.start);
  out << "  direction: ";
  write_vec3(out, path.direction);
  out << "\n  step_mm: " << num(path.step_mm) << "\n";
  out << "  profiles: " << path.profiles << "\n";
  return out.str();
}

}  // namespace vts
