#pragma once
// Workpieces for the standard joints and the grooves (v, single bevel, U, J,
// with beads laid in them), built from plates, with their analytic ground
// truth (docs/CELLS.md; the grooves' quantities: docs/design/grooves.md).
//
// Joint frame: x along the seam (the seam runs from x = 0 to x = length_mm),
// y across the seam, z out of the work towards the side the sensor looks from.
// The joint's root (the track reference, see JointTruth::root_yz) is at the
// origin. A workpiece's pose maps the joint frame into the world.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "sensor/mesh.h"
#include "sensor/mesh_file.h"
#include "sensor/pose.h"
#include "tracker/types.h"

namespace vts {

struct SaddleParams;  // sensor/saddle.h

enum class JointType { Fillet, Corner, Lap, Butt, VGroove, Plate, Bevel, UGroove, JGroove };

// "fillet", "corner", "lap", "butt", "vgroove", "bevel", "ugroove",
// "jgroove" (the tracker's template names, tracker/types.h), "plate".
std::string_view to_string(JointType type);
std::optional<JointType> joint_type_from_string(std::string_view name);
// The tracker's template for a joint; none for the plate.
std::optional<tracker::JointType> tracker_joint(JointType type);
// vgroove, bevel, ugroove, jgroove: the joints that read passes, layer_mm and
// crown_mm and have the groove truth (JointTruth::track_yz ...).
bool is_groove(JointType type);

// Every joint reads the fields that apply to it (see docs/SCENE_FORMAT.md);
// default_params() gives each joint's defaults.
struct JointParams {
  double length_mm = 200.0;     // plates' extent along the seam (x)
  double width_mm = 80.0;       // each plate's extent across the seam
  double thickness_mm = 6.0;    // plate thickness
  double height_mm = 80.0;      // fillet: web height above the flange
  double gap_mm = 0.0;          // fillet: web lifted off the flange; corner, butt,
                                // v-groove: opening between the plates; lap: upper
                                // plate lifted off the lower one
  double angle_deg = 90.0;      // fillet: angle between the plates on the open side;
                                // corner: inside angle between the plates (90..179);
                                // v-groove, U-groove: included groove angle;
                                // bevel, J-groove: side b's wall from vertical
  double mismatch_mm = 0.0;     // butt, grooves: right plate (side b) raised by this much
  double root_face_mm = 1.0;    // grooves: height of the unbevelled land
  int passes = 0;               // grooves: beads laid in the groove (0: empty)
  double layer_mm = 3.0;        // grooves: pass k fills up to k * layer_mm above the root
  double crown_mm = 0.5;        // grooves: sagitta of the last pass's cap (< 0: concave)
  double radius_mm = 5.0;       // U-groove, J-groove: radius of the bottom arc
  double segment_mm = 10.0;     // mesh: plates are cut every segment_mm along x
  double cell_mm = 0.0;         // mesh: 0 = only the cuts along x; > 0 = every face
                                // is also a grid of about cell_mm x cell_mm quads
  // Grooves: where each bead was laid, across the seam (+y, mm), from the
  // middle between the toes of the fill it was laid on; one per pass, missing
  // ones 0. All 0 (or empty): the flat fill of passes x layer_mm, as before;
  // otherwise each bead still deposits its flat layer's area but its top
  // tilts towards the side it was laid on (sensor/groove.cpp, docs/CELLS.md).
  std::vector<double> bead_offsets_mm;
};

JointParams default_params(JointType type);

// `p` with one more bead laid, offset_mm across the seam from the middle of
// the fill under it (the adaptive fill, docs/SIM.md "Multi-pass"): passes
// + 1, bead_offsets_mm the earlier beads' (missing ones 0) and this one's.
JointParams with_bead_laid(JointParams p, double offset_mm);

// The JointParams fields that are numbers, by their key in scene files
// (docs/SCENE_FORMAT.md) and dataset specs; `passes` is the one integer.
struct JointParamKey {
  std::string_view key;
  double JointParams::*member;
};
inline constexpr JointParamKey kJointParamNumbers[] = {
    {"length_mm", &JointParams::length_mm},       {"width_mm", &JointParams::width_mm},
    {"thickness_mm", &JointParams::thickness_mm}, {"height_mm", &JointParams::height_mm},
    {"gap_mm", &JointParams::gap_mm},             {"angle_deg", &JointParams::angle_deg},
    {"mismatch_mm", &JointParams::mismatch_mm},   {"root_face_mm", &JointParams::root_face_mm},
    {"segment_mm", &JointParams::segment_mm},     {"cell_mm", &JointParams::cell_mm},
    {"layer_mm", &JointParams::layer_mm},         {"crown_mm", &JointParams::crown_mm},
    {"radius_mm", &JointParams::radius_mm}};

// Empty when the parameters are usable for the joint, else a message naming
// the field and value, e.g. "gap_mm = -1: must be >= 0".
std::string validate(JointType type, const JointParams& params);

// Curved surfaces (the U and J grooves' bottom arcs, the last bead's cap) are
// polylines whose chords stay within this of the true arc; a non-convex
// section (a plate under an arc, the beads) is several convex plates.
inline constexpr double kArcChordErrorMm = 0.002;

// A plate: a convex cross-section polygon in the joint's y-z plane (mm,
// counter-clockwise), extruded along x from x0_mm to x1_mm.
struct Plate {
  std::vector<Vec2> section_yz;
  double x0_mm = 0.0;
  double x1_mm = 0.0;
};

// The joint's true cross-section features, in the joint frame's y-z plane (mm).
struct JointTruth {
  Vec2 root_yz = Vec2::Zero();  // track reference point (always the origin)
  double gap_mm = 0.0;
  double angle_deg = 0.0;       // angle between the two joined surfaces (grooves: included)
  double mismatch_mm = 0.0;
  double step_mm = 0.0;         // lap: height of the upper plate's edge above the lower plate
  // Grooves: what is left to fill (docs/design/grooves.md): from the line
  // B1-B5 to fill_lowest, and the area between that line and the groove's
  // surface. An empty v-groove keeps the depth from plate top to root
  // (thickness - root face) even with mismatch, as before the fill existed.
  double depth_mm = 0.0;
  double area_mm2 = 0.0;
  // Grooves only (zero for the other joints), docs/design/grooves.md:
  Vec2 track_yz = Vec2::Zero();     // B3, the track point (an empty v-groove: the origin)
  Vec2 top_a_yz = Vec2::Zero();     // B1: plate a's top edge
  Vec2 top_b_yz = Vec2::Zero();     // B5: plate b's top edge
  Vec2 toe_a_yz = Vec2::Zero();     // B2: the bottom surface meets wall a
  Vec2 toe_b_yz = Vec2::Zero();     // B4: the bottom surface meets wall b
  Vec2 fill_lowest_yz = Vec2::Zero();  // the bottom surface's point farthest from B1-B5
  double wall_angle_a_deg = 0.0;    // wall a's straight part against plate a's top (90: square)
  double wall_angle_b_deg = 0.0;
  double top_width_mm = 0.0;        // |B5 - B1|
  // Named feature points, e.g. {"web_edge", (0, gap)}; see docs/SCENE_FORMAT.md.
  std::vector<std::pair<std::string, Vec2>> features;
};

struct Workpiece {
  JointType type = JointType::Fillet;  // a mesh workpiece: see mesh_joint
  JointParams params;
  Pose world_from_joint = Pose::Identity();
  std::vector<Plate> plates;  // joint frame
  JointTruth truth;

  // A mesh workpiece (a CAD part, scene key `mesh`; docs/SCENE_FORMAT.md):
  // the triangles in the joint frame, mm, already scaled to mm. It has no
  // plates, no seam and no truth (params are the defaults of `type`, truth
  // all zero). Null for the joints.
  std::shared_ptr<const Mesh> file_mesh;
  std::string mesh_file;      // the file it was read from (absolute); empty if not from a file
  double mesh_unit_mm = 1.0;  // mm per file unit
  bool mesh_joint = false;    // the scene named the joint the part contains: then it is `type`
  MeshLoadStats mesh_stats;   // what the loader found
  // A pipe saddle (sensor/saddle.h, scene key `saddle`): its mesh is built
  // from these on mesh(); it counts as a mesh workpiece with a fillet joint
  // (no straight seam, no plates, truth all zero here: its truth is
  // saddle_point / saddle_truth_in_plane). Null otherwise.
  std::shared_ptr<const SaddleParams> saddle;

  bool is_mesh() const { return file_mesh != nullptr || saddle != nullptr; }
  // The joint is known: always for the joints, for a mesh only when named.
  bool has_joint() const { return !is_mesh() || mesh_joint; }

  Mesh mesh() const;  // world frame
  // Seam line in world: origin + s * direction, s in [0, length_mm]. A mesh
  // workpiece has no seam: its joint frame's origin and x axis.
  Vec3 seam_origin() const;
  Vec3 seam_direction() const;
  // A cross-section point (joint frame y, z) where the laser plane of a
  // sensor at world_from_sensor cuts the seam, in that sensor's frame (y, z):
  // where the truth lies in its profile. The line along the seam through the
  // point is cut exactly, also by a plane oblique to the seam (a sensor
  // leaning along the seam or turned about its optical axis); a plane
  // parallel to the seam takes the point at the sensor's own seam position.
  Vec2 in_sensor_frame(const Pose& world_from_sensor, const Vec2& joint_yz) const;
  // A profile point (sensor frame y, z, in the laser plane) of a sensor at
  // world_from_sensor, in the joint frame (y across the seam, z): where a
  // reading lies on the cross-section.
  Vec2 in_joint_frame(const Pose& world_from_sensor, const Vec2& sensor_yz) const;
  // Plane (unit outward normal n, offset d: n.p = d) of every flat face of
  // every plate, world frame; from the section polygons, not the mesh. None
  // for a mesh workpiece.
  std::vector<std::pair<Vec3, double>> face_planes() const;
};

// Builds the plates and truth. Precondition: validate(type, params) is empty.
Workpiece build_workpiece(JointType type, const JointParams& params,
                          const Pose& world_from_joint = Pose::Identity());

// A mesh workpiece from a mesh in its joint frame (mm; null: an empty mesh).
// `joint`, if given, names the joint the part contains (mesh_joint = true).
// mesh_stats: *stats if given (the loader's), else mesh_edge_stats(mesh).
Workpiece mesh_workpiece(std::shared_ptr<const Mesh> mesh_in_joint_frame,
                         const Pose& world_from_joint = Pose::Identity(),
                         std::optional<JointType> joint = std::nullopt,
                         const MeshLoadStats* stats = nullptr);

// A pipe saddle workpiece (sensor/saddle.h). Precondition: validate(params) is empty.
Workpiece saddle_workpiece(const SaddleParams& params, const Pose& world_from_saddle = Pose::Identity());

// Plate extruded along x, triangulated with a cut every segment_mm. With
// cell_mm > 0 the cuts are at most cell_mm apart too, and every face is a
// grid of about cell_mm x cell_mm quads: each side face has
// ceil(edge length / cell_mm) columns across; an end cap of a four-sided
// section is a bilinear grid (opposite sides get the larger count), other end
// caps are fanned from the section's centroid to the subdivided outline.
// Each plate's mesh is closed (every edge shared by two triangles).
Mesh plate_mesh(const Plate& plate, double segment_mm, const Pose& world_from_joint,
                double cell_mm = 0.0);
// plate_mesh(...).triangle_count() without building it.
std::int64_t plate_triangle_count(const Plate& plate, double segment_mm, double cell_mm = 0.0);

// Most triangles a joint workpiece may have (validate() refuses a smaller cell_mm).
inline constexpr std::int64_t kMaxWorkpieceTriangles = 20'000'000;

}  // namespace vts
