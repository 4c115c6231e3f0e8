#pragma once
// A pipe saddle: a branch pipe set at right angles onto a main pipe, the
// fillet joint between them running around their intersection curve
// (docs/CELLS.md "The pipe saddle"). A curved dense mesh with analytic truth.
//
// Saddle frame (the workpiece's joint frame): origin where the two axes
// cross, x along the main pipe's axis, z along the branch's axis (the branch
// stands on the main pipe's top, z > 0). With R the main pipe's outer radius
// and r < R the branch's, the outer surfaces are y^2 + z^2 = R^2 and
// x^2 + y^2 = r^2, and they meet on the saddle curve
//   C(t) = (r cos t, r sin t, sqrt(R^2 - r^2 sin^2 t)),  t in [0, 2 pi):
// t = 0 and pi are the crowns (highest, z = R, the fillet's open angle
// 90 degrees), t = pi/2 and 3 pi/2 the flanks (lowest, z = sqrt(R^2 - r^2),
// open angle 90 + asin(r / R) degrees). The pipes are solid bars (the sensor
// sees only their outsides near the seam); their ends are flat discs.
//
// The mesh conforms to the curve (the two surfaces share its vertices) and
// has no two neighbouring triangles in one plane except in the end discs:
// the main pipe is a staggered lattice (each ring along x turned half a step
// against the last), the branch is staggered rings, and between the lattice
// and the curve an O-grid of rings in the main pipe's unrolled coordinates
// (u = x, v = R * the angle from the top) joins the two.
#include <cstdint>
#include <optional>
#include <string>

#include "sensor/mesh.h"
#include "sensor/pose.h"

namespace vts {

struct SaddleParams {
  double main_radius_mm = 100.0;    // R: the main pipe's outer radius
  double branch_radius_mm = 50.0;   // r: the branch's outer radius, r < R
  double main_length_mm = 400.0;    // the main pipe runs from x = -L/2 to L/2
  double branch_height_mm = 200.0;  // the branch's top end, z = H above the main pipe's axis
  double cell_mm = 4.0;             // tessellation pitch: lattice step along and around both pipes
};

// The fields by their key in scene files (docs/SCENE_FORMAT.md).
struct SaddleParamKey {
  const char* key;
  double SaddleParams::*member;
};
inline constexpr SaddleParamKey kSaddleParamNumbers[] = {
    {"main_radius_mm", &SaddleParams::main_radius_mm},
    {"branch_radius_mm", &SaddleParams::branch_radius_mm},
    {"main_length_mm", &SaddleParams::main_length_mm},
    {"branch_height_mm", &SaddleParams::branch_height_mm},
    {"cell_mm", &SaddleParams::cell_mm}};

// Empty when usable, else "field = value: why".
std::string validate(const SaddleParams& params);

// The mesh in the saddle frame mapped by world_from_saddle (closed: every edge
// shared by two triangles, wound outward). Precondition: validate() is empty.
Mesh saddle_mesh(const SaddleParams& params, const Pose& world_from_saddle = Pose::Identity());
// Roughly saddle_mesh(params).triangle_count(), from the areas, without building it.
double saddle_triangle_estimate(const SaddleParams& params);

// The truth at parameter t (saddle frame unless mapped by a pose below).
struct SaddlePoint {
  double t = 0.0;            // rad, in [0, 2 pi)
  Vec3 root;                 // C(t): the fillet's root
  Vec3 tangent;              // unit dC/dt
  Vec3 main_normal;          // outward normal of the main pipe at the root
  Vec3 branch_normal;        // outward normal of the branch at the root
  Vec3 main_side;            // unit: the main pipe's surface leaving the root, square to the tangent, away from the branch
  Vec3 branch_side;          // unit: the branch's surface leaving the root, square to the tangent, up the branch
  Vec3 bisector;             // unit: halfway between main_side and branch_side (into the open side)
  double open_angle_deg = 0; // between main_side and branch_side: 90 at the crowns, 90 + asin(r/R) at the flanks
};
SaddlePoint saddle_point(const SaddleParams& params, double t);
SaddlePoint transformed(const SaddlePoint& p, const Pose& world_from_saddle);

// The truth where the laser plane of a sensor at world_from_sensor (its
// x = 0 plane) cuts the saddle curve: of the cuts (a plane crossing the
// closed curve cuts it an even number of times), the one nearest the
// sensor's optical axis; world frame. None if the plane misses the curve.
std::optional<SaddlePoint> saddle_truth_in_plane(const SaddleParams& params, const Pose& world_from_saddle,
                                                 const Pose& world_from_sensor);

// A sensor pose looking at C(t) along the bisector from standoff_mm, its
// laser plane square to the seam (travel x along the tangent). World frame.
Pose saddle_sensor_pose(const SaddleParams& params, const Pose& world_from_saddle, double t, double standoff_mm);

}  // namespace vts
