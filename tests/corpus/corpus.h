// An independent test corpus for the seam tracker: laser profiles of the five
// joints with ground truth, from a small 2D cross-section ray caster written
// for the tests alone (nothing from sensor/, render/ or tracker/). See
// tests/corpus/README.md for what each variant does and how often.
//
// Frames (mm): the joint frame has y across the seam, z up out of the work,
// the root near the origin; the sensor frame has y along the laser line and z
// the range along the optical axis, the laser at the origin and the work at
// +z; every column's ray starts at the origin. Truth is in the sensor frame.
#pragma once

#include "geometry.h"

#include <array>
#include <cstdint>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace vts_corpus {

inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

enum class Joint { Fillet, Corner, Lap, Butt, VGroove, Bevel, UGroove, JGroove, VGrooveThick };
// The five joints of the score table (kept as they were: scores stay comparable).
inline constexpr std::array<Joint, 5> kAllJoints = {Joint::Fillet, Joint::Corner, Joint::Lap,
                                                    Joint::Butt, Joint::VGroove};
// The thick-plate and multi-pass grooves of docs/design/grooves.md (issue 18):
// single bevel, U, J and a V in thick plate (the tracker's v-groove template).
inline constexpr std::array<Joint, 4> kGrooveJoints = {Joint::Bevel, Joint::UGroove, Joint::JGroove,
                                                       Joint::VGrooveThick};
// "fillet", "corner", "lap", "butt", "vgroove", "bevel", "ugroove", "jgroove", "vgroove-thick"
const char* joint_name(Joint joint);
std::optional<Joint> joint_from_name(std::string_view name);
bool is_groove(Joint joint);  // one of kGrooveJoints

// The noise levels of the corpus (sigma of the range along the ray, mm RMS).
inline constexpr std::array<double, 6> kNoiseLevels_mm = {0.0, 0.005, 0.02, 0.05, 0.1, 0.2};

struct Options {
  // Range noise sigma along the ray (mm); negative: each profile draws one of
  // kNoiseLevels_mm. Applied whatever `imperfections` says.
  double noise_mm = 0.0;
  // Waviness, quantization, reflection clusters, dropouts and shadowing bodies
  // (each with its own probability). Off: an ideal profile (plus noise).
  bool imperfections = true;
  // A smaller feature of the same kind 20-40 mm from the seam (README.md).
  bool decoy = false;
  int columns = 0;           // 0: draw 256..2048; else 16..4096
  double standoff_mm = 0.0;  // root distance along the optical axis; 0: draw 50..250
  // The camera sits in the laser plane at a baseline along +y or -y (the
  // corpus' model); false: along the travel direction, out of the plane, so
  // only pitch/yaw and bodies make camera shadows (a real line sensor).
  bool camera_in_laser_plane = true;
  // Variant probabilities by name (variant_names()), overriding the defaults.
  // Unknown names or values outside [0, 1] throw std::invalid_argument.
  std::map<std::string, double> probability;
  // Fill Profile::debug (the scene and every column's ideal hit).
  bool keep_debug = false;
};

// Variant names accepted in Options::probability for this joint, and their
// default probabilities.
std::vector<std::string> variant_names(Joint joint);
double default_probability(Joint joint, const std::string& variant);

struct Truth {
  Joint joint = Joint::Fillet;
  double track_y_mm = kNaN, track_z_mm = kNaN;
  // NaN where the value does not apply to the joint.
  double gap_mm = kNaN, mismatch_mm = kNaN, angle_deg = kNaN, step_mm = kNaN, depth_mm = kNaN;
  double area_mm2 = kNaN;  // v-groove: open cross-section B1-B2-B4-B5; grooves: the area left to fill
  // Grooves (docs/design/grooves.md; NaN / -1 for the other joints): each
  // wall's straight part against its plate top (a: the first plate in scan
  // order), the top width B1-B5, the lowest point of the bottom surface (the
  // last bead's cap, or the root), the number of beads laid.
  double wall_angle_a_deg = kNaN, wall_angle_b_deg = kNaN, top_width_mm = kNaN;
  double fill_lowest_y_mm = kNaN, fill_lowest_z_mm = kNaN;
  int passes = -1;
  // Break points as named in docs/JOINTS.md (those truth can give), sensor frame.
  std::vector<std::pair<std::string, std::array<double, 2>>> break_points;
  std::vector<std::string> tags;                          // variants, imperfections, visibility
  std::vector<std::pair<std::string, double>> params;     // everything drawn (joint frame for shapes)
  double decoy_y_mm = kNaN, decoy_z_mm = kNaN;            // the decoy's feature point, if any
  double noise_mm = 0.0;
  int columns = 0;
  double standoff_mm = kNaN;  // the track point's z
  std::uint64_t seed = 0;
  int index = 0;      // profile index in a recording
  double s_mm = 0.0;  // travel along the seam in a recording

  bool has_tag(std::string_view tag) const;
  const std::array<double, 2>* break_point(std::string_view name) const;  // nullptr if absent
  double param(std::string_view name) const;                              // NaN if absent
};

// Why a column has no point (Debug::status).
enum ColumnStatus : std::uint8_t {
  kValid = 0,
  kNoHit,         // the ray met nothing
  kOutOfRange,    // hit outside the measuring range
  kCameraShadow,  // the work hides the hit from the camera
  kBodyShadow,    // a torch or clamp blocks the ray or the camera's view
  kDropout,       // an imperfection removed it
};

struct Sensor {
  int columns = 512;
  double fan_deg = 40.0;
  bool tangent_spacing = true;  // columns evenly spaced in tan(angle) (a camera's pixels), else in angle
  Vec2 camera_yz{60.0, 0.0};    // occlusion viewpoint in the laser plane
  double z_near_mm = 0.0, z_far_mm = std::numeric_limits<double>::infinity();
};

struct Debug {
  Scene scene;                    // sensor frame, including a body if any
  Sensor sensor;
  std::vector<Vec2> ray_dir;      // unit column directions
  std::vector<double> ideal_range_mm;  // distance to the ideal hit (NaN: none)
  std::vector<int> hit_face;      // face of the ideal hit (-1: none)
  std::vector<std::uint8_t> status;
  Mat2 joint_to_sensor_A = Mat2::Identity();  // sensor = A joint + t
  Vec2 joint_to_sensor_t{0, 0};
};

struct Profile {
  std::vector<float> y, z;            // sensor frame, mm; NaN where invalid
  std::vector<std::uint8_t> valid;    // 1 measured, 0 not
  Truth truth;
  std::shared_ptr<const Debug> debug;  // with Options::keep_debug
};

// One profile: a pure function of its arguments (same bytes on every run).
Profile make_profile(Joint joint, std::uint64_t seed, const Options& options = {});

struct RecordingOptions {
  Options profile;                 // per-profile options (decoy: on every profile)
  double ds_mm = 0.0;              // travel per profile; 0: draw 0.1..1
  double lateral_drift_mm = -1.0;  // max |lateral drift| of the joint; < 0: draw 0..5
  double height_drift_mm = -1.0;   // max |height drift|; < 0: draw 0..3
  double gap_opening_mm = -1.0;    // gap change over the recording; < 0: half fixed, half opening up to 1 mm
  int decoy_every = 0;             // a decoy on every k-th profile (0: as profile.decoy)
};

// A sequence of profiles along the seam: the joint drifts smoothly in the
// sensor frame, its shape is fixed (or the gap opens slowly), imperfections
// and noise are redrawn per profile from (seed, index).
std::vector<Profile> make_recording(Joint joint, std::uint64_t seed, int count,
                                    const RecordingOptions& options = {});
// Profile `index` of that recording alone (same bytes as make_recording's).
Profile make_recording_profile(Joint joint, std::uint64_t seed, int count, int index,
                               const RecordingOptions& options = {});

// The caster on its own, for tests: unit column directions in scan order
// (increasing y/z), and one rendered profile of an arbitrary scene with range
// noise only (no other imperfections), as make_profile renders.
std::vector<Vec2> column_directions(const Sensor& sensor);
Profile render_scene(const Scene& scene, const Sensor& sensor, double noise_mm, std::uint64_t seed);

// A groove of fixed shape (joint frame, docs/design/grooves.md), for tests
// that work its truth out by hand.
struct GrooveShape {
  Joint joint = Joint::VGrooveThick;  // one of kGrooveJoints
  double thickness_mm = 40, angle_deg = 60, root_face_mm = 0, gap_mm = 0, mismatch_mm = 0;
  double radius_mm = 5;  // U, J
  int passes = 0;
  double layer_mm = 3, crown_mm = 0.5, ripple_mm = 0;
};
// The groove straight below the sensor (no roll, pitch, yaw or mirror: sensor
// y = joint y, sensor z = root_standoff_mm - joint z), rendered without
// imperfections or noise, with truth and debug. Throws std::invalid_argument
// when the fill does not stay below the tops.
Profile make_groove_profile(const GrooveShape& shape, const Sensor& sensor, double root_standoff_mm);

}  // namespace vts_corpus
