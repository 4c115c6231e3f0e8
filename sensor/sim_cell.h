#pragma once
// The cell of the paper's dynamic experiment (section 5.2): a square box on a
// bottom plate, welded along two of its sides (two fillet seams meeting at a
// corner of the box). The master knows the nominal workpiece pose; the actual
// pose is displaced from it by a seeded random rigid motion. Ground truth: the
// analytic seam lines of the actual workpiece.
//
// Workpiece frame: origin at the centre of the plate's top face, z up (out of
// the plate), the box's sides along x and y. Seam 1 runs along the box's -y
// side from x = -side/2 to +side/2; seam 2 along its +x side from y = -side/2
// to +side/2 (it starts at the corner where seam 1 ends).
#include <cstdint>
#include <string>
#include <vector>

#include "sensor/mesh.h"
#include "sensor/pose.h"
#include "sensor/saddle.h"
#include "sensor/scanner.h"
#include "tracker/master.h"

namespace vts {

// The part welded: the paper's box on a plate (two straight fillets), or a
// pipe saddle (sensor/saddle.h: a branch pipe on a main pipe, the fillet
// round their intersection welded in two halves, each from one crown over a
// flank to the other crown).
enum class SimWorkpiece { Box, Saddle };

struct SimCellParams {
  SimWorkpiece workpiece = SimWorkpiece::Box;
  // The saddle's pipes (workpiece Saddle). Its workpiece frame is the saddle
  // frame lowered by the main pipe's radius: the crowns at z = 0, where the
  // box's plate top is.
  SaddleParams saddle;
  double box_side_mm = 150.0;    // the box's square footprint
  double box_height_mm = 80.0;
  double plate_side_mm = 320.0;  // the bottom plate's square footprint
  double plate_thickness_mm = 8.0;
  // Nominal pose of the workpiece in the world (what the master believes).
  Pose nominal_world_from_workpiece = pose_from_xyz_rpy(Vec3(600.0, 200.0, 0.0), Vec3(0.0, 0.0, 30.0));
  // The actual pose: the nominal one turned about the workpiece origin by a
  // random angle in [0, rotation_deg] about a random axis, then translated by
  // a random vector of length <= offset_mm (uniform in the ball).
  double offset_mm = 10.0;
  double rotation_deg = 5.0;
  std::uint64_t seed = 1;
  // Deviations of the actual part from the model, for robustness runs:
  // the box is this much shorter along x (seam 1 ends early; seam 2 moves in);
  double seam1_short_mm = 0.0;
  // the box is tilted about its bottom edge at x = -side/2 so that the gap
  // under seam 1's wall grows linearly from 0 to this at the seam's end.
  double seam1_gap_rise_mm = 0.0;
  // the box's seam-1 wall bows out of the box (towards -y) along a circular
  // arc through its ends, this far at the middle: a curved seam 1;
  double seam1_bow_mm = 0.0;
  // and/or waves across its length: the wall's footprint moves out of the
  // box by seam1_wave_mm sin(2 pi u / seam1_wavelength_mm) at u mm from
  // seam 1's start (an S-curve for one wavelength over the seam);
  double seam1_wave_mm = 0.0;
  double seam1_wavelength_mm = 150.0;
  // tack welds on both seams: a bead in the fillet's corner (legs
  // tack_leg_mm on the plate and up the wall, its face bulging 0.3 leg out
  // of the straight line between them) tack_length_mm long, the first
  // tack_first_mm from each seam's start and then every tack_spacing_mm
  // (0: none) up to tack_first_mm before its end.
  double tack_spacing_mm = 0.0;
  double tack_first_mm = 20.0;
  double tack_length_mm = 3.0;
  double tack_leg_mm = 3.0;
  // thermal distortion while seam 1 is welded (SeamDistortion): the part
  // ahead of the arc turns about the plate normal through the arc's point
  // by this much per 100 mm welded, its far end towards seam 1's open side.
  double distortion_deg_per_100mm = 0.0;
  // and the box's wall lifts off the plate ahead of the arc: the box turns
  // about the axis square to seam 1's wall through the seam's point at the
  // arc by this much per 100 mm welded, its far end up, so that the gap
  // under the wall at u mm ahead of the arc is u sin(lift) (SeamDistortion).
  // Needs the plain box (no bow, wave, gap rise, shortening or tacks) and
  // the ray-cast reference source (the moving wall is an Embree instance).
  double distortion_lift_deg_per_100mm = 0.0;
  // Either kind of thermal distortion asked for (SeamDistortion).
  bool distorted() const { return distortion_deg_per_100mm != 0.0 || distortion_lift_deg_per_100mm != 0.0; }
  // Sensor mount: the laser plane lookahead_mm ahead of the TCP, the laser
  // origin standoff_mm back along the torch axis (= the optical axis).
  double lookahead_mm = 50.0;
  double standoff_mm = 100.0;
};

// Empty if usable, else a message naming the field and value.
std::string validate(const SimCellParams& params);

// One seam of the actual workpiece, world frame (mm).
struct SimSeamTruth {
  Vec3 start = Vec3::Zero();
  Vec3 end = Vec3::Zero();
  Vec3 plate_normal = Vec3::UnitZ();  // unit, out of the plate
  Vec3 wall_normal = -Vec3::UnitY();  // unit, the wall's open-side face, out of the box
  // A curved seam: the root line as a polyline from start to end (points
  // 2 mm apart or closer, the wall flat between them); empty: the straight line.
  std::vector<Vec3> path;
  // A seam whose surfaces turn along it (the saddle): at each path point the
  // plate's normal and the lateral direction (in the plate, square to the
  // seam, towards the open side); errors are taken in that frame. Empty:
  // plate_normal, and the lateral across each segment in the plate.
  std::vector<Vec3> path_plate_normal, path_lateral;
  Vec3 direction() const { return (end - start).normalized(); }
  double length() const;  // along the path
  // Across the seam in the plate, towards the open side (unit), of the chord.
  Vec3 lateral() const;
};
// Tack welds' spans along a seam, as arc length from its start (mm).
struct TackSpan {
  int seam = 0;
  double s0_mm = 0.0, s1_mm = 0.0;
};

struct SimCell {
  SimCellParams params;
  Pose nominal_world_from_workpiece = Pose::Identity();
  Pose actual_world_from_workpiece = Pose::Identity();
  std::vector<tracker::SeamPlan> plan;  // the master's model, workpiece frame
  std::vector<SimSeamTruth> truth;      // the actual seams, world
  std::vector<TackSpan> tacks;
  Mesh mesh;                            // the actual workpiece, world
  // With a lift (distortion_lift_deg_per_100mm): `mesh` split into the part
  // that stays (the plate) and the box that lifts off it; else both empty.
  Mesh fixed_part, moving_part;
  Pose tool_from_laser = Pose::Identity();
};

// Precondition: validate(params) is empty. With distortion, seam 2's truth
// is where the part has turned once seam 1 is welded to its end.
SimCell build_sim_cell(const SimCellParams& params);

// Thermal distortion (SimCellParams::distortion_deg_per_100mm): as seam 1 is
// welded, the weld shrinks behind the arc and the part ahead of it turns.
// Model: once the arc has welded seam 1 up to arc length s, the part is
// turned by theta(s) = rate * s / 100 mm about the plate normal through the
// seam's point at s (the arc pins the seam where it is): a point of the
// seam at arc length u > s ahead moves across the seam by about
// theta (u - s). The seam at the arc stays put, so a torch on the seam is
// on its truth, but the sensor 50 mm ahead sees the seam displaced by
// theta x 50 mm, where it will not be once the torch gets there. After
// seam 1, seam 2 is turned by theta(L1) about seam 1's end (its start).
// With a lift (SimCellParams::distortion_lift_deg_per_100mm) the box also
// turns against the plate by phi(s) = lift rate * s / 100 mm about the axis
// through the seam's point at s square to seam 1's wall, its far end up: the
// wall's foot u mm ahead of the arc stands (u - s) sin phi above the plate
// (the gap the sensor sees) and the wall's face stays in its plane, so the
// root line (the truth) does not move; behind the arc the weld holds it.
class SeamDistortion {
 public:
  explicit SeamDistortion(const SimCell& cell);
  // The TCP (the arc) is at `tcp`: the weld's progress along seam 1 is its
  // projection onto the seam, never going back.
  void update(const Vec3& tcp);
  double welded_mm() const { return s_; }
  const SimCell& cell() const { return *cell_; }
  double angle_deg() const;
  double lift_deg() const;
  // The part's rigid motion now (world): where its points have moved to.
  Pose part_motion() const;
  // The box's motion against the plate now (world, before part_motion()):
  // the lift; identity without one.
  Pose wall_motion() const;

 private:
  const SimCell* cell_;
  double rate_deg_per_mm_ = 0.0;
  double lift_deg_per_mm_ = 0.0;
  double s_ = 0.0;
};

// A standoff suiting the sensor: 100 mm (the paper's static setup B is 103 mm)
// for sensors with a deep window, else the middle of its depth of field.
double sim_standoff_mm(const ScannerDesc& scanner);

// Tracker parameters for the cell's fillets seen by `scanner` (surface
// tolerance from the depth noise at the standoff).
tracker::TrackerParams sim_tracker_params(const ScannerDesc& scanner, double standoff_mm);
// Master parameters for the cell (mount, speed, control at the sensor rate).
tracker::MasterParams sim_master_params(const SimCell& cell, double speed_mm_s, double rate_hz);

// Tracking error of one seam against its truth. Lateral: along
// SimSeamTruth::lateral(); vertical: along the plate normal; both of the TCP
// from the nearest point of the true seam line, over the weld samples.
struct SeamMetrics {
  bool welded = false;  // start found and some welding done
  bool start_found = false, end_found = false, lost = false;
  std::string failure;
  int samples = 0;
  double rms_lateral_mm = 0.0;
  double rms_vertical_mm = 0.0;
  double max_error_mm = 0.0;    // largest distance of the TCP from the true seam line (across it)
  double start_error_mm = 0.0;  // weld start (TCP) to the true start
  double end_error_mm = 0.0;    // weld end (TCP) to the true end
  double start_along_mm = 0.0;  // the start error's part along the seam (> 0: started late)
  double end_along_mm = 0.0;    // the end error's part along the seam (> 0: ended past the end)
  double search_mm = 0.0;
  double welded_mm = 0.0;
  int points = 0, rejected_points = 0, refits = 0;
  // The sensor's own accuracy: rms distance of the track points the master
  // accepted from the true seam line (before the seam object's fit).
  double sensor_rms_mm = 0.0;
  // The largest gap the sensor reported on the seam (SeamRun::max_gap_mm).
  double sensor_max_gap_mm = 0.0;
};

// TCP error against a seam: lateral, vertical (mm), and the nearest point of
// the true seam line (or path: lateral then across the path's local
// direction, on the open side).
struct PointError {
  double lateral_mm = 0.0, vertical_mm = 0.0;
  Vec3 true_point = Vec3::Zero();
};
PointError seam_error(const SimSeamTruth& seam, const Vec3& tcp);

// Where the TCP really was at a run's sample i: actual[i] when given (a
// robot's; RobotSensor::actual()), else the sample's commanded pose; and the
// weld path's centre there (that less the weave's offset).
Pose sample_tcp(const tracker::MasterResult& result, const std::vector<Pose>* actual, std::size_t i);
Vec3 weld_centre(const tracker::MasterResult& result, const std::vector<Pose>* actual, std::size_t i);

// The metrics of a master's run. `actual`: where the TCP really was at each
// sample (a robot's; RobotSensor::actual()), else the samples' commanded
// poses; either less the weave's offset (the weld path's centre).
std::vector<SeamMetrics> evaluate(const SimCell& cell, const tracker::MasterResult& result,
                                  const std::vector<Pose>* actual = nullptr);

}  // namespace vts
