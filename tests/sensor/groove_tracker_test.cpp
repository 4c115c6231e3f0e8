// The tracker's groove model on the built-in groove cells (issue 18: a thick
// v-groove with beads, single bevels, U and J grooves), scanned by the Embree
// reference at each cell's own preset and standoff and at the ends of the
// 100-400 mm range, against each workpiece's analytic JointTruth (sensor/
// groove.cpp's closed formulas), never the tracker's own output.
//
// Sides: the tracker's first wall is the first in scan order; the cells'
// wall a is the joint's -y plate, which the default path sees on the
// sensor's +y side. Truth points are matched by their position along the
// laser line.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <utility>

#include "sensor/cell.h"
#include "sensor/presets.h"
#include "sensor/reference_source.h"
#include "sensor/workpiece.h"
#include "tracker/tracker.h"

using namespace vts;
namespace tk = vts::tracker;

namespace {

struct Case {
  const char* cell;
  double standoff_mm;  // 0: the cell's own
};

// Sensor-frame (y, z) of a joint-frame (y, z) point in the laser plane of `pose`.
Vec2 to_sensor(const Workpiece& w, const Pose& pose, const Vec2& yz) {
  const Pose sensor_from_joint = pose.inverse() * w.world_from_joint;
  const double x0 = (w.world_from_joint.inverse() * pose).translation().x();
  const Vec3 s = sensor_from_joint * Vec3(x0, yz.x(), yz.y());
  return Vec2(s.y(), s.z());
}

}  // namespace

TEST_CASE("groove cells: the groove model against the analytic truth", "[sensor][groove]") {
  const Case cases[] = {{"vgroove-thick", 0.0}, {"bevel", 0.0},         {"bevel-thick", 0.0},
                        {"ugroove", 0.0},       {"ugroove-fill", 0.0},  {"jgroove", 0.0},
                        {"vgroove-thick", 400.0}, {"bevel-thick", 400.0}, {"bevel", 95.0}, {"jgroove", 95.0}};
  // The jgroove seen from 95 mm by lps-2048-short: its square wall shows on
  // down as the root face through the gap; the square toe is the root edge,
  // at the level of the radius' lowest point across the gap, not the root
  // face's foot (1.6 mm too deep before: docs/JOINTS.md, "Grooves and fill").
  for (const Case& c : cases) {
    auto cell = builtin_cell(c.cell);
    REQUIRE(cell);
    const Workpiece& w = cell->workpieces.front();
    ScannerDesc desc = cell->scanner;
    Pose pose = cell->path.pose_at(0);
    if (c.standoff_mm > 0.0) {
      // The same view from 100 or 400 mm: lps-2048-short (60-100 mm) and the
      // mspot preset, whose window reaches 400 mm.
      desc = *sensor_preset(c.standoff_mm <= 100.0 ? "lps-2048-short" : "mspot");
      pose = default_path(w, c.standoff_mm).pose_at(0);
    }
    desc.ideal = true;
    Profile p;
    make_reference_source(desc, w.mesh())->scan(pose, p);
    tk::TrackerParams params;
    params.joint = *tracker_joint(w.type);
    params.groove.vgroove_fill = w.params.passes > 0;
    tk::Tracker tracker(params);
    const tk::TrackResult& r = tracker.track({p.y_mm, p.z_mm, p.valid});
    const JointTruth& t = w.truth;
    INFO(c.cell << " at " << (c.standoff_mm > 0.0 ? c.standoff_mm : 0.0) << " mm: " << tk::to_string(r.status) << " "
                << r.reason);
    REQUIRE(r.status == tk::TrackStatus::Ok);
    // Truth in scan order (by sensor y).
    Vec2 top1 = to_sensor(w, pose, t.top_a_yz), top2 = to_sensor(w, pose, t.top_b_yz);
    Vec2 toe1 = to_sensor(w, pose, t.toe_a_yz), toe2 = to_sensor(w, pose, t.toe_b_yz);
    double wall1 = t.wall_angle_a_deg, wall2 = t.wall_angle_b_deg;
    if (top1.x() > top2.x()) std::swap(top1, top2), std::swap(toe1, toe2), std::swap(wall1, wall2);
    const Vec2 b3 = to_sensor(w, pose, t.track_yz);
    // Ray spacing at the tops: an edge no line meets (a hidden square wall)
    // lies between two rays.
    const double spacing = top1.y() * 2.0 * std::tan(0.25 * desc.fan_deg * std::numbers::pi / 90.0) / desc.points;
    const double edge_tol = std::max(0.1, spacing);
    CHECK((*r.break_points[1] - top1).norm() < edge_tol);
    CHECK((*r.break_points[5] - top2).norm() < edge_tol);
    CHECK(r.wall_angle_a_deg == Approx(wall1).margin(0.5));
    CHECK(r.wall_angle_b_deg == Approx(wall2).margin(0.5));
    CHECK(r.top_width_mm == Approx(t.top_width_mm).margin(2.0 * edge_tol));
    CHECK(r.depth_mm == Approx(t.depth_mm).margin(0.1 + (w.params.passes == 0 ? spacing : 0.0)));
    CHECK(r.area_mm2 == Approx(t.area_mm2).epsilon(0.02));
    REQUIRE(r.track_point);
    CHECK((*r.track_point - b3).norm() < 0.3);
    INFO("B2 " << r.break_points[2]->transpose() << " truth " << toe1.transpose() << "; B4 "
               << r.break_points[4]->transpose() << " truth " << toe2.transpose() << "; B3 "
               << r.track_point->transpose() << " truth " << b3.transpose());
    CHECK((*r.break_points[2] - toe1).norm() < 0.5);
    CHECK((*r.break_points[4] - toe2).norm() < 0.5);
  }
}
