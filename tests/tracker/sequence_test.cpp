// The sensor's sequence logic (tracker/sequence.h) and the sensor unit over a
// synthetic profile stream (tracker/sensor_interface.h), and the master's
// seam object and re-calibration (tracker/master.h). The stream is worked out
// here: a straight seam along world X from x = kSeamStart to kSeamEnd, seen
// by a sensor looking straight down from 100 mm; where the laser plane cuts
// the seam the profile is a 90-degree valley with its root on the seam, and
// elsewhere a flat plate 100 mm away.
#include <catch2/catch.hpp>

#include <cmath>
#include <memory>
#include <numbers>
#include <set>

#include "synthetic.h"
#include "tracker/master.h"
#include "tracker/sensor_interface.h"
#include "tracker/sequence.h"

namespace tk = vts::tracker;
using Eigen::Vector3d;

namespace {

constexpr double kSeamStart = 20.0;
constexpr double kSeamEnd = 80.0;
constexpr double kRate = 20.0;

// The sensor's x (travel) along world +X, y along world -Y, z (range) down.
Eigen::Matrix3d down_looking() {
  Eigen::Matrix3d r;
  r.col(0) = Vector3d::UnitX();
  r.col(1) = -Vector3d::UnitY();
  r.col(2) = -Vector3d::UnitZ();
  return r;
}

// A 90-degree valley whose first (web) plate stands gap_mm off the second
// (flange), which runs on under the web's edge.
std::vector<synth::Piece> stub_valley(const synth::Vec2& root, double gap_mm) {
  const synth::Vec2 web = synth::dir_deg(-135.0), flange = synth::dir_deg(-45.0);
  return {{root + 80.0 * web, root + gap_mm * web}, {root - 5.0 * flange, root + 80.0 * flange}};
}

struct SyntheticStream final : tk::ProfileStream {
  // Profiles whose index is in `invalid` come back with no valid point.
  std::set<std::int64_t> invalid;
  double lateral_mm = 0.0;  // the seam's offset along world Y
  // A wall entering and leaving the laser plane at a slant: this far before
  // the start and past the end, only a stub of the web is in the plane,
  // standing stub_gap_mm off the flange.
  double stub_mm = 0.0;
  double stub_gap_mm = 2.0;
  tk::Pose3 mount = tk::Pose3::Identity();
  int acquired = 0;

  bool acquire(std::int64_t index, double time_s, const tk::Pose3& world_from_tool,
               tk::SensorProfile& out) override {
    ++acquired;
    out.index = index;
    out.time_s = time_s;
    out.world_from_sensor = world_from_tool * mount;
    const double x = out.world_from_sensor.translation().x();
    // Root in the sensor frame: world (x, lateral, 0) seen from (x, y0, 100).
    const Vector3d root = out.world_from_sensor.inverse() * Vector3d(x, lateral_mm, 0.0);
    const synth::Vec2 root_yz(root.y(), root.z());
    const bool on_seam = x >= kSeamStart && x <= kSeamEnd;
    const bool stub = !on_seam && x >= kSeamStart - stub_mm && x <= kSeamEnd + stub_mm;
    auto pieces = on_seam ? synth::valley(root_yz, 90.0)
                          : std::vector<synth::Piece>{{{-80.0, 100.0}, {80.0, 100.0}}};
    if (stub) pieces = stub_valley(root_yz, stub_gap_mm);
    synth::Profile p = synth::sample(pieces, 256);
    if (invalid.count(index)) p.invalidate(0, p.size() - 1);
    out.y_mm = p.y;
    out.z_mm = p.z;
    out.valid = p.valid;
    return true;
  }
  double rate_hz() const override { return kRate; }
  const tk::Pose3& tool_from_sensor() const override { return mount; }
};

tk::Pose3 tool_at(double x) {
  tk::Pose3 p = tk::Pose3::Identity();
  p.linear() = down_looking();
  p.translation() = Vector3d(x, 0.0, 100.0);
  return p;
}

// Drives a unit along X from x0 at `step_mm` per profile; returns the events
// with the x at which each was raised.
struct Drive {
  std::vector<std::pair<tk::Event, double>> events;
  double x = 0.0;
  int cycles = 0;
};
void drive(tk::SensorUnit& unit, Drive& d, double x_until, double step_mm, double& clock_s,
           bool stop_on_event = true) {
  while (d.x < x_until) {
    d.x += step_mm;
    clock_s += 1.0 / kRate;
    ++d.cycles;
    for (tk::Event e : unit.advance(clock_s, tool_at(d.x))) d.events.emplace_back(e, d.x);
    if (stop_on_event && !d.events.empty()) return;
  }
}

struct Fixture {
  SyntheticStream* stream = nullptr;
  std::unique_ptr<tk::SensorUnit> unit;
  double clock_s = 0.0;
  Fixture() {
    auto s = std::make_unique<SyntheticStream>();
    stream = s.get();
    unit = std::make_unique<tk::SensorUnit>(std::move(s), tk::TrackerParams{});
  }
};

}  // namespace

TEST_CASE("sequence: commands move through the states", "[sequence]") {
  tk::Sequence seq;
  CHECK(seq.state() == tk::SensorState::Idle);
  seq.search_start();  // laser off: ignored
  CHECK(seq.state() == tk::SensorState::Idle);
  seq.laser_on();
  CHECK(seq.state() == tk::SensorState::LaserOn);
  seq.search_start();
  CHECK(seq.state() == tk::SensorState::Searching);
  seq.look_for_end();  // only from tracking
  CHECK(seq.state() == tk::SensorState::Searching);
  seq.idle();
  CHECK(seq.state() == tk::SensorState::LaserOn);
  seq.start_tracking();
  CHECK(seq.state() == tk::SensorState::Tracking);
  seq.look_for_end();
  CHECK(seq.state() == tk::SensorState::LookingForEnd);
  seq.laser_off();
  CHECK(seq.state() == tk::SensorState::Idle);
  // Observations while idle change nothing and are not counted.
  tk::Observation o;
  o.joint = true;
  CHECK_FALSE(seq.update(o).has_value());
  CHECK(seq.counters().profiles == 0);
}

TEST_CASE("sensor unit: no profiles with the laser off", "[sequence]") {
  Fixture f;
  Drive d;
  d.x = 0.0;
  drive(*f.unit, d, 50.0, 0.5, f.clock_s, false);
  CHECK(f.stream->acquired == 0);
  CHECK(f.unit->state() == tk::SensorState::Idle);
  CHECK_FALSE(f.unit->latest_joint(f.clock_s).has_value());
}

TEST_CASE("sensor unit: the start search finds the seam start within half a profile step", "[sequence]") {
  for (double step : {0.5, 0.37, 0.1}) {
    Fixture f;
    REQUIRE(f.unit->laser_on());
    f.unit->search_start();
    Drive d;
    d.x = 5.13;
    // The first profile on the seam; the one before it missed the seam.
    double x_first = d.x;
    while (x_first < kSeamStart) x_first += step;
    drive(*f.unit, d, 40.0, step, f.clock_s);
    REQUIRE(d.events.size() == 1);
    CHECK(d.events[0].first == tk::Event::StartFound);
    CHECK(f.unit->state() == tk::SensorState::StartFound);
    REQUIRE(f.unit->start_point());
    const Vector3d s = *f.unit->start_point();
    INFO("step " << step << " start " << s.transpose());
    CHECK(std::abs(s.x() - kSeamStart) <= 0.5 * step + 0.01);
    // The middle between the last plane without the joint and the first with it.
    CHECK(s.x() == Approx(x_first - 0.5 * step).margin(0.01));
    CHECK(std::abs(s.y()) < 0.01);
    CHECK(std::abs(s.z()) < 0.01);
    // Confirmation needs 1 mm and 3 profiles with the joint.
    CHECK(d.x >= x_first + 1.0 - 1e-9);
    CHECK(d.x <= x_first + std::max(1.0, 2 * step) + step + 1e-9);
  }
}

TEST_CASE("sensor unit: a joint only partly in the laser plane is not its start or its end", "[sequence]") {
  {
    // The stub is recognised as a fillet with a gap (what the sequence sees).
    tk::Tracker tracker;
    const synth::Profile p = synth::sample(stub_valley(synth::Vec2(0.0, 100.0), 2.0), 256);
    const tk::TrackResult& r = tracker.track(p.view());
    REQUIRE(r.status == tk::TrackStatus::Ok);
    REQUIRE(r.gap_mm == Approx(2.0).margin(0.3));
  }
  Fixture f;
  f.stream->stub_mm = 0.8;
  REQUIRE(f.unit->laser_on());
  f.unit->search_start();
  Drive d;
  d.x = 5.13;
  double x_first = d.x;  // the first profile with the whole joint
  while (x_first < kSeamStart) x_first += 0.5;
  drive(*f.unit, d, 40.0, 0.5, f.clock_s);
  REQUIRE(d.events.size() == 1);
  REQUIRE(d.events[0].first == tk::Event::StartFound);
  CHECK(f.unit->start_point()->x() == Approx(x_first - 0.25).margin(0.01));
  f.unit->start_tracking();
  f.unit->look_for_end();
  d.events.clear();
  drive(*f.unit, d, 100.0, 0.5, f.clock_s);
  REQUIRE(d.events.size() == 1);
  REQUIRE(d.events[0].first == tk::Event::EndFound);
  double x_last = x_first;  // the last profile with the whole joint
  while (x_last + 0.5 <= kSeamEnd) x_last += 0.5;
  CHECK(f.unit->end_point()->x() == Approx(x_last + 0.25).margin(0.01));
}

TEST_CASE("sensor unit: tracking reports joint data with its age and the end of the seam", "[sequence]") {
  Fixture f;
  f.stream->lateral_mm = 3.0;
  REQUIRE(f.unit->laser_on());
  f.unit->search_start();
  Drive d;
  d.x = 5.0;
  drive(*f.unit, d, 40.0, 0.5, f.clock_s);
  REQUIRE(f.unit->state() == tk::SensorState::StartFound);
  f.unit->start_tracking();
  d.events.clear();
  drive(*f.unit, d, 60.0, 0.5, f.clock_s, false);
  CHECK(d.events.empty());
  CHECK(f.unit->state() == tk::SensorState::Tracking);
  auto j = f.unit->latest_joint(f.clock_s);
  REQUIRE(j);
  CHECK(j->age_s == Approx(0.0).margin(1e-12));
  CHECK(j->track_point_world.x() == Approx(d.x).margin(0.01));
  CHECK(j->track_point_world.y() == Approx(3.0).margin(0.01));
  CHECK(j->track_point_world.z() == Approx(0.0).margin(0.01));
  CHECK(j->break_points[1].has_value());  // the fillet's root

  // Past the end while only tracking: the seam is lost after 5 mm.
  SECTION("not looking for the end: seam lost") {
    drive(*f.unit, d, 100.0, 0.5, f.clock_s);
    REQUIRE(d.events.size() == 1);
    CHECK(d.events[0].first == tk::Event::SeamLost);
    CHECK(d.events[0].second == Approx(kSeamEnd + 5.0).margin(0.6));
    CHECK(f.unit->state() == tk::SensorState::SeamLost);
    CHECK_FALSE(f.unit->end_point().has_value());
    // The data's age: the last joint was seen about 5 mm (0.5 s) ago.
    auto late = f.unit->latest_joint(f.clock_s);
    REQUIRE(late);
    CHECK(late->age_s == Approx(0.5).margin(0.06));
  }
  SECTION("looking for the end: end found within half a step") {
    f.unit->look_for_end();
    CHECK(f.unit->state() == tk::SensorState::LookingForEnd);
    drive(*f.unit, d, 100.0, 0.5, f.clock_s);
    REQUIRE(d.events.size() == 1);
    CHECK(d.events[0].first == tk::Event::EndFound);
    CHECK(d.events[0].second == Approx(kSeamEnd + 2.0).margin(0.6));
    REQUIRE(f.unit->end_point());
    CHECK(f.unit->end_point()->x() == Approx(kSeamEnd).margin(0.26));
    CHECK(f.unit->end_point()->y() == Approx(3.0).margin(0.01));
    f.unit->laser_off();
    CHECK(f.unit->state() == tk::SensorState::Idle);
    const int before = f.stream->acquired;
    drive(*f.unit, d, 110.0, 0.5, f.clock_s, false);
    CHECK(f.stream->acquired == before);
  }
}

TEST_CASE("sensor unit: invalid profiles are counted and a short run of them is bridged", "[sequence]") {
  Fixture f;
  REQUIRE(f.unit->laser_on());
  f.unit->start_tracking();  // tracking without a search
  // 40 profiles at 0.5 mm from x = 20.5: the seam; profiles 10..17 (4 mm) invalid.
  for (std::int64_t i = 10; i <= 17; ++i) f.stream->invalid.insert(i);
  Drive d;
  d.x = 20.0;
  drive(*f.unit, d, 40.0, 0.5, f.clock_s, false);
  CHECK(d.events.empty());
  CHECK(f.unit->state() == tk::SensorState::Tracking);
  CHECK(f.unit->counters().invalid_profiles == 8);
  CHECK(f.unit->counters().joint_profiles == 32);
  CHECK(f.unit->counters().longest_gap_mm == Approx(4.5).margin(1e-6));

  // A longer run (6 mm) while tracking loses the seam.
  for (std::int64_t i = 40; i <= 52; ++i) f.stream->invalid.insert(i);
  drive(*f.unit, d, 60.0, 0.5, f.clock_s);
  REQUIRE(d.events.size() == 1);
  CHECK(d.events[0].first == tk::Event::SeamLost);
}

TEST_CASE("sensor unit: a search that begins on the joint reports the start behind", "[sequence]") {
  Fixture f;
  REQUIRE(f.unit->laser_on());
  f.unit->search_start();
  Drive d;
  d.x = 30.0;  // already on the seam
  drive(*f.unit, d, 60.0, 0.5, f.clock_s);
  REQUIRE(d.events.size() == 1);
  CHECK(d.events[0].first == tk::Event::StartBehind);
  CHECK(f.unit->state() == tk::SensorState::LaserOn);
  CHECK_FALSE(f.unit->start_point().has_value());
}

TEST_CASE("sensor unit: profiles between two advance calls take interpolated poses", "[sequence]") {
  Fixture f;
  REQUIRE(f.unit->laser_on());
  f.unit->start_tracking();
  f.unit->advance(1.0, tool_at(30.0));  // profiles 1..20 at x = 30
  CHECK(f.stream->acquired == 20);
  f.unit->advance(2.0, tool_at(40.0));  // profiles 21..40, x from 30.5 to 40
  CHECK(f.stream->acquired == 40);
  CHECK(f.unit->last_profile().time_s == Approx(2.0));
  CHECK(f.unit->last_profile().world_from_sensor.translation().x() == Approx(40.0));
  auto j = f.unit->latest_joint(2.0);
  REQUIRE(j);
  CHECK(j->track_point_world.x() == Approx(40.0).margin(0.01));
}

TEST_CASE("seam object: the fit through noisy points follows the line", "[master]") {
  // World coordinates of the size the cells use, far from the origin.
  const Vector3d origin(600.0, 200.0, -6.0);
  const Vector3d dir = Vector3d(1.0, 0.2, -0.05).normalized();
  const Vector3d across = dir.cross(Vector3d::UnitZ()).normalized();
  tk::SeamObject seam;
  seam.reset(origin, Vector3d::UnitX());  // a guess 11 degrees off
  // Deterministic +-0.05 mm zig-zag across the seam, 0.5 mm apart, checked
  // behind the newest point as it grows (as the torch follows the sensor).
  for (int i = 0; i <= 200; ++i) {
    const double s = 0.5 * i;
    const double noise = (i % 2 ? 0.05 : -0.05);
    REQUIRE(seam.add(origin + s * dir + noise * across, 10.0, 1.0, 10));
    if (i >= 20 && i % 5 == 0) {
      INFO("i = " << i);
      CHECK(seam.direction().dot(dir) == Approx(1.0).margin(1e-5));
      for (double back : {0.0, 5.0, 10.0}) {
        const Vector3d p = seam.at(s - back, 10.0);
        CHECK((p - (origin + (s - back) * dir)).norm() < 0.02);
      }
    }
  }
  CHECK(seam.direction().dot(dir) == Approx(1.0).margin(1e-6));
  for (double s : {0.0, 25.0, 50.0, 99.0}) {
    const Vector3d p = seam.at(s, 10.0);
    const Vector3d truth = origin + s * dir;
    INFO("s = " << s);
    CHECK((p - truth).norm() < 0.01);
  }
  CHECK(seam.max_arc() == Approx(100.0).margin(0.01));
  // An outlier 2 mm off the line is gated out.
  CHECK_FALSE(seam.add(origin + 50.0 * dir + 2.0 * across, 10.0, 1.0, 10));
  CHECK(seam.size() == 201);
}

TEST_CASE("re-calibration recovers a displaced workpiece pose from one seam", "[master]") {
  tk::SeamPlan seam;
  seam.start_mm = Vector3d(-75.0, -75.0, 0.0);
  seam.end_mm = Vector3d(75.0, -75.0, 0.0);
  seam.plate_normal = Vector3d::UnitZ();
  seam.wall_normal = -Vector3d::UnitY();
  tk::Pose3 believed = tk::Pose3::Identity();
  believed.translation() = Vector3d(600.0, 200.0, 0.0);
  tk::Pose3 actual = believed;
  actual.rotate(Eigen::AngleAxisd(4.0 * std::numbers::pi / 180.0, Vector3d(0.3, -0.5, 1.0).normalized()));
  actual.pretranslate(Vector3d(6.0, -5.0, 3.0));
  const Vector3d s = actual * seam.start_mm, e = actual * seam.end_mm;
  const Vector3d np = actual.linear() * seam.plate_normal, nw = actual.linear() * seam.wall_normal;
  const tk::Pose3 est = tk::recalibrate(believed, seam, s, e, np, nw);
  CHECK((est.linear() - actual.linear()).norm() < 1e-9);
  CHECK((est.translation() - actual.translation()).norm() < 1e-9);
  // Without the normals, the seam still maps exactly onto the measured one.
  const tk::Pose3 line_only = tk::recalibrate(believed, seam, s, e, Vector3d::Zero(), Vector3d::Zero());
  CHECK((line_only * seam.start_mm - s).norm() < 1e-9);
  CHECK((line_only * seam.end_mm - e).norm() < 1e-9);
}

TEST_CASE("tool rotation: x along the seam and z into the joint", "[master]") {
  const Eigen::Matrix3d r = tk::tool_rotation(Vector3d::UnitX(), Vector3d::UnitZ(), -Vector3d::UnitY());
  CHECK(r.determinant() == Approx(1.0));
  CHECK((r.col(0) - Vector3d::UnitX()).norm() < 1e-12);
  CHECK((r.col(2) - Vector3d(0.0, 1.0, -1.0).normalized()).norm() < 1e-12);
}

TEST_CASE("curve seam object: a circle of radius 50 mm, points 0.5 mm apart with +-0.05 mm zig-zag, is followed to 0.02 mm",
          "[master]") {
  // A circle in a tilted plane: the seam at arc s is c + R (cos(s/R) u + sin(s/R) v).
  constexpr double R = 50.0;
  const Vector3d c(10.0, -20.0, 5.0);
  const Vector3d u = Vector3d(1.0, 0.0, 0.2).normalized();
  const Vector3d v = Vector3d::UnitY();
  auto seam_at = [&](double s) { return Vector3d(c + R * (std::cos(s / R) * u + std::sin(s / R) * v)); };
  auto tangent_at = [&](double s) { return Vector3d(-std::sin(s / R) * u + std::cos(s / R) * v); };
  tk::CurveSeamObject seam;
  seam.reset(tangent_at(0.0));
  // Half a turn (157 mm); the zig-zag alternates across the seam in the plane
  // and out of it.
  const int n = 314;
  for (int i = 0; i <= n; ++i) {
    const double s = 0.5 * i;
    const Vector3d across = (seam_at(s) - c).normalized();
    const Vector3d out = u.cross(v);
    const double noise = (i % 2 ? 0.05 : -0.05);
    REQUIRE(seam.add(seam_at(s) + noise * ((i / 2) % 2 ? across : out), 10.0, 1.0, 10));
    if (i >= 40 && i % 10 == 0) {
      INFO("i = " << i);
      // The arcs follow the true arc length to 0.5 %: they are sums of steps
      // projected onto the fit's tangent, which leans towards the last
      // point's noise (they only order the points; positions come from the fit).
      CHECK(seam.max_arc() == Approx(s).epsilon(0.005));
      for (double back : {0.0, 5.0, 10.0}) {
        Vector3d t;
        const Vector3d p = seam.at(seam.max_arc() - back, 10.0, &t);
        // Distance from the circle: across the true seam, not along it.
        const Vector3d r = p - c;
        const Vector3d in_plane = r - r.dot(u.cross(v)) * u.cross(v);
        CHECK(std::hypot(in_plane.norm() - R, r.dot(u.cross(v))) < 0.02);
        const double s_true = std::atan2(in_plane.dot(v), in_plane.dot(u)) * R;
        CHECK(t.dot(tangent_at(s_true)) > std::cos(0.5 * std::numbers::pi / 180.0));
      }
    }
  }
  // (A line fitted over +-10 mm sits 100 / (6 R) = 0.33 mm inside the
  // circle at the window's middle.) An outlier 2 mm off is gated out; the
  // plane square to the seam at s = 120 is crossed there.
  const Vector3d off = seam_at(100.0) + 2.0 * (seam_at(100.0) - c).normalized();
  CHECK_FALSE(seam.add(off, 10.0, 1.0, 10));
  const double s_cross = seam.crossing(seam_at(120.0), tangent_at(120.0), 10.0, 0.0);
  CHECK(s_cross == Approx(120.0).epsilon(0.005));
  CHECK((seam.at(s_cross, 10.0) - seam_at(120.0)).norm() < 0.02);
  // Not reached: NaN.
  CHECK(std::isnan(seam.crossing(seam_at(200.0), tangent_at(200.0), 10.0, 0.0)));
}
