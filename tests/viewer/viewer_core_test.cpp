// vts-view's window-free parts: the key script, the torch mount and motion,
// the scan clock, the orbit camera and the sensor thread. Expected values come
// from the cells' geometry (sensor/cell.h, paper Table 2), not from the code.
#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>
#include <stdexcept>

#include "viewer/camera.h"
#include "viewer/keys.h"
#include "viewer/scan_worker.h"
#include "viewer/torch.h"
#include "sensor/cell.h"

namespace {

using vts::Pose;
using vts::Vec3;
using namespace vts::viewer;
using vts::SourceKind;

constexpr double kPi = std::numbers::pi;

}  // namespace

TEST_CASE("key script: names repeats chords and idle frames", "[viewer]") {
  const auto frames = parse_key_script("w*3 _, D+plus  space");
  REQUIRE(frames.size() == 6);
  CHECK(frames[0] == KeyFrame{Key::Forward});
  CHECK(frames[2] == KeyFrame{Key::Forward});
  CHECK(frames[3].empty());
  CHECK(frames[4] == (KeyFrame{Key::Right, Key::Faster}));
  CHECK(frames[5] == KeyFrame{Key::Pause});
  CHECK(parse_key_script("").empty());
  CHECK(parse_key_script("  ").empty());
}

TEST_CASE("key script: bad tokens name the token", "[viewer]") {
  const auto message = [](const char* script) {
    try {
      parse_key_script(script);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  CHECK_THAT(message("w x"), Catch::Contains("'x'") && Catch::Contains("valid names"));
  CHECK_THAT(message("w*0"), Catch::Contains("'w*0'"));
  CHECK_THAT(message("w*"), Catch::Contains("'w*'"));
  CHECK_THAT(message("w+"), Catch::Contains("'w+'"));
}

TEST_CASE("key table: every key has a unique script name", "[viewer]") {
  const auto keys = key_table();
  for (std::size_t i = 0; i < keys.size(); ++i)
    for (std::size_t j = i + 1; j < keys.size(); ++j) CHECK(keys[i].name != keys[j].name);
  for (const auto& k : keys) CHECK(parse_key_script(k.name) == std::vector<KeyFrame>{KeyFrame{k.key}});
}

TEST_CASE("torch mount: static-B puts the TCP on the root 50 mm behind the laser line", "[viewer]") {
  // Table 2 B: the laser origin is 103 mm from the root along the optical
  // axis; the path starts with the optical axis on the root at x = 20 mm.
  const vts::Cell cell = *vts::builtin_cell("static-B");
  const double standoff = standoff_at_start(cell);
  CHECK(standoff == Approx(103.0).margin(1e-3));

  const Pose tool_from_laser = default_tool_from_laser(standoff);
  const Pose torch = cell.path.start * tool_from_laser.inverse();
  // The root line is the joint frame's x axis (identity workpiece pose).
  CHECK(torch.translation().x() == Approx(20.0 - kLookAheadMm).margin(1e-9));
  CHECK(torch.translation().y() == Approx(0.0).margin(1e-9));
  CHECK(torch.translation().z() == Approx(0.0).margin(1e-9));
  // The torch axis (tool z) points into the work along the bisector of the
  // 90-degree fillet, and travel (tool x) runs along the seam.
  const Vec3 z = torch.linear().col(2), x = torch.linear().col(0);
  CHECK(z.isApprox(Vec3(0.0, -std::sqrt(0.5), -std::sqrt(0.5)), 1e-12));
  CHECK(x.isApprox(Vec3::UnitX(), 1e-12));
  // The laser sits 50 mm ahead of the TCP along travel.
  CHECK(((torch * tool_from_laser).translation() - torch.translation()).dot(x) ==
        Approx(kLookAheadMm).margin(1e-9));
}

TEST_CASE("torch motion: translation along tool axes and rotation about the TCP", "[viewer]") {
  Pose start = Pose::Identity();
  start.linear() = Eigen::AngleAxisd(0.3, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  start.translation() = Vec3(10, -5, 40);

  MotionInput forward;
  forward.translate = Vec3(1, 0, 0);
  const Pose moved = move_torch(start, forward, 10.0, 0.0, 2.0, false);
  CHECK((moved.translation() - start.translation()).isApprox(20.0 * start.linear().col(0), 1e-12));
  CHECK(moved.linear().isApprox(start.linear(), 1e-12));

  const Pose world = move_torch(start, forward, 10.0, 0.0, 2.0, true);
  CHECK((world.translation() - start.translation()).isApprox(Vec3(20, 0, 0), 1e-12));

  MotionInput yaw;
  yaw.rotate = Vec3(0, 0, 1);
  const Pose turned = move_torch(start, yaw, 0.0, 90.0, 1.0, false);
  CHECK(turned.translation().isApprox(start.translation(), 1e-12));
  // +90 degrees about tool z takes tool x to where tool y was.
  CHECK(turned.linear().col(0).isApprox(start.linear().col(1), 1e-9));
  CHECK(turned.linear().col(2).isApprox(start.linear().col(2), 1e-9));
}

TEST_CASE("interpolate: halfway in translation and angle", "[viewer]") {
  Pose a = Pose::Identity(), b = Pose::Identity();
  b.translation() = Vec3(10, 0, 0);
  b.linear() = Eigen::AngleAxisd(kPi / 2, Vec3::UnitZ()).toRotationMatrix();
  const Pose h = interpolate(a, b, 0.5);
  CHECK(h.translation().isApprox(Vec3(5, 0, 0)));
  CHECK(Eigen::AngleAxisd(h.linear()).angle() == Approx(kPi / 4));
}

TEST_CASE("scan clock: scan k at k / rate with none skipped and at most max per step", "[viewer]") {
  ScanClock clock{20.0};
  std::vector<ScanClock::Due> all;
  for (int i = 0; i < 30; ++i)
    for (const auto& d : clock.advance(1.0 / 30.0, 100)) {
      CHECK(d.fraction >= 0.0);
      CHECK(d.fraction <= 1.0);
      all.push_back(d);
    }
  // One second: scans at 0, 0.05, ..., 1.0 (the last within rounding).
  REQUIRE(all.size() >= 20);
  REQUIRE(all.size() <= 21);
  for (std::size_t k = 0; k < all.size(); ++k) {
    CHECK(all[k].index == static_cast<std::int64_t>(k));
    CHECK(all[k].time_s == Approx(static_cast<double>(k) / 20.0));
  }

  ScanClock fast{1000.0};
  const auto due = fast.advance(1.0, 10);
  CHECK(due.size() == 10);
  CHECK(fast.time_s == Approx(0.009));  // the clock waits at the last scan listed
  CHECK(fast.advance(0.0005, 10).size() == 0);
}

TEST_CASE("orbit camera: the target projects to the viewport's centre", "[viewer]") {
  const OrbitCamera cam = camera_looking_at(Vec3(10, 20, 30), Vec3(1, -1, 1), 500.0);
  CHECK((cam.eye_mm() - Vec3(10, 20, 30)).norm() == Approx(500.0));
  CHECK((cam.eye_mm() - Vec3(10, 20, 30)).normalized().isApprox(Vec3(1, -1, 1).normalized(), 1e-9));
  const auto px = project_to_pixel(cam.clip_from_world(800.0 / 600.0), Vec3(10, 20, 30), 800, 600);
  REQUIRE(px);
  CHECK(px->x() == Approx(400.0));
  CHECK(px->y() == Approx(300.0));
  // Behind the camera: no pixel.
  const Vec3 behind = cam.eye_mm() + (cam.eye_mm() - cam.target_mm);
  CHECK_FALSE(project_to_pixel(cam.clip_from_world(1.0), behind, 800, 600));
}

namespace {

void worker_scans_the_plate(SourceKind kind) {
  // The "plate" cell: a flat plate square to the optical axis at 100 mm.
  vts::Cell cell = *vts::builtin_cell("plate");
  cell.scanner.ideal = true;
  ScanWorker worker;
  worker.configure(cell.scanner, cell.mesh(), kind, 0);
  std::vector<ScanWorker::Request> requests;
  for (int i = 0; i < 5; ++i) requests.push_back({cell.path.pose_at(i), 0.05 * i, 100 + i});
  worker.submit(requests);
  worker.wait_idle();
  CHECK(worker.take_error().empty());
  const auto profiles = worker.take_results().output;
  REQUIRE(profiles.size() == 5);
  for (int i = 0; i < 5; ++i) {
    const vts::Profile& p = profiles[static_cast<std::size_t>(i)];
    CHECK(p.index == 100 + i);
    CHECK(p.time_s == Approx(0.05 * i));
    CHECK(p.world_from_sensor.isApprox(cell.path.pose_at(i)));
    REQUIRE(p.size() == cell.scanner.points);
    for (int c = 0; c < p.size(); ++c) {
      REQUIRE(p.valid[c]);
      CHECK(p.z_mm[c] == Approx(100.0).margin(1e-3));
    }
  }
  CHECK(worker.pending() == 0);

  // Reconfiguring drops what was submitted before.
  worker.submit(requests);
  worker.configure(cell.scanner, cell.mesh(), kind, 0);
  worker.wait_idle();
  CHECK(worker.take_results().output.empty());
}

}  // namespace

TEST_CASE("sensor thread: reference source gives results in request order", "[viewer]") {
  worker_scans_the_plate(SourceKind::Reference);
}

TEST_CASE("sensor thread: raster source on its own thread", "[viewer][gl]") {
  worker_scans_the_plate(SourceKind::Raster);
}
