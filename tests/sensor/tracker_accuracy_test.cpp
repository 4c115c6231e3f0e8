// The tracker on ideal profiles of the built-in joints (Embree reference),
// against each workpiece's analytic JointTruth, at standoffs 50..250 mm and
// the sensor tilted -20..+20 degrees about its x axis (the seam).
//
// Tolerances: the issue's (track point 0.05 mm, gap 0.1 mm, angle 0.5 deg)
// wherever the value comes from intersecting fitted lines. Where it depends on
// where a plate's surface ends (a plate edge), no algorithm can place the edge
// better than between two neighbouring column rays, so the tolerance is the
// larger of the issue's and that ray spacing along the surface, worked out
// here from the column geometry (sensor/rays.h's definition) and the analytic
// surfaces, never from the tracker's own output.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <sstream>
#include <string>

#include "joint_views.h"
#include "sensor/cell.h"
#include "sensor/reference_source.h"
#include "sensor/workpiece.h"
#include "tracker/tracker.h"

using namespace vts;
namespace tk = vts::tracker;

namespace {

using namespace vts::test;

// One scan: the laser looks at the root (shifted by shift_mm across the view)
// from the joint's natural direction turned by tilt_deg about the seam.
struct Scan : JointView {
  Profile profile;
};

Scan scan(const Workpiece& w, double standoff_mm, double tilt_deg, double shift_mm, int points = 512,
          double fan_deg = ScannerDesc{}.fan_deg) {
  Scan s;
  s.w = &w;
  s.desc.points = points;
  s.desc.fan_deg = fan_deg;
  // Depth of field wide enough to see the whole cross-section at 50 mm.
  s.desc.min_range_mm = 20.0;
  s.pose = root_view(w, standoff_mm, tilt_deg, shift_mm);
  auto source = make_reference_source(s.desc, w.mesh());
  source->scan(s.pose, s.profile);
  return s;
}

// Tolerances for one scan, from the geometry.
struct Tol {
  double track = kTrackTolMm;
  double gap = kGapTolMm;
  double angle = kAngleTolDeg;
  double other = kGapTolMm;  // mismatch, step, depth
  double area = 0.5;
  bool angle_always = true;  // the angle must be measured
};

Tol tolerances(const Scan& s) {
  const Workpiece& w = *s.w;
  const JointParams& p = w.params;
  const auto [d1, d2] = edge_spacings(s);
  Tol t;
  switch (w.type) {
    case JointType::Fillet:
      // The web's edge lies between two rays along the web.
      if (p.gap_mm > 0.0) t.gap = std::max(kGapTolMm, d1 * std::sin(p.angle_deg * kDeg));
      break;
    case JointType::Corner:
    case JointType::Butt:
      // Each plate's edge lies between two rays on its plate.
      if (w.type == JointType::Butt || p.gap_mm > 0.0) {
        t.track = std::max(kTrackTolMm, 0.5 * (d1 + d2));
        t.gap = std::max(kGapTolMm, d1 + d2);
      }
      break;
    case JointType::Lap:
      // Hidden edge face: the top edge lies between two rays on the upper plate.
      t.track = std::max(kTrackTolMm, d1);
      if (p.gap_mm > 0.0) t.gap = std::max(kGapTolMm, std::min(d2, 10.0));
      t.angle_always = false;  // only where the edge face is seen
      break;
    case JointType::VGroove:
      if (p.gap_mm > 0.0 || p.mismatch_mm != 0.0) {
        t.track = std::max(kTrackTolMm, std::max(d1, d2));
        t.gap = std::max(kGapTolMm, d1 + d2);
        t.other = std::max(kGapTolMm, std::max(d1, d2));
        const double top_width = 2.0 * (p.thickness_mm - p.root_face_mm) * std::tan(0.5 * p.angle_deg * kDeg);
        t.area = std::max(0.5, (p.thickness_mm - p.root_face_mm) * (d1 + d2) + top_width * std::max(d1, d2));
      }
      break;
    default: break;
  }
  return t;
}

std::string describe(const Scan& s, double standoff, double tilt, double shift) {
  std::ostringstream o;
  o << to_string(s.w->type) << " gap " << s.w->params.gap_mm << " mismatch " << s.w->params.mismatch_mm
    << " angle " << s.w->params.angle_deg << " at " << standoff << " mm, tilt " << tilt << " deg, shift " << shift;
  return o.str();
}

// Tracks one scan and checks it against the truth; returns false on failure.
void check_scan(const Scan& s, double standoff, double tilt, double shift, Worst& worst, int* angles = nullptr) {
  const Workpiece& w = *s.w;
  tk::Tracker tracker(params_for(w));
  const tk::TrackResult& r = tracker.track(view_of(s.profile));
  const Tol tol = tolerances(s);
  std::ostringstream segs;  // shown only when a check fails
  for (const auto& g : r.segments)
    segs << " [" << g.first_col << "-" << g.last_col << " n=" << g.points << " normal " << g.line.n.transpose()
         << " rms " << g.rms_mm << "]";
  INFO(describe(s, standoff, tilt, shift) << ": " << to_string(r.status) << " " << r.reason << ", "
                                          << r.segments.size() << " segments" << segs.str());
  REQUIRE(r.status == tk::TrackStatus::Ok);
  REQUIRE(r.track_point);
  const Vec2 root = s.to_sensor(w.truth.root_yz);
  const double track_err = (*r.track_point - root).norm();
  const double gap_err = std::abs(r.gap_mm - w.truth.gap_mm);
  INFO("track " << r.track_point->transpose() << " vs " << root.transpose() << " (err " << track_err << ", tol "
                << tol.track << "); gap " << r.gap_mm << " vs " << w.truth.gap_mm << " (tol " << tol.gap
                << "); angle " << r.angle_deg << " vs " << w.truth.angle_deg << "; mismatch " << r.mismatch_mm
                << "; step " << r.step_mm << "; depth " << r.depth_mm << "; area " << r.area_mm2
                << "; edge uncertainty " << r.edge_uncertainty_mm);
  const std::string key = std::string(to_string(w.type));
  CHECK(track_err <= tol.track);
  worst.add(key + " track", track_err);
  CHECK(gap_err <= tol.gap);
  worst.add(key + " gap", gap_err);
  if (tol.angle_always) REQUIRE(std::isfinite(r.angle_deg));
  if (std::isfinite(r.angle_deg)) {
    CHECK(std::abs(r.angle_deg - w.truth.angle_deg) <= tol.angle);
    worst.add(key + " angle", std::abs(r.angle_deg - w.truth.angle_deg));
    if (angles) ++*angles;
  }
  if (w.type == JointType::Butt || w.type == JointType::VGroove) {
    CHECK(std::abs(r.mismatch_mm - w.truth.mismatch_mm) <= tol.other);
    worst.add(key + " mismatch", std::abs(r.mismatch_mm - w.truth.mismatch_mm));
  }
  if (w.type == JointType::Lap) {
    CHECK(std::abs(r.step_mm - w.truth.step_mm) <= kGapTolMm);
    worst.add(key + " step", std::abs(r.step_mm - w.truth.step_mm));
  }
  if (w.type == JointType::VGroove) {
    REQUIRE(std::isfinite(r.depth_mm));
    REQUIRE(std::isfinite(r.area_mm2));
    CHECK(std::abs(r.depth_mm - w.truth.depth_mm) <= tol.other);
    CHECK(std::abs(r.area_mm2 - w.truth.area_mm2) <= tol.area);
    worst.add(key + " depth", std::abs(r.depth_mm - w.truth.depth_mm));
    worst.add(key + " area", std::abs(r.area_mm2 - w.truth.area_mm2));
  }
}

constexpr double kStandoffs[] = {50.0, 75.0, 100.0, 150.0, 200.0, 250.0};
constexpr double kTilts[] = {-20.0, -10.0, 0.0, 10.0, 20.0};
constexpr double kShifts[] = {0.0, 0.043};

}  // namespace

TEST_CASE("tracker: built-in joints at standoffs 50-250 mm, tilts -20..+20 deg", "[tracker][accuracy]") {
  for (const char* name : {"fillet", "corner", "lap", "butt", "vgroove"}) {
    const Cell cell = *builtin_cell(name);
    const Workpiece& w = cell.workpieces.front();
    Worst worst;
    int angles = 0;
    for (double standoff : kStandoffs)
      for (double tilt : kTilts)
        for (double shift : kShifts) check_scan(scan(w, standoff, tilt, shift), standoff, tilt, shift, worst, &angles);
    if (w.type == JointType::Lap) CHECK(angles > 0);  // the edge face is seen from one side
    WARN(name << " worst errors: " << worst.str());
  }
}

TEST_CASE("tracker: the paper's static setups A-F, tilted -20..+20 deg", "[tracker][accuracy][static]") {
  Worst worst;
  for (const auto& setup : kStaticSetups) {
    const Cell cell = *builtin_cell(std::string("static-") + setup.label);
    const Workpiece& w = cell.workpieces.front();
    // The cell's own pose first, then the same distance tilted.
    {
      tk::Tracker tracker(params_for(w));
      Profile p;
      auto source = make_reference_source(cell.scanner, cell.mesh());
      const Pose pose = cell.path.pose_at(0);
      source->scan(pose, p);
      const tk::TrackResult& r = tracker.track(view_of(p));
      INFO("static-" << setup.label << ": " << r.reason);
      REQUIRE(r.status == tk::TrackStatus::Ok);
      // The root is on the optical axis at the Table 2 distance.
      CHECK(r.track_point->x() == Approx(0.0).margin(kTrackTolMm));
      CHECK(r.track_point->y() == Approx(setup.distance_mm).margin(kTrackTolMm));
      CHECK(r.angle_deg == Approx(90.0).margin(kAngleTolDeg));
    }
    for (double tilt : kTilts)
      for (double shift : kShifts) check_scan(scan(w, setup.distance_mm, tilt, shift), setup.distance_mm, tilt, shift, worst);
  }
  WARN("static A-F worst errors: " << worst.str());
}

TEST_CASE("tracker: gaps of 0 to 2 point spacings", "[tracker][accuracy][gap]") {
  for (JointType type : {JointType::Fillet, JointType::Corner, JointType::Butt, JointType::VGroove, JointType::Lap}) {
    Worst worst;
    for (double standoff : {60.0, 100.0, 200.0}) {
      // Lateral column spacing at this standoff.
      const ScannerDesc desc;
      const double spacing = standoff * 2.0 * std::tan(0.5 * desc.fan_deg * kDeg) / desc.points;
      for (double k : {0.0, 0.5, 1.0, 1.5, 2.0}) {
        JointParams p = default_params(type);
        p.gap_mm = k * spacing;
        const Workpiece w = build_workpiece(type, p);
        for (double tilt : kTilts) {
          const Scan s = scan(w, standoff, tilt, 0.0);
          if (type == JointType::Butt &&
              p.gap_mm < 2.0 * s.spacing_along(feature(w, "left_edge"), Vec2(1.0, 0.0))) {
            // Coplanar plates with a gap narrower than two ray spacings: no
            // ray, or one, need fall into it, so there may be no joint to
            // see, or too little to be sure of (one ray into a gap is what
            // one dropout or reflection gives: rejected as weak,
            // ConfidenceParams). If the tracker reads one, it must be right.
            tk::Tracker tracker(params_for(w));
            const tk::TrackResult& r = tracker.track(view_of(s.profile));
            if (r.status == tk::TrackStatus::Rejected) {
              INFO(describe(s, standoff, tilt, 0.0) << ": " << r.reason);
              CHECK((r.reason == "no gap or step between two parallel plates" || r.reason.rfind("weak", 0) == 0));
              continue;
            }
          }
          check_scan(s, standoff, tilt, 0.0, worst);
        }
      }
    }
    WARN(to_string(type) << " small gaps, worst errors: " << worst.str());
  }
}

TEST_CASE("tracker: butt and v-groove with mismatch", "[tracker][accuracy]") {
  for (JointType type : {JointType::Butt, JointType::VGroove}) {
    Worst worst;
    for (double mismatch : {0.5, 1.0, 2.0}) {
      JointParams p = default_params(type);
      p.mismatch_mm = mismatch;
      const Workpiece w = build_workpiece(type, p);
      for (double standoff : {60.0, 120.0, 220.0})
        for (double tilt : kTilts) check_scan(scan(w, standoff, tilt, 0.0), standoff, tilt, 0.0, worst);
    }
    WARN(to_string(type) << " with mismatch, worst errors: " << worst.str());
  }
}

TEST_CASE("tracker: fillet and corner angles other than 90 degrees", "[tracker][accuracy]") {
  Worst worst;
  for (double angle : {60.0, 75.0, 110.0, 120.0}) {
    JointParams p = default_params(JointType::Fillet);
    p.angle_deg = angle;
    const Workpiece w = build_workpiece(JointType::Fillet, p);
    for (double standoff : {60.0, 150.0, 250.0})
      for (double tilt : kTilts) check_scan(scan(w, standoff, tilt, 0.0), standoff, tilt, 0.0, worst);
  }
  for (double angle : {90.0, 120.0, 150.0}) {
    JointParams p = default_params(JointType::Corner);
    p.angle_deg = angle;
    const Workpiece w = build_workpiece(JointType::Corner, p);
    for (double standoff : {60.0, 150.0, 250.0})
      for (double tilt : kTilts) check_scan(scan(w, standoff, tilt, 0.0), standoff, tilt, 0.0, worst);
  }
  WARN("other angles, worst errors: " << worst.str());
}

TEST_CASE("tracker: v-groove root face shorter than the minimum segment size", "[tracker][accuracy]") {
  Worst worst;
  for (double root_face : {0.3, 0.6, 1.0}) {
    JointParams p = default_params(JointType::VGroove);
    p.root_face_mm = root_face;
    p.gap_mm = 1.5;
    const Workpiece w = build_workpiece(JointType::VGroove, p);
    for (double standoff : {60.0, 100.0, 200.0}) {
      for (double tilt : kTilts) {
        const Scan s = scan(w, standoff, tilt, 0.0);
        // Count the points on the root faces: fewer than s_min = 8.
        int on_faces = 0;
        for (int i = 0; i < s.profile.size(); ++i) {
          if (!s.profile.valid[i]) continue;
          const Vec3 j = w.world_from_joint.inverse() * (s.pose * Vec3(0.0, s.profile.y_mm[i], s.profile.z_mm[i]));
          if (std::abs(std::abs(j.y()) - 0.5 * p.gap_mm) < 1e-3 && j.z() < 1e-3) ++on_faces;
        }
        INFO("root face " << root_face << ", " << on_faces << " points on the root faces");
        CHECK(on_faces < 8);
        check_scan(s, standoff, tilt, 0.0, worst);
      }
    }
  }
  WARN("short root faces, worst errors: " << worst.str());
}

// The same sweep with a 4096-column sensor (the largest ScannerDesc allows):
// its rays lie 0.05 mm apart at 250 mm, so the geometry-derived tolerances
// above come down to the issue's own figures (track 0.05 mm, gap 0.1 mm)
// for every fillet, corner, lap and butt scan. A v-groove's bevels are seen
// at 30 degrees or less (10 when tilted towards one), which spreads the rays
// along them two to six times wider than on a plate; for it the 4096 columns
// span a field 30 mm wide at the standoff (the groove is 13 mm wide at the
// top), which puts the rays 0.0073 mm apart across the seam and at most
// 0.045 mm apart along a bevel. Every scan of every joint is then held to
// the issue's tolerances, which the tolerances() geometry is checked to give.
TEST_CASE("tracker: the issue's tolerances where the columns resolve the plate edges", "[tracker][accuracy][fine]") {
  for (const char* name : {"fillet", "corner", "lap", "butt", "vgroove"}) {
    const Cell cell = *builtin_cell(name);
    const Workpiece& w = cell.workpieces.front();
    Worst worst;
    int scans = 0, at_issue_tolerance = 0;
    for (double standoff : kStandoffs)
      for (double tilt : kTilts)
        for (double shift : kShifts) {
          const double fan_deg =
              w.type == JointType::VGroove ? 2.0 * std::atan(15.0 / standoff) / kDeg : ScannerDesc{}.fan_deg;
          const Scan s = scan(w, standoff, tilt, shift, 4096, fan_deg);
          const Tol tol = tolerances(s);
          ++scans;
          if (tol.track == kTrackTolMm && tol.gap == kGapTolMm && tol.other == kGapTolMm) ++at_issue_tolerance;
          check_scan(s, standoff, tilt, shift, worst);
        }
    CHECK(at_issue_tolerance == scans);
    WARN(name << " at 4096 columns, " << at_issue_tolerance << " of " << scans
              << " scans at the issue's tolerances; worst errors: " << worst.str());
  }
}
