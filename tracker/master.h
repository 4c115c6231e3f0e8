#pragma once
// The master program of the paper's dynamic experiment (section 5.2): welds
// the seams of one workpiece, guided through the sensor interface only.
// Per seam: move to the search pose, laser on, search for the start point
// along the planned seam, approach the start while the sensor tracks ahead,
// weld along the seam object (the measured seam) through a delay buffer, ask
// the sensor to look for the end near the planned end, stop at the end point.
// Between seams the workpiece pose is re-estimated from the welded seam so
// that the next search starts closer to the actual start.
//
// Frames: world (mm); workpiece frame (the master's model, placed in the
// world by its believed world_from_workpiece); tool frame: origin at the TCP,
// x the travel direction, z along the torch axis into the joint.
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "tracker/sensor_interface.h"

namespace vts::tracker {

using Vec3 = Eigen::Vector3d;

// A point of a curved seam's plan: the root and the two surfaces' normals
// there (workpiece frame).
struct PathPoint {
  Vec3 point = Vec3::Zero();
  Vec3 plate_normal = Vec3::UnitZ();
  Vec3 wall_normal = -Vec3::UnitY();
};

// A fillet seam of the master's model, workpiece frame.
struct SeamPlan {
  Vec3 start_mm = Vec3::Zero();
  Vec3 end_mm = Vec3::UnitX();
  Vec3 plate_normal = Vec3::UnitZ();  // unit: bottom plate (flange) surface, out of the material
  Vec3 wall_normal = -Vec3::UnitY();  // unit: wall (web) surface on the open side, out of the material
  // A curved seam (e.g. half of a pipe saddle), when not empty: the root as
  // points at most a few mm apart with their normals. The weld runs from
  // arc length weld_from_mm along the path to its end; the path before that
  // is the approach, along which the sensor measures the seam ahead of the
  // torch. start_mm .. end_mm are then not used. See Master.
  std::vector<PathPoint> path;
  double weld_from_mm = 0.0;
};

struct MasterParams {
  double speed_mm_s = 10.0;       // weld, search and approach speed
  double control_rate_hz = 20.0;  // master cycle (one sensor advance per cycle)
  // The sensor's mount as calibrated: the laser plane crosses the work this
  // far ahead of the TCP along tool x.
  double lookahead_mm = 50.0;
  // The search begins with the laser plane this far before the planned start:
  // first seam (workpiece pose unknown) and later seams (after re-calibration).
  double search_margin_mm = 25.0;
  double search_margin_recalibrated_mm = 3.0;
  // The search gives up after margin * 2 + this much travel.
  double search_extra_mm = 10.0;
  int max_search_retries = 2;  // backing off after Event::StartBehind
  // look_for_end() is issued when the sensor is this far before the planned end.
  double end_margin_mm = 20.0;
  // Seam object: the torch position at arc length s is a linear fit of the
  // measured points within s +- fit_window_mm; a new point further than
  // gate_mm from the fit's prediction is rejected (once gate_after points exist).
  double fit_window_mm = 10.0;
  double gate_mm = 1.0;
  int gate_after = 10;
  // The torch travels along the planned direction until the seam object
  // spans this much, then along the measured one.
  double direction_span_mm = 10.0;
  // This many consecutive joint points rejected by the gate, consistent with
  // one another (within gate_mm of their own line): the seam object is
  // started again from them (SeamRun::refits).
  int refit_after_rejections = 6;
  bool recalibrate = true;
  // Joint data further than this from the planned seam line end the seam
  // with a failure: the joint tracked is not the seam planned (another
  // joint, the wrong part). 0: search_margin_mm, the displacement the
  // program is prepared for.
  double plan_tolerance_mm = 0.0;
  // Moves between poses (to a search pose, backing off): 0 puts the tool
  // there in one cycle, as a perfect robot can; > 0 travels in a straight
  // line at up to this speed (the orientation turned by slerp, at most
  // kMaxTurnDegS), starting and stopping smoothly (3 u^2 - 2 u^3 of the way
  // at u of the move's time), one servo target per cycle, then waits
  // settle_s for the robot to come to rest.
  double move_speed_mm_s = 0.0;
  double settle_s = 0.0;
  static constexpr double kMaxTurnDegS = 90.0;
  // Weaving while welding (amplitude 0: none), see Weave.
  struct Weave {
    double amplitude_mm = 0.0;  // the torch's lateral excursion either side of the seam
    double frequency_hz = 1.0;
    double dwell_s = 0.0;       // held at each side per period
  } weave;
  // The same program without the sensor: each seam welded along its plan
  // (the believed workpiece pose) from the planned start to the planned end.
  // The laser stays off; the sensor interface only keeps the clock.
  bool open_loop = false;
};

// The weave's lateral offset, in units of the amplitude, t seconds into the
// weld: 0 -> +1 over a quarter of the moving time, dwell, +1 -> -1 over half
// of it, dwell, -1 -> 0; the moving time is 1/frequency - 2 dwell.
double weave_unit(const MasterParams::Weave& weave, double t);

enum class Phase { Move, Search, Approach, Weld, Done };
std::string_view to_string(Phase phase);

// One master cycle.
struct MasterSample {
  double time_s = 0.0;
  int seam = 0;  // index into the plan
  Phase phase = Phase::Move;
  SensorState sensor = SensorState::Idle;
  Pose3 world_from_tool = Pose3::Identity();
  double s_mm = 0.0;  // weld: the TCP's arc length along the seam object
  // The weave's offset in world_from_tool (world, mm): the path's centre is
  // world_from_tool.translation() - weave_mm.
  Vec3 weave_mm = Vec3::Zero();
};

struct SeamRun {
  bool start_found = false;
  bool end_found = false;
  bool lost = false;          // the sensor reported the seam lost; welded up to the last point
  std::string failure;        // empty when the seam was welded from start to end
  double search_mm = 0.0;     // laser travel during the search(es)
  Vec3 start_point = Vec3::Zero();  // as the sensor reported it, world
  Vec3 end_point = Vec3::Zero();    // as the sensor reported it (end_found), world
  Vec3 weld_start = Vec3::Zero();   // TCP where welding began
  Vec3 weld_end = Vec3::Zero();     // TCP where welding stopped
  double welded_mm = 0.0;
  int points = 0;           // joint data accepted into the seam object
  std::vector<Vec3> track_points;  // those points (world), in order of arrival
  // The largest gap the sensor reported with the joint data accepted as
  // they came (not those taken back in by a refit); 0 if none was measured.
  double max_gap_mm = 0.0;
  int rejected_points = 0;  // joint data gated out
  int refits = 0;           // times the seam object was started again (refit_after_rejections)
  // The seam object's line at the end: point and unit direction, world.
  Vec3 line_point = Vec3::Zero();
  Vec3 line_direction = Vec3::UnitX();
};

struct MasterResult {
  std::vector<MasterSample> samples;
  std::vector<SeamRun> seams;
  // The workpiece pose as believed before each seam (index = seam).
  std::vector<Pose3> world_from_workpiece;
};

// The measured seam: joint points in world, arc length from the start point
// along the running line fit.
class SeamObject {
 public:
  void reset(const Vec3& origin, const Vec3& direction_guess);
  // Adds a measured point unless it lies more than gate_mm off the current
  // fit (once gate_after points exist; before, more than gate_mm + 0.2 arc
  // off the line from the origin along direction()). Returns whether it was added.
  bool add(const Vec3& p, double window_mm, double gate_mm, int gate_after);
  int size() const { return static_cast<int>(points_.size()); }
  // Unit direction of the least-squares line through all points (the guess
  // until two points span 2 mm).
  Vec3 direction() const;
  double arc(const Vec3& p) const { return (p - origin_).dot(direction()); }
  double max_arc() const;
  // The seam at arc length s: a linear fit of the points within s +- window_mm
  // (all points if too few lie there).
  Vec3 at(double s, double window_mm) const;
  Vec3 centroid() const;

 private:
  Vec3 origin_ = Vec3::Zero();
  Vec3 guess_ = Vec3::UnitX();
  double first_arc_ = 0.0;
  std::vector<Vec3> points_;  // sorted by arcs_
  std::vector<double> arcs_;  // arc length of each point when it was added
  double span_ = 0.0;         // largest distance of a point from the origin
  Vec3 sum_ = Vec3::Zero();  // of (point - origin)
  Eigen::Matrix3d sum_outer_ = Eigen::Matrix3d::Zero();
};

// The measured seam of a curved plan: joint points in world, each at an arc
// length along the points before it (the projection onto the seam's local
// fit), and the seam at arc s from a local quadratic fit of the points
// within s +- a window: on a circle of radius 50 mm a line fit over +-10 mm
// is 0.3 mm inside the arc, a quadratic 0.01 mm.
class CurveSeamObject {
 public:
  // `direction_guess`: the planned travel direction at the first point;
  // the first point's arc is first_arc.
  void reset(const Vec3& direction_guess, double first_arc = 0.0);
  // The arc a new point p would get.
  double arc_of(const Vec3& p, double window_mm) const;
  // Adds a measured point unless, once gate_after points exist, it lies more
  // than gate_mm from the fit's prediction at its arc (before: more than
  // gate_mm + 0.2 arc off the line from the first point along the guess).
  bool add(const Vec3& p, double window_mm, double gate_mm, int gate_after);
  int size() const { return static_cast<int>(points_.size()); }
  double max_arc() const { return arcs_.empty() ? 0.0 : arcs_.back(); }
  // The seam at arc s and its unit tangent there: least squares of
  // p(u) = a + b u + c u^2 over the points with |arc - s| <= window_mm
  // (u = arc - s): a and b / |b|; a line with fewer than 5 points or a span
  // under 2 mm, the nearest point with fewer than 2.
  Vec3 at(double s, double window_mm, Vec3* tangent = nullptr) const;
  // The arc at which the seam crosses the plane through q square to the
  // unit n from its back (n . (p - q) < 0) to its front: the first such
  // crossing at or after from_arc; NaN if the points do not reach it.
  double crossing(const Vec3& q, const Vec3& n, double window_mm, double from_arc) const;
  const std::vector<Vec3>& points() const { return points_; }

 private:
  Vec3 guess_ = Vec3::UnitX();
  double first_arc_ = 0.0;
  std::vector<Vec3> points_;  // sorted by arcs_
  std::vector<double> arcs_;
};

// The tool orientation for a seam: x along `direction`, z into the joint
// (against the bisector of the two surface normals), y = z cross x.
Eigen::Matrix3d tool_rotation(const Vec3& direction, const Vec3& plate_normal, const Vec3& wall_normal);

// Re-calibration: the workpiece pose that maps the seam plan's start and end
// onto the measured ones (least squares) and its direction and face normals
// onto the measured direction and normals (Kabsch). `measured_plate_normal`
// and `measured_wall_normal` may be zero (unknown): the believed ones are kept.
Pose3 recalibrate(const Pose3& believed_world_from_workpiece, const SeamPlan& seam, const Vec3& start,
                  const Vec3& end, const Vec3& measured_plate_normal, const Vec3& measured_wall_normal);

// A straight seam (SeamPlan without a path) is searched for its start,
// welded along the seam object and ended where the sensor finds its end.
// A curved seam (SeamPlan::path) is not searched: a closed seam (a saddle)
// has no start to find. The tool moves to the path's first point, the
// laser comes on and tracks while the tool travels the planned path up to
// weld_from_mm; the weld starts where the measured seam crosses the plane
// square to the path there, follows the measured seam (CurveSeamObject),
// the torch along its tangent and turned about it by the planned normals
// nearest the torch, and ends where the measured seam crosses the plane
// square to the path at its end. Re-calibration after a curved seam shifts
// the believed pose by the mean offset of the accepted joint points from
// the planned path (a translation; the turn is not estimated).
class Master {
 public:
  explicit Master(const MasterParams& params = {}) : params_(params) {}
  // Welds `seams` of the workpiece believed at world_from_workpiece. Calls
  // on_cycle after every cycle (may be empty).
  MasterResult run(SensorInterface& sensor, const Pose3& world_from_workpiece,
                   const std::vector<SeamPlan>& seams,
                   const std::function<void(const MasterSample&)>& on_cycle = {});
  const MasterParams& params() const { return params_; }

 private:
  MasterParams params_;
};

}  // namespace vts::tracker
