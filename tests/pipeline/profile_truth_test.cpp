// profile_truth (pipeline/profile_truth.h): the labels' break points carry
// the tracker's numbers and scan order. The tracker reads ideal profiles of
// the built-in cells (Embree reference) from a view tilted and turned so the
// order matters; each break point the truth gives must be where the tracker
// puts the one of the same number. (Turned 4 and leaning 6 degrees, the
// bevel's square wall hides its root from lps-2048-short and the tracker
// puts its toe 4-7 mm up the wall, docs/JOINTS.md's known limit: the views
// here are milder.)
#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>
#include <string>

#include "pipeline/profile_truth.h"
#include "sensor/cell.h"
#include "sensor/reference_source.h"
#include "tracker/tracker.h"

using namespace vts;
namespace tk = vts::tracker;

TEST_CASE("profile truth: break points numbered and ordered as the tracker's", "[pipeline][truth]") {
  constexpr double kDeg = std::numbers::pi / 180.0;
  for (const char* name : {"static-E", "corner", "lap", "butt", "vgroove", "bevel", "ugroove-fill"}) {
    for (const double turn : {0.0, 180.0}) {  // the laser line's direction reversed: scan order too
      const Cell cell = *builtin_cell(name);
      const Workpiece& w = cell.workpieces.front();
      Pose pose = cell.path.pose_at(0);
      pose.rotate(Eigen::AngleAxisd((turn + 2.0) * kDeg, Vec3::UnitZ()));
      pose.rotate(Eigen::AngleAxisd(3.0 * kDeg, Vec3::UnitY()));
      ScannerDesc desc = cell.scanner;
      desc.ideal = true;
      Profile p;
      make_reference_source(desc, w.mesh())->scan(pose, p);
      tk::TrackerParams params;
      params.joint = *tracker_joint(w.type);
      if (w.type == JointType::Lap) params.lap.upper_thickness_mm = w.params.thickness_mm;
      params.groove.vgroove_fill = w.params.passes > 0;
      tk::Tracker tracker(params);
      const tk::TrackResult& r = tracker.track({p.y_mm, p.z_mm, p.valid});
      const ProfileTruth t = profile_truth(w, desc, pose);
      INFO(name << " turned " << turn << ": " << tk::to_string(r.status) << " " << r.reason);
      REQUIRE(r.status == tk::TrackStatus::Ok);
      CHECK(t.in_window);
      CHECK((*r.track_point - t.track_point).norm() < 0.1 + r.track_uncertainty_mm);
      int compared = 0;
      for (int b = 0; b < tk::kMaxBreakPoints; ++b) {
        if (!t.break_points[b]) continue;
        INFO("B" << b << ": tracker " << r.break_points[b]->transpose() << ", truth " << t.break_points[b]->transpose());
        REQUIRE(r.break_points[b]);
        CHECK((*r.break_points[b] - *t.break_points[b]).norm() < 0.3 + r.edge_uncertainty_mm);
        ++compared;
      }
      CHECK(compared >= 3);
      if (is_groove(w.type) && std::isfinite(r.wall_angle_a_deg)) {
        CHECK(r.wall_angle_a_deg == Approx(t.wall_angle_a_deg).margin(1.0));
        CHECK(r.wall_angle_b_deg == Approx(t.wall_angle_b_deg).margin(1.0));
      }
    }
  }
  CHECK_THROWS_AS(profile_truth(builtin_cell("plate")->workpieces.front(), ScannerDesc{}, Pose::Identity()),
                  std::invalid_argument);
}
