#pragma once
// A 6-axis industrial arm (issue 19, docs/ROBOT.md): standard Denavit-
// Hartenberg kinematics of the common spherical-wrist layout (axes 4-6 meet
// in the wrist centre), forward and closed-form inverse kinematics with the
// eight configurations, joint limits, configuration flags and singularity
// measures, and an absolute-accuracy model: the same arm with small seeded
// errors in link lengths and joint zeros, so that the controller's idea of
// its TCP differs from where it is. Pure C++ and Eigen: no files, no GL.
//
// Units: mm and radians inside; the presets' tables are in mm and degrees.
// Frames: base (world of the arm, z up along axis 1), flange (DH frame 6),
// tool (the TCP, flange_from_tool).
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Geometry>

namespace vts::robot {

using Pose3 = Eigen::Isometry3d;
using Joints = Eigen::Matrix<double, 6, 1>;  // radians

// One axis: T(i-1 -> i) = Rz(q + offset) Tz(d) Tx(a) Rx(alpha).
struct Axis {
  double a_mm = 0.0, alpha_rad = 0.0, d_mm = 0.0, offset_rad = 0.0;
  double min_rad = -M_PI, max_rad = M_PI;  // joint limits
  double max_vel_rad_s = M_PI;             // velocity limit
  double max_acc_rad_s2 = 4.0 * M_PI;      // acceleration limit
};

struct ArmModel {
  std::string name;
  std::string source;  // where the numbers come from
  std::array<Axis, 6> axes;
  // Axis 3 driven through a parallel linkage (ABB IRB 2400): its limits
  // hold for the forearm's angle against the base, q2 + q3, not for q3.
  bool axis3_coupled = false;
  // The layout inverse() solves: a = (a1, a2, a3, 0, 0, 0), d = (d1, 0, 0, d4,
  // 0, d6), alpha = (-90, 0, -90, 90, -90, 0) degrees, offsets (0, -90, 0, 0,
  // 0, 0). validate() says when a model departs from it.
};

// The value an axis's limits apply to (axis 0-based): q[i], or q2 + q3 for
// a coupled axis 3.
double limited_value(const ArmModel& model, const Joints& q, int axis);
// "irb2400" (ABB IRB 2400/16) and "kr16" (KUKA KR 16-2): docs/ROBOT.md.
std::optional<ArmModel> arm_preset(std::string_view name);
std::vector<std::string> arm_preset_names();
// Empty if the model has the layout inverse() solves and sane limits, else why.
std::string validate(const ArmModel& model);

// base -> flange.
Pose3 forward(const ArmModel& model, const Joints& q);
// Every axis's frame, base frame: frames[0] the base itself, frames[i] the
// frame after axis i (frames[6] the flange), as the DH chain defines them.
std::array<Pose3, 7> frames(const ArmModel& model, const Joints& q);
// The wrist centre (where axes 4-6 meet), base frame.
Eigen::Vector3d wrist_centre(const ArmModel& model, const Joints& q);

// The configuration: which of the (up to) eight joint solutions of a flange
// pose. front: the wrist centre lies ahead of axis 1 (q1 points at it), else
// the arm reaches over backwards; elbow_up: the elbow lies above the line
// from axis 2 to the wrist centre (on the front side); flip: q5 < 0.
struct Config {
  bool front = true, elbow_up = true, flip = false;
  bool operator==(const Config&) const = default;
};
Config config_of(const ArmModel& model, const Joints& q);
std::string to_string(const Config& c);  // e.g. "front/up/noflip"

// How near a singularity q is: wrist |sin q5| (0: axes 4 and 6 aligned),
// elbow |sin| of the angle between upper arm and forearm-to-wrist (0:
// stretched or folded), shoulder: the wrist centre's distance from axis 1 (mm).
struct Singularity {
  double wrist = 1.0, elbow = 1.0, shoulder_mm = 1e9;
};
Singularity singularity(const ArmModel& model, const Joints& q);

struct Limits {
  double wrist = std::sin(2.0 * M_PI / 180.0);   // |sin q5| below this is singular
  double elbow = std::sin(2.0 * M_PI / 180.0);
  double shoulder_mm = 20.0;
};

// Every joint solution of a flange pose (no limits applied), in a fixed
// order: front before back, elbow up before down, no flip before flip. Empty
// if the wrist centre is out of reach. A wrist-singular pose (|sin q5| ~ 0)
// gives q4 = 0 and q6 taking the whole turn.
struct Solution {
  Joints q;
  Config config;
};
std::vector<Solution> inverse_all(const ArmModel& model, const Pose3& base_from_flange);

enum class IkStatus { Ok, Unreachable, JointLimit, Singular };
std::string_view to_string(IkStatus s);
struct IkResult {
  IkStatus status = IkStatus::Ok;
  Joints q = Joints::Zero();
  std::string message;  // why, naming the axis and the value, when not Ok
};
// The solution of `config` nearest `near` (each wrist and base angle taken
// modulo a full turn to the representative nearest `near` inside its
// limits), checked against the limits and the singularity limits. With
// `continuous` (a servo's next command), an angle whose nearest
// representative lies outside its limits is a JointLimit: the axis would
// have to unwind a full turn, not a step.
IkResult inverse(const ArmModel& model, const Pose3& base_from_flange, const Config& config, const Joints& near,
                 const Limits& limits = {}, bool continuous = false);

// The absolute-accuracy model: a copy of `nominal` with each a, d drawn from
// N(0, sigma_length_mm) and each joint zero from N(0, sigma_zero_rad), from
// `seed` (deterministic). The controller computes with `nominal`; the arm
// moves as the copy.
ArmModel perturbed(const ArmModel& nominal, std::uint64_t seed, double sigma_length_mm = 0.3,
                   double sigma_zero_rad = 0.01 * M_PI / 180.0);

}  // namespace vts::robot
