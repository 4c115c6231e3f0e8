// Issue 19's disturbances and scenarios (pipeline/scenario.h,
// sensor/sim_cell.h, tracker/master.h): each disturbance's truth against
// its formula worked out here, the weave against its definition, the open
// loop's error against the distance between the planned and the true seam
// lines, scenario files' errors, and every built-in scenario's verdict.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numbers>

#include "pipeline/scenario.h"
#include "pipeline/sim_run.h"
#include "sensor/ray_scene.h"
#include "sensor/sim_cell.h"
#include "tracker/master.h"

using namespace vts;
namespace tk = vts::tracker;

namespace {

// Distance of p across the line through a and b (the errors are measured
// across the seam: lateral and vertical, not along it).
double line_distance(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 d = (b - a).normalized();
  const Vec3 r = p - a;
  return (r - r.dot(d) * d).norm();
}

// The box where the program believes it is.
SimCellParams undisplaced() {
  SimCellParams p;
  p.offset_mm = 0.0;
  p.rotation_deg = 0.0;
  return p;
}

// Whether a ray cast at the wall from the open side 0.05 mm above the plate
// at `foot` meets it.
bool hits_wall_behind(const vts::RayScene& scene, const Vec3& foot, const Vec3& n, const Vec3& a) {
  const Vec3 o = foot + 0.05 * n + 2.0 * a;
  vts::RayScene::Hit hit;
  return scene.intersect(o.cast<float>(), (-a).cast<float>(), 0.0f, 10.0f, hit);
}

}  // namespace

TEST_CASE("weave: 0 -> +1 -> -1 -> 0 with dwells, by its definition", "[sim]") {
  tk::MasterParams::Weave w;
  w.amplitude_mm = 2.0;
  w.frequency_hz = 1.0;
  w.dwell_s = 0.1;
  // Moving time 0.8 s: a quarter is 0.2 s.
  CHECK(tk::weave_unit(w, 0.0) == Approx(0.0).margin(1e-12));
  CHECK(tk::weave_unit(w, 0.1) == Approx(0.5));
  CHECK(tk::weave_unit(w, 0.2) == Approx(1.0));
  CHECK(tk::weave_unit(w, 0.25) == Approx(1.0));   // dwell 0.2 .. 0.3
  CHECK(tk::weave_unit(w, 0.5) == Approx(0.0).margin(1e-12));   // 0.3 + 0.2
  CHECK(tk::weave_unit(w, 0.7) == Approx(-1.0));
  CHECK(tk::weave_unit(w, 0.75) == Approx(-1.0));  // dwell 0.7 .. 0.8
  CHECK(tk::weave_unit(w, 0.9) == Approx(-0.5));
  CHECK(tk::weave_unit(w, 1.2) == Approx(1.0));    // periodic
  w.amplitude_mm = 0.0;
  CHECK(tk::weave_unit(w, 0.2) == 0.0);
}

TEST_CASE("sim cell: a bowed seam 1 is a circular arc of the given sagitta through the box's corners", "[sim]") {
  SimCellParams p = undisplaced();
  p.seam1_bow_mm = 6.0;
  const SimCell cell = build_sim_cell(p);
  const SimSeamTruth& t = cell.truth[0];
  REQUIRE(t.path.size() > 50);
  // Workpiece frame = world less the nominal pose (no displacement here).
  const Pose wp = cell.actual_world_from_workpiece.inverse();
  const Vec3 a = wp * t.path.front(), b = wp * t.path.back();
  CHECK((a - Vec3(-75.0, -75.0, 0.0)).norm() < 1e-9);
  CHECK((b - Vec3(75.0, -75.0, 0.0)).norm() < 1e-9);
  // Circle through the ends with sagitta 6 mm: R = (75^2 + 6^2) / 12, centre (0, -75 - 6 + R).
  const double r = (75.0 * 75.0 + 36.0) / 12.0;
  const Vec3 c(0.0, -81.0 + r, 0.0);
  double deepest = 0.0;
  for (const Vec3& q : t.path) {
    const Vec3 w = wp * q;
    CHECK(std::abs(w.z()) < 1e-9);
    CHECK((w - c).norm() == Approx(r).margin(1e-6));
    deepest = std::max(deepest, -75.0 - w.y());
  }
  CHECK(deepest == Approx(6.0).margin(1e-3));
  // The arc's length: 2 R asin(75 / R).
  CHECK(t.length() == Approx(2.0 * r * std::asin(75.0 / r)).epsilon(1e-5));
  // seam_error: a point 1 mm outside the arc's middle, 0.5 mm up, is 1 mm
  // lateral (towards the open side, -y) and 0.5 mm vertical.
  const Pose& w = cell.actual_world_from_workpiece;
  const PointError e = seam_error(t, w * Vec3(0.0, -82.0, 0.5));
  CHECK(e.lateral_mm == Approx(1.0).margin(1e-4));
  CHECK(e.vertical_mm == Approx(0.5).margin(1e-9));
}

TEST_CASE("sim cell: an S-curved seam 1 follows its sine", "[sim]") {
  SimCellParams p = undisplaced();
  p.seam1_wave_mm = 4.0;
  p.seam1_wavelength_mm = 100.0;
  const SimCell cell = build_sim_cell(p);
  const SimSeamTruth& t = cell.truth[0];
  REQUIRE(t.path.size() > 50);
  const Pose wp = cell.actual_world_from_workpiece.inverse();
  double lo = 0.0, hi = 0.0;
  for (const Vec3& q : t.path) {
    const Vec3 w = wp * q;
    const double u = w.x() + 75.0;
    CHECK(w.y() == Approx(-75.0 - 4.0 * std::sin(2.0 * std::numbers::pi * u / 100.0)).margin(1e-9));
    CHECK(std::abs(w.z()) < 1e-9);
    lo = std::min(lo, w.y() + 75.0);
    hi = std::max(hi, w.y() + 75.0);
  }
  CHECK(lo == Approx(-4.0).margin(0.01));
  CHECK(hi == Approx(4.0).margin(0.01));
  // 1 mm outside the crest (u = 25 mm, 4 mm out) is 1 mm lateral (the
  // polyline's chords, 2 mm long, sag up to 7 um there).
  const Pose& w = cell.actual_world_from_workpiece;
  const PointError e = seam_error(t, w * Vec3(-50.0, -79.0 - 1.0, 0.0));
  CHECK(e.lateral_mm == Approx(1.0).margin(0.01));
}

TEST_CASE("sim cell: tack welds where and as long as asked, as beads in the fillet's corner", "[sim]") {
  SimCellParams p = undisplaced();
  p.tack_spacing_mm = 50.0;
  p.tack_first_mm = 25.0;
  p.tack_length_mm = 3.0;
  p.tack_leg_mm = 3.0;
  const SimCell plain = build_sim_cell(undisplaced());
  const SimCell cell = build_sim_cell(p);
  // 150 mm seams: tacks from 25 and 75 mm (one from 125 would end at 128,
  // less than 25 mm before the end).
  REQUIRE(cell.tacks.size() == 4);
  for (int k = 0; k < 2; ++k)
    for (int i = 0; i < 2; ++i) {
      const TackSpan& s = cell.tacks[static_cast<std::size_t>(2 * k + i)];
      CHECK(s.seam == k);
      CHECK(s.s0_mm == Approx(25.0 + 50.0 * i));
      CHECK(s.s1_mm == Approx(28.0 + 50.0 * i));
    }
  // Every vertex the tacks add lies within their spans along the seam and
  // within the bead's section: legs of 3 mm, bulging 0.3 leg at most.
  const std::size_t first = plain.mesh.vertices.size();
  REQUIRE(cell.mesh.vertices.size() > first);
  const Pose wp = cell.actual_world_from_workpiece.inverse();
  for (std::size_t i = first; i < cell.mesh.vertices.size(); ++i) {
    const Vec3 v = wp * cell.mesh.vertices[i].cast<double>();
    const bool on1 = std::abs(v.y() + 75.0) < 4.5;  // seam 1 along y = -75 (open side -y)
    const bool on2 = std::abs(v.x() - 75.0) < 4.5;  // seam 2 along x = 75 (open side +x)
    REQUIRE((on1 || on2));
    const double along = on1 ? v.x() + 75.0 : v.y() + 75.0;
    const double out = on1 ? -75.0 - v.y() : v.x() - 75.0;
    INFO("vertex " << v.transpose());
    CHECK(v.z() >= -0.06);
    CHECK(v.z() <= 3.0 + 1e-4);
    CHECK(out <= 3.0 + 1e-4);
    CHECK(out + v.z() <= 3.0 + 0.3 * 3.0 * std::sqrt(2.0) + 1e-3);  // the bulge
    bool in_span = false;
    for (double s0 : {25.0, 75.0}) in_span = in_span || (along >= s0 - 1e-4 && along <= s0 + 3.0 + 1e-4);
    CHECK(in_span);
  }
}

TEST_CASE("sim cell: thermal distortion turns the part ahead of the arc about the arc's point", "[sim]") {
  SimCellParams p = undisplaced();
  p.distortion_deg_per_100mm = 1.0;
  const SimCell cell = build_sim_cell(p);
  const SimSeamTruth& t = cell.truth[0];
  const Vec3 d = t.direction(), lat = t.lateral(), n = t.plate_normal;
  SeamDistortion dist(cell);
  CHECK(dist.part_motion().isApprox(Pose::Identity()));
  dist.update(t.start + 60.0 * d + 0.3 * n);  // the arc welding at s = 60 (the TCP a little above the root)
  CHECK(dist.welded_mm() == Approx(60.0));
  CHECK(dist.angle_deg() == Approx(0.6));
  dist.update(t.start + 40.0 * d);  // never back
  CHECK(dist.welded_mm() == Approx(60.0));
  const Pose m = dist.part_motion();
  // The seam at the arc stays; 50 mm ahead it moves 50 sin(0.6 deg) towards
  // the open side and 50 (1 - cos) back along the seam.
  const Vec3 at = t.start + 60.0 * d, ahead = t.start + 110.0 * d;
  CHECK((m * at - at).norm() < 1e-9);
  const Vec3 moved = m * ahead - ahead;
  const double a = 0.6 * std::numbers::pi / 180.0;
  CHECK(moved.dot(lat) == Approx(50.0 * std::sin(a)).epsilon(1e-9));
  CHECK(moved.dot(d) == Approx(-50.0 * (1.0 - std::cos(a))).epsilon(1e-6));
  CHECK(std::abs(moved.dot(n)) < 1e-9);
  // Seam 2 as the part lies after seam 1: turned 1.5 degrees about its start.
  const SimCell plain = build_sim_cell(undisplaced());
  const SimSeamTruth& s2 = cell.truth[1];
  const SimSeamTruth& s2_plain = plain.truth[1];
  CHECK((s2.start - s2_plain.start).norm() < 1e-9);
  const double turned = std::acos(std::clamp(s2.direction().dot(s2_plain.direction()), -1.0, 1.0));
  CHECK(turned * 180.0 / std::numbers::pi == Approx(1.5).epsilon(1e-6));
  CHECK((s2.end - s2_plain.end).norm() == Approx(2.0 * 150.0 * std::sin(0.75 * std::numbers::pi / 180.0)).epsilon(1e-6));
}

TEST_CASE("sim cell: a thermal lift opens the gap under the wall ahead of the arc by x tan(phi)", "[sim]") {
  SimCellParams p = undisplaced();
  p.distortion_lift_deg_per_100mm = 1.0;
  const SimCell cell = build_sim_cell(p);
  REQUIRE_FALSE(cell.moving_part.triangles.empty());
  REQUIRE(cell.fixed_part.triangles.size() + cell.moving_part.triangles.size() == cell.mesh.triangles.size());
  const SimSeamTruth& t = cell.truth[0];
  const SimSeamTruth plain = build_sim_cell(undisplaced()).truth[0];
  CHECK((t.start - plain.start).norm() < 1e-12);  // the root line is the box's
  const Vec3 d = t.direction(), n = t.plate_normal, a = t.wall_normal;
  SeamDistortion dist(cell);
  CHECK(dist.wall_motion().isApprox(Pose::Identity()));
  dist.update(t.start + 60.0 * d + 0.3 * n);
  CHECK(dist.lift_deg() == Approx(0.6));
  CHECK(dist.part_motion().isApprox(Pose::Identity()));  // no turn asked for
  const Pose m = dist.wall_motion();
  // The wall's face stays in its plane; the point at the arc stays.
  const Vec3 at = t.start + 60.0 * d;
  CHECK((m * at - at).norm() < 1e-9);
  CHECK((m.linear() * a - a).norm() < 1e-12);
  // Where the box's bottom face lies x mm ahead of the arc (horizontally):
  // x tan(phi) above the plate, found by rays cast at the wall from the open
  // side, 2 mm away, at heights around it (those below pass under the wall).
  vts::RayScene scene(cell.fixed_part, cell.moving_part, "test");
  scene.move_part(m);
  const double phi = 0.6 * std::numbers::pi / 180.0;
  for (double x : {20.0, 50.0, 80.0}) {
    const double gap = x * std::tan(phi);
    auto hits_wall = [&](double z) {
      const Vec3 o = at + x * d + z * n + 2.0 * a;
      vts::RayScene::Hit hit;
      const bool h = scene.intersect(o.cast<float>(), (-a).cast<float>(), 0.0f, 10.0f, hit);
      if (h) {
        CHECK(hit.t == Approx(2.0).margin(1e-3));
        CHECK(std::abs(hit.normal.cast<double>().dot(a)) == Approx(1.0).margin(1e-6));
      }
      return h;
    };
    INFO("x = " << x << " mm ahead, gap " << gap << " mm");
    CHECK(hits_wall(gap + 0.005));
    CHECK_FALSE(hits_wall(gap - 0.005));
  }
  // Behind the arc the weld holds it: no gap.
  CHECK(hits_wall_behind(scene, at - 20.0 * d, n, a));
  // Rays cast 8 at a time see the moved wall as single rays do, its normal
  // turned into the world.
  std::vector<vts::RayScene::Segment> rays;
  for (int k = 0; k < 11; ++k) {
    const Vec3 o = at + (5.0 + 9.0 * k) * d + 0.6 * n + 2.0 * a;
    rays.push_back({o.cast<float>(), (-a).cast<float>(), 0.0f, 10.0f});
  }
  std::vector<vts::RayScene::Hit> hits(rays.size());
  std::vector<unsigned char> found(rays.size());
  scene.intersect(rays.data(), rays.size(), hits.data(), found.data());
  for (std::size_t k = 0; k < rays.size(); ++k) {
    vts::RayScene::Hit one;
    const bool single = scene.intersect(rays[k].o, rays[k].d, rays[k].tnear, rays[k].tfar, one);
    INFO("ray " << k);
    REQUIRE(static_cast<bool>(found[k]) == single);
    if (single) {
      CHECK(hits[k].t == one.t);
      CHECK((hits[k].normal - one.normal).norm() < 1e-6f);
      CHECK(hits[k].normal.cast<double>().dot(a) == Approx(1.0).margin(1e-6));
    }
  }
}

TEST_CASE("open loop: a perfect robot's error is the distance between the planned and the true seam lines", "[sim]") {
  SimSpec spec;
  spec.source = SourceKind::Reference;
  spec.cell.seed = spec.seed = 3;
  const SimRun run = run_sim(spec);
  REQUIRE(run.completed());
  REQUIRE(run.open_loop_metrics.size() == 2);
  for (std::size_t k = 0; k < 2; ++k) {
    const auto& plan = run.cell.plan[k];
    const Vec3 a = run.cell.nominal_world_from_workpiece * plan.start_mm;
    const Vec3 b = run.cell.nominal_world_from_workpiece * plan.end_mm;
    const SimSeamTruth& t = run.cell.truth[k];
    // Two straight lines: the largest distance is at an end of the weld,
    // whose first sample is one step (speed / rate = 0.5 mm) past a.
    const Vec3 a1 = a + 0.5 * (b - a).normalized();
    const double expected = std::max(line_distance(a1, t.start, t.end), line_distance(b, t.start, t.end));
    INFO("seam " << k + 1);
    CHECK(run.open_loop_metrics[k].max_error_mm == Approx(expected).margin(1e-6));
    CHECK(run.open_loop_metrics[k].start_error_mm == Approx((a - t.start).norm()).margin(1e-6));
    CHECK(run.open_loop_metrics[k].end_error_mm == Approx((b - t.end).norm()).margin(1e-6));
    CHECK(run.open_loop_metrics[k].max_error_mm > 2.0);
    CHECK(run.metrics[k].max_error_mm < 0.1);
  }
}

TEST_CASE("scenario files: bad values name the file, line and key", "[sim]") {
  auto error_of = [](const std::string& text) {
    try {
      parse_scenario(text, "s.yaml");
    } catch (const ScenarioError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  CHECK(error_of("robot: ur5\n") == "s.yaml:1: robot: robot = 'ur5': expected one of perfect, irb2400, kr16");
  CHECK(error_of("seed: 1\nexpect: maybe\n") == "s.yaml:2: expect: expect = 'maybe': expected pass or fail");
  CHECK(error_of("offset_mm: -1\n").find("s.yaml:1: offset_mm:") == 0);
  CHECK(error_of("seam1_bow_mm: 100\n").find("seam1_bow_mm") != std::string::npos);
  CHECK(error_of("colour: red\n").find("s.yaml:1: colour") == 0);
  CHECK(error_of("weave_frequency_hz: 1\nweave_dwell_s: 0.5\n").find("s.yaml:2: weave_dwell_s") == 0);
  CHECK(error_of("").find("empty scenario") != std::string::npos);
  CHECK(error_of("workpiece: cylinder\n") == "s.yaml:1: workpiece: workpiece = 'cylinder': expected box or saddle");
  CHECK(error_of("main_radius_mm: 150\n").find("s.yaml:1: main_radius_mm: main_radius_mm: only with workpiece: saddle") == 0);
  CHECK(error_of("workpiece: saddle\nbranch_radius_mm: 120\n").find("branch_radius_mm") != std::string::npos);
  CHECK(error_of("distortion_lift_deg_per_100mm: 1\nseam1_bow_mm: 10\n").find("seam1_bow_mm = 10: must be 0 with "
                                                                              "distortion_lift_deg_per_100mm") !=
        std::string::npos);
  CHECK(error_of("distortion_lift_deg_per_100mm: -1\n").find("distortion_lift_deg_per_100mm") != std::string::npos);
  CHECK_THROWS_AS(builtin_scenario("no-such"), ScenarioError);
  CHECK_THROWS_AS(load_scenario("/nonexistent/x.yaml"), ScenarioError);
}

TEST_CASE("every built-in scenario reaches the verdict its file expects, and the suite has what issue 19 asks",
          "[sim]") {
  const std::vector<std::string> names = scenario_names();
  REQUIRE(names.size() >= 8);
  int open_loop_beaten = 0, failing = 0;
  for (const std::string& name : names) {
    const Scenario sc = builtin_scenario(name);
    // The file under examples/ is the one compiled in.
    const Scenario from_file =
        load_scenario(std::filesystem::path(VTS_SOURCE_DIR) / "examples" / "scenarios" / (name + ".yaml"));
    CHECK(from_file.description == sc.description);
    const SimRun run = run_sim(sc.spec);
    const std::string reason = scenario_failure(run);
    INFO(name << ": " << reason);
    if (name == "thermal-gap") {
      // The sensor, 50 mm ahead, sees the gap 50 tan(phi) of a wall lifted
      // by phi = s / 100 mm degrees, s <= 100 mm while the laser is on seam 1:
      // at most 0.873 mm (with the noise), and none under seam 2's wall,
      // which turns about its own foot.
      REQUIRE(run.metrics.size() == 2);
      CHECK(run.metrics[0].sensor_max_gap_mm > 0.5);
      CHECK(run.metrics[0].sensor_max_gap_mm < 50.0 * std::tan(std::numbers::pi / 180.0) + 0.05);
      CHECK(run.metrics[1].sensor_max_gap_mm < 0.1);
    }
    if (sc.expect_pass) {
      CHECK(reason.empty());
      bool beaten = !run.open_loop_metrics.empty();
      for (std::size_t k = 0; k < run.metrics.size(); ++k)
        beaten = beaten && run.open_loop_metrics[k].max_error_mm > 2.0 && run.metrics[k].rms_lateral_mm < 0.2 &&
                 run.metrics[k].rms_vertical_mm < 0.2 && run.metrics[k].max_error_mm < 0.5;
      open_loop_beaten += beaten;
    } else {
      CHECK_FALSE(reason.empty());
      CHECK(reason.find(sc.expect_reason) != std::string::npos);
      ++failing;
    }
  }
  CHECK(open_loop_beaten >= 3);
  CHECK(failing >= 1);
}

TEST_CASE("master: a joint tracked farther from the plan than the part may be displaced is not welded", "[sim]") {
  // sharp-curve: seam 1 is lost, so seam 2 is searched from the plan; the
  // search finds seam 1's bowed wall near the corner, 35 mm from seam 2's
  // planned line. Before the check the torch welded it, 35.7 mm off seam 2.
  const Scenario sc = builtin_scenario("sharp-curve");
  const SimRun run = run_sim(sc.spec);
  REQUIRE(run.metrics.size() == 2);
  CHECK(run.metrics[0].lost);
  const SeamMetrics& m = run.metrics[1];
  INFO(m.failure);
  CHECK(m.failure.find("not the seam planned") != std::string::npos);
  CHECK(m.welded_mm < 1.0);
  CHECK(m.max_error_mm < 1.0);
}

TEST_CASE("sim cell: the saddle's plan and truth lie on both pipes, in the main pipe's frame", "[sim]") {
  SimCellParams p;
  p.workpiece = SimWorkpiece::Saddle;
  p.lookahead_mm = 20.0;
  p.seed = 7;
  REQUIRE(validate(p).empty());
  const SimCell cell = build_sim_cell(p);
  const double R = p.saddle.main_radius_mm, r = p.saddle.branch_radius_mm;
  REQUIRE(cell.plan.size() == 2);
  REQUIRE(cell.truth.size() == 2);
  // The saddle frame: the workpiece frame raised by R (the crowns at z = 0).
  auto in_saddle = [&](const Pose& world_from_workpiece, const Vec3& world) {
    return Vec3(world_from_workpiece.inverse() * world + Vec3(0.0, 0.0, R));
  };
  for (int k = 0; k < 2; ++k) {
    INFO("seam " << k + 1);
    const auto& plan = cell.plan[static_cast<std::size_t>(k)];
    REQUIRE(plan.path.size() > 150);
    for (const auto& q : plan.path) {
      const Vec3 s = q.point + Vec3(0.0, 0.0, R);
      CHECK(std::hypot(s.x(), s.y()) == Approx(r).margin(1e-9));  // on the branch
      CHECK(std::hypot(s.y(), s.z()) == Approx(R).margin(1e-9));  // on the main pipe
      CHECK((q.plate_normal - Vec3(0.0, s.y(), s.z()) / R).norm() < 1e-9);
      CHECK((q.wall_normal - Vec3(s.x(), s.y(), 0.0) / r).norm() < 1e-9);
    }
    // Both halves run from the crown at t = 0 (x = r, y = 0) over a flank
    // (seam 1 y > 0, seam 2 y < 0) to the other crown.
    const Vec3 start = plan.start_mm + Vec3(0.0, 0.0, R), end = plan.end_mm + Vec3(0.0, 0.0, R);
    CHECK((start - Vec3(r, 0.0, R)).norm() < 1e-9);
    CHECK((end - Vec3(-r, 0.0, R)).norm() < 1e-9);
    const Vec3 mid = plan.path[plan.path.size() / 2 + 20].point;
    CHECK(mid.y() * (k == 0 ? 1.0 : -1.0) > 0.5 * r);
    // Its lead-in: lookahead + 15 mm of the curve before the start.
    CHECK(plan.weld_from_mm == Approx(p.lookahead_mm + 15.0).margin(1.0));
    const SimSeamTruth& t = cell.truth[static_cast<std::size_t>(k)];
    REQUIRE(t.path_lateral.size() == t.path.size());
    REQUIRE(t.path_plate_normal.size() == t.path.size());
    for (std::size_t i = 0; i < t.path.size(); ++i) {
      const Vec3 s = in_saddle(cell.actual_world_from_workpiece, t.path[i]);
      CHECK(std::hypot(s.x(), s.y()) == Approx(r).margin(1e-6));
      CHECK(std::hypot(s.y(), s.z()) == Approx(R).margin(1e-6));
      const Eigen::Matrix3d rot = cell.actual_world_from_workpiece.linear();
      CHECK((t.path_plate_normal[i] - rot * Vec3(0.0, s.y(), s.z()) / R).norm() < 1e-6);
      // The lateral: in the main pipe's surface, square to the seam, away
      // from the branch.
      const Vec3 lat = rot.transpose() * t.path_lateral[i];
      CHECK(lat.dot(Vec3(0.0, s.y(), s.z())) == Approx(0.0).margin(1e-9));
      CHECK(lat.dot(Vec3(s.x(), s.y(), 0.0)) > 0.0);
      if (i > 0) CHECK(std::abs(t.path_lateral[i].dot((t.path[i] - t.path[i - 1]).normalized())) < 0.02);
    }
    // Errors in that frame: a point moved from a path point by a along the
    // lateral and b along the normal reads (a, b).
    const std::size_t i = t.path.size() / 3;
    const PointError e = seam_error(t, t.path[i] + 0.3 * t.path_lateral[i] - 0.2 * t.path_plate_normal[i]);
    CHECK(e.lateral_mm == Approx(0.3).margin(1e-3));
    CHECK(e.vertical_mm == Approx(-0.2).margin(1e-3));
  }
  // The box's disturbances are refused on the saddle, naming the field; the
  // look-ahead must leave the laser plane crossing the curving seam.
  SimCellParams bad = p;
  bad.seam1_bow_mm = 3.0;
  CHECK(validate(bad).find("seam1_bow_mm = 3") == 0);
  bad = p;
  bad.lookahead_mm = 50.0;
  CHECK(validate(bad).find("lookahead_mm = 50") == 0);
}
