// Internals shared by the corpus' source files (not part of its API).
#pragma once

#include "corpus.h"
#include "dmath.h"
#include "random.h"


#include <map>
#include <memory>
#include <string>
#include <vector>

namespace vts_corpus::detail {

inline constexpr double kPi = 3.14159265358979323846;
inline double deg(double rad) { return rad * 180.0 / kPi; }
inline double rad(double deg) { return deg * kPi / 180.0; }

// Variant probabilities after Options::probability and Options::imperfections.
class Probabilities {
 public:
  Probabilities(Joint joint, const Options& options);  // throws on unknown names
  double operator()(const std::string& name) const;

 private:
  std::map<std::string, double> p_;
};

// The sensor as drawn for a profile (or a whole recording).
struct SensorDraw {
  Sensor sensor;
  double standoff_mm = 100;          // the track point's range
  double nominal_standoff_mm = 100;  // centre of the measuring range
  double triangulation_deg = 25;
  double baseline_mm = 50;
  int camera_side = 1;
  // Grooves: a thick plate (20-80 mm), drawn before the sensor because a
  // thick plate is seen from farther (standoff 100-400 mm instead of 50-250).
  bool thick = false;
};
SensorDraw draw_sensor(Rng& rng, const Options& options, double standoff_lo_mm = 50, double standoff_hi_mm = 250);

struct EdgeStyle {
  CornerKind kind = CornerKind::Sharp;
  double size_mm = 0;
};

// Every shape parameter of a joint (joint frame, mm, degrees). One struct for
// all joints; each uses its own fields.
struct JointSpec {
  Joint joint = Joint::Fillet;
  double plate_half_length_mm = 500;
  double gap_mm = 0;
  double mismatch_mm = 0;  // signed: + raises plate 2 (+y)
  EdgeStyle edge{};
  bool tack = false;
  double tack_a_mm = 0, tack_b_mm = 0, tack_c = 0;  // joint-specific tack shape draws
  bool backing = false;
  double backing_width_mm = 0, backing_thickness_mm = 0, backing_offset_mm = 0;
  double angle_deg = 90;         // fillet: open angle; corner: inside angle; v-groove: included angle
  double t1_mm = 10, t2_mm = 10;  // plate thicknesses (fillet: flange, web; corner, butt: plates 1, 2)
  double web_height_mm = 50;     // fillet
  double tilt_deg = 0;           // lap: upper plate lifted away from its edge
  double root_face_mm = 0;       // v-groove
  double depth_mm = 0;           // v-groove, grooves: plate top to root edge (thickness - root face)
  // Grooves (docs/design/grooves.md): angle_deg is the included angle.
  double radius_mm = 0;          // U, J: the arc at the root
  int passes = 0;                // beads laid
  double layer_mm = 3, crown_mm = 0.5;
  double ripple_mm = 0, ripple_wavelength_mm = 3, ripple_phase = 0;  // bead ripples on the cap
  std::vector<std::string> tags{};
  std::vector<std::pair<std::string, double>> params{};
};
JointSpec draw_joint(Joint joint, Rng& rng, const SensorDraw& sensor, const Probabilities& p);

struct DecoySpec {
  bool on = false;
  double distance_mm = 30;
  double a_mm = 1, b_mm = 1, c = 0;  // joint-specific size draws
  int kind = 0;
};
DecoySpec draw_decoy(Joint joint, Rng& rng, const SensorDraw& sensor);

// The cross-section in the joint frame with the features truth needs.
struct Section {
  std::vector<Polygon> solids;
  Vec2 view_dir{0, -1};  // from the sensor towards the joint
  Vec2 track{0, 0};
  double halfwidth_mm = 5;  // lateral extent of what the tracker needs, from the track point
  double max_roll_deg = 15;  // the roll keeps the plates at least 20 degrees off the rays
  // Grooves: how far the plate tops lie above the track point (the field of
  // view at the tops, narrower than at the track point, must hold the groove).
  double top_height_mm = 0;
  // Fillet: the open angle the camera must look into (NaN: no constraint).
  double open_angle_deg = std::numeric_limits<double>::quiet_NaN();
  std::map<std::string, Vec2> pts;   // named truth points
  std::map<std::string, Vec2> dirs;  // named directions
  std::vector<std::string> defining;  // truth points whose visibility decides "joint_hidden"
  bool has_decoy = false;
  Vec2 decoy_point{0, 0};
};
Section build_section(const JointSpec& spec, const DecoySpec& decoy);

// Sensor = A joint + t.
struct Affine {
  Mat2 A = Mat2::Identity();
  Vec2 t{0, 0};
  Vec2 operator()(const Vec2& p) const { return mul(A, p) + t; }
  Vec2 dir(const Vec2& d) const { return mul(A, d).normalized(); }
};

// Fills the truth values and break points of `truth` from the section mapped
// into the sensor frame.
void compute_truth(const JointSpec& spec, const Section& section, const Affine& map, Truth& truth);

// The groove joints (grooves.cpp): parameters, cross-section, truth, and the
// sensor fitted to the groove (standoff raised, then the fan widened, until
// the groove and 10 mm of each plate top fit the field and the measuring range).
JointSpec draw_groove(Joint joint, Rng& rng, const SensorDraw& sensor, const Probabilities& p);
Section build_groove_section(const JointSpec& spec, const DecoySpec& decoy);
void compute_groove_truth(const JointSpec& spec, const Section& section, const Affine& map, Truth& truth);
void fit_groove_sensor(SensorDraw& sensor, JointSpec& spec, const Options& options);
// A small V notch in plate 1's top (z = top_z) beyond its top edge at y = edge_y:
// the v-groove decoy. Appends its corners and sets the section's decoy point.
void add_notch_decoy(std::vector<Corner>& plate1, double edge_y, double top_z, const DecoySpec& decoy, Section& sec);

// Ideal casting of every column (no imperfections).
struct Cast {
  std::vector<Vec2> dir;
  std::vector<double> u;        // dir.y / dir.z, increasing
  std::vector<double> range_mm;  // NaN: no hit
  std::vector<int> edge;         // scene edge hit, -1 none
  std::vector<std::uint8_t> status;
};
Cast cast_scene(const Scene& scene, const Sensor& sensor, std::vector<Vec2> dirs);

// Imperfections drawn for one profile (after the ideal cast: clusters and
// dropouts are placed on measured columns).
struct Imperfections {
  double noise_mm = 0;
  double quant_step_mm = 0;  // 0: none
  struct Wave {
    double amplitude_mm, wavelength_mm, phase;
  };
  std::vector<Wave> waves;
  struct Cluster {
    int first, count;
    double offset_mm;  // along the ray: + behind the surface, - in front
  };
  std::vector<Cluster> reflections;
  std::vector<std::pair<int, int>> dropout_runs;  // first, count
  std::vector<int> single_dropouts;
};

// Applies the imperfections and noise to the cast; fills y, z, valid.
void finish_profile(const Scene& scene, const Cast& cast, const Imperfections& imp, Rng& noise_rng,
                    Profile& out, std::vector<std::uint8_t>& status);

// The debug record of a cast profile (Options::keep_debug, render_scene).
std::shared_ptr<Debug> make_debug(const Scene& scene, const Sensor& sensor, const Cast& cast,
                                  const std::vector<std::uint8_t>& status, const Mat2& A = Mat2::Identity(),
                                  const Vec2& t = Vec2(0, 0));

}  // namespace vts_corpus::detail
