// The raster source against geometry worked out here, in double, from the
// column definition t_i = tan(fan/2) * (2 (i + 0.5) / N - 1) of sensor/rays.h.
#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <thread>
#include <vector>

#include <Eigen/Geometry>

#include "render/raster_source.h"
#include "sensor/mesh.h"
#include "sensor/pose.h"
#include "sensor/profile.h"
#include "sensor/scanner.h"

namespace {

using Eigen::Vector3d;

constexpr double kTolMm = 1e-3;
constexpr double kPi = std::numbers::pi;

vts::ScannerDesc scanner(int points) {
  vts::ScannerDesc d;
  d.fan_deg = 40.0;
  d.points = points;
  d.min_range_mm = 20.0;
  d.max_range_mm = 1000.0;
  d.max_hit_mm = 1200.0;
  return d;
}

double tan_i(const vts::ScannerDesc& d, int i) {
  return std::tan(0.5 * d.fan_deg * kPi / 180.0) * (2.0 * (i + 0.5) / d.points - 1.0);
}

// Unit ray of column i in the sensor frame.
Vector3d ray_i(const vts::ScannerDesc& d, int i) {
  return Vector3d(0.0, tan_i(d, i), 1.0).normalized();
}

// Square centre +- half*u +- half*v, split into cells x cells quads of two
// triangles each (so the source sees many triangles and clipped ones).
vts::Mesh square(const Vector3d& centre, const Vector3d& u, const Vector3d& v, double half,
                 int cells = 4) {
  vts::Mesh m;
  for (int a = 0; a <= cells; ++a)
    for (int b = 0; b <= cells; ++b) {
      const double s = -half + 2.0 * half * a / cells;
      const double t = -half + 2.0 * half * b / cells;
      m.vertices.push_back((centre + s * u + t * v).cast<float>());
    }
  const auto at = [&](int a, int b) { return static_cast<std::uint32_t>(a * (cells + 1) + b); };
  for (int a = 0; a < cells; ++a)
    for (int b = 0; b < cells; ++b) {
      m.triangles.push_back({at(a, b), at(a + 1, b), at(a + 1, b + 1)});
      m.triangles.push_back({at(a, b), at(a + 1, b + 1), at(a, b + 1)});
    }
  return m;
}

// A plane given in the sensor frame, meshed in the world frame of `pose`.
vts::Mesh plane_in_sensor(const vts::Pose& pose, const Vector3d& point_s,
                          const Eigen::Matrix3d& rot_s, double half, int cells = 4) {
  return square(pose * point_s, pose.linear() * rot_s.col(0), pose.linear() * rot_s.col(1),
                half, cells);
}

// Distance along column i to the plane through p with normal n (sensor frame),
// or nullopt when the ray misses it (parallel or behind).
std::optional<double> ray_plane(const vts::ScannerDesc& d, int i, const Vector3d& p,
                                const Vector3d& n) {
  const Vector3d dir = ray_i(d, i);
  const double den = n.dot(dir);
  if (den == 0.0) return std::nullopt;
  const double t = n.dot(p) / den;
  if (!(t > 0.0)) return std::nullopt;
  return t;
}

// What the scanner should report for a raw hit at distance t along column i.
bool expect_valid(const vts::ScannerDesc& d, int i, std::optional<double> t) {
  if (!t) return false;
  const double z = *t * ray_i(d, i).z();
  return *t <= d.max_hit_mm && z >= d.min_range_mm && z <= d.max_range_mm;
}

// Checks every column against expected raw hits; returns max |range error|.
double check_profile(const vts::ScannerDesc& d, const vts::Profile& p,
                     const std::vector<std::optional<double>>& hits) {
  REQUIRE(p.size() == d.points);
  double worst = 0.0;
  for (int i = 0; i < d.points; ++i) {
    INFO("column " << i << " of " << d.points);
    const bool valid = expect_valid(d, i, hits[i]);
    REQUIRE(static_cast<bool>(p.valid[i]) == valid);
    if (!valid) {
      CHECK(p.range_mm[i] == 0.0f);
      continue;
    }
    const double t = *hits[i];
    const Vector3d dir = ray_i(d, i);
    const double err = std::abs(p.range_mm[i] - t);
    worst = std::max(worst, err);
    CHECK(err <= kTolMm);
    CHECK(std::abs(p.y_mm[i] - t * dir.y()) <= kTolMm);
    CHECK(std::abs(p.z_mm[i] - t * dir.z()) <= kTolMm);
  }
  return worst;
}

std::vector<std::optional<double>> plane_hits(const vts::ScannerDesc& d, const Vector3d& p,
                                              const Vector3d& n) {
  std::vector<std::optional<double>> hits(d.points);
  for (int i = 0; i < d.points; ++i) hits[i] = ray_plane(d, i, p, n);
  return hits;
}

Eigen::Matrix3d rot_x_deg(double deg) {
  return Eigen::AngleAxisd(deg * kPi / 180.0, Vector3d::UnitX()).toRotationMatrix();
}
Eigen::Matrix3d rot_y_deg(double deg) {
  return Eigen::AngleAxisd(deg * kPi / 180.0, Vector3d::UnitY()).toRotationMatrix();
}

vts::Pose some_pose() {
  return vts::pose_from_xyz_rpy(Vector3d(1250.0, -730.0, 410.0), Vector3d(28.0, -17.0, 63.0));
}

}  // namespace

TEST_CASE("raster: perpendicular plane gives D / cos(atan t_i)", "[gl][raster]") {
  const auto d = scanner(512);
  for (const double dist : {100.0, 300.0, 500.0}) {
    for (const bool moved : {false, true}) {
      INFO("D = " << dist << (moved ? ", sensor moved and rotated" : ", sensor at origin"));
      const vts::Pose pose = moved ? some_pose() : vts::Pose::Identity();
      const auto mesh =
          plane_in_sensor(pose, Vector3d(0, 0, dist), Eigen::Matrix3d::Identity(), 2.0 * dist);
      auto source = vts::make_raster_source(d, mesh);
      CHECK(source->kind() == "raster");
      CHECK(source->scanner().points == 512);
      vts::Profile p;
      source->scan(pose, p);
      CHECK(p.valid_count() == d.points);
      CHECK(p.world_from_sensor.isApprox(pose));
      std::vector<std::optional<double>> hits(d.points);
      for (int i = 0; i < d.points; ++i) {
        const double expected = dist / std::cos(std::atan(tan_i(d, i)));
        hits[i] = expected;
        CHECK(std::abs(p.y_mm[i] - dist * tan_i(d, i)) <= kTolMm);
      }
      check_profile(d, p, hits);
    }
  }
}

TEST_CASE("raster: plane tilted about sensor x and y", "[gl][raster]") {
  const auto d = scanner(512);
  struct Tilt {
    double about_x_deg, about_y_deg, dist_mm;
  };
  for (const Tilt tilt : {Tilt{25.0, 0.0, 250.0}, Tilt{-40.0, 0.0, 300.0},
                          Tilt{0.0, 35.0, 200.0}, Tilt{30.0, 50.0, 400.0},
                          Tilt{-15.0, -60.0, 150.0}}) {
    for (const bool moved : {false, true}) {
      INFO("tilt x " << tilt.about_x_deg << " deg, y " << tilt.about_y_deg << " deg, at "
                     << tilt.dist_mm << " mm" << (moved ? ", sensor moved" : ""));
      const vts::Pose pose = moved ? some_pose() : vts::Pose::Identity();
      const Eigen::Matrix3d rot = rot_x_deg(tilt.about_x_deg) * rot_y_deg(tilt.about_y_deg);
      const Vector3d point(0.0, 0.0, tilt.dist_mm);
      const auto mesh = plane_in_sensor(pose, point, rot, 4.0 * tilt.dist_mm, 6);
      auto source = vts::make_raster_source(d, mesh);
      vts::Profile p;
      source->scan(pose, p);
      const auto hits = plane_hits(d, point, rot.col(2));
      check_profile(d, p, hits);
      // Tilting about y alone turns the plane within the laser plane's normal
      // direction: every column still sees z = dist.
      if (tilt.about_x_deg == 0.0)
        for (int i = 0; i < d.points; ++i) CHECK(std::abs(p.z_mm[i] - tilt.dist_mm) <= kTolMm);
    }
  }
}

TEST_CASE("raster: nothing in view gives no valid column", "[gl][raster]") {
  const auto d = scanner(256);
  const vts::Pose pose = vts::Pose::Identity();
  const Eigen::Matrix3d flat = Eigen::Matrix3d::Identity();
  vts::Profile p;

  SECTION("empty mesh") {
    vts::make_raster_source(d, vts::Mesh{})->scan(pose, p);
    CHECK(p.valid_count() == 0);
  }
  SECTION("plane behind the laser") {
    vts::make_raster_source(d, plane_in_sensor(pose, Vector3d(0, 0, -300), flat, 2000.0))
        ->scan(pose, p);
    CHECK(p.valid_count() == 0);
  }
  SECTION("plate outside the fan") {
    // At z = 300 the fan reaches |y| = 300 tan 20 = 109 mm.
    vts::make_raster_source(d, plane_in_sensor(pose, Vector3d(0, 200, 300), flat, 50.0))
        ->scan(pose, p);
    CHECK(p.valid_count() == 0);
  }
  SECTION("plate beside the laser plane") {
    // Spans x in [20, 120]: the laser plane x = 0 never meets it.
    vts::make_raster_source(d, plane_in_sensor(pose, Vector3d(70, 0, 300), flat, 50.0))
        ->scan(pose, p);
    CHECK(p.valid_count() == 0);
  }
  SECTION("plane beyond the maximum hit distance") {
    vts::make_raster_source(d, plane_in_sensor(pose, Vector3d(0, 0, 1300), flat, 3000.0))
        ->scan(pose, p);
    CHECK(p.valid_count() == 0);
  }
  SECTION("plane beyond max range but within max hit") {
    vts::make_raster_source(d, plane_in_sensor(pose, Vector3d(0, 0, 1100), flat, 3000.0))
        ->scan(pose, p);
    CHECK(p.valid_count() == 0);
  }
  SECTION("plane nearer than min range") {
    vts::make_raster_source(d, plane_in_sensor(pose, Vector3d(0, 0, 10), flat, 100.0))
        ->scan(pose, p);
    CHECK(p.valid_count() == 0);
  }
  SECTION("too-near plane occludes a measurable one") {
    auto mesh = plane_in_sensor(pose, Vector3d(0, 0, 300), flat, 600.0);
    mesh.append(plane_in_sensor(pose, Vector3d(0, 0, 10), flat, 100.0));
    vts::make_raster_source(d, mesh)->scan(pose, p);
    CHECK(p.valid_count() == 0);
  }
  CHECK(p.size() == d.points);
}

TEST_CASE("raster: depth of field and max hit cut a tilted plane per column", "[gl][raster]") {
  // A plane tilted 60 deg about x through z = 900 runs from z ~ 640 at one end
  // of the line to beyond 1000 (and beyond max hit) at the other.
  auto d = scanner(512);
  d.max_hit_mm = 1100.0;
  const vts::Pose pose = vts::Pose::Identity();
  const Eigen::Matrix3d rot = rot_x_deg(-60.0);
  const Vector3d point(0.0, 0.0, 900.0);
  vts::Profile p;
  vts::make_raster_source(d, plane_in_sensor(pose, point, rot, 20000.0, 2))->scan(pose, p);
  const auto hits = plane_hits(d, point, rot.col(2));
  int expected_valid = 0;
  for (int i = 0; i < d.points; ++i) expected_valid += expect_valid(d, i, hits[i]) ? 1 : 0;
  // The cut must fall inside the line for this test to mean anything.
  REQUIRE(expected_valid > 50);
  REQUIRE(expected_valid < d.points - 50);
  check_profile(d, p, hits);
}

TEST_CASE("raster: nearest of overlapping surfaces wins", "[gl][raster]") {
  const auto d = scanner(512);
  const vts::Pose pose = vts::Pose::Identity();
  const Eigen::Matrix3d flat = Eigen::Matrix3d::Identity();

  SECTION("half-width plate in front of a full plane, either draw order") {
    // Plate at z = 200 covering y >= 20 mm, in front of a plane at z = 300.
    const auto back = plane_in_sensor(pose, Vector3d(0, 0, 300), flat, 600.0);
    const auto front = square(Vector3d(0, 20.0 + 250.0, 200), Vector3d::UnitX(),
                              Vector3d::UnitY(), 250.0);
    for (const bool front_first : {true, false}) {
      INFO((front_first ? "front drawn first" : "back drawn first"));
      vts::Mesh mesh = front_first ? front : back;
      mesh.append(front_first ? back : front);
      vts::Profile p;
      vts::make_raster_source(d, mesh)->scan(pose, p);
      std::vector<std::optional<double>> hits(d.points);
      int in_front = 0;
      for (int i = 0; i < d.points; ++i) {
        const double t = tan_i(d, i);
        // The plate's edge y = 20 at z = 200 is t = 0.1; skip columns whose
        // ray passes within 1/100 pixel of it.
        const double pixel = 2.0 * std::tan(20.0 * kPi / 180.0) / d.points;
        if (std::abs(t - 0.1) < 0.01 * pixel) continue;
        const bool front_hit = t > 0.1;
        in_front += front_hit ? 1 : 0;
        hits[i] = (front_hit ? 200.0 : 300.0) / ray_i(d, i).z();
      }
      REQUIRE(in_front > 100);
      for (int i = 0; i < d.points; ++i)
        if (!hits[i]) hits[i] = p.range_mm[i];  // skipped edge column
      check_profile(d, p, hits);
    }
  }

  SECTION("two crossing planes: per column the nearer") {
    // A plane at z = 300 and one tilted 30 deg about x through the same point
    // cross on the optical axis.
    const Vector3d point(0, 0, 300);
    const Eigen::Matrix3d tilted = rot_x_deg(30.0);
    auto mesh = plane_in_sensor(pose, point, flat, 800.0, 3);
    mesh.append(plane_in_sensor(pose, point, tilted, 800.0, 5));
    vts::Profile p;
    vts::make_raster_source(d, mesh)->scan(pose, p);
    const auto a = plane_hits(d, point, flat.col(2));
    const auto b = plane_hits(d, point, tilted.col(2));
    std::vector<std::optional<double>> hits(d.points);
    for (int i = 0; i < d.points; ++i) hits[i] = std::min(*a[i], *b[i]);
    check_profile(d, p, hits);
  }
}

TEST_CASE("raster: 16 / 256 / 512 / 4096 columns", "[gl][raster]") {
  for (const int n : {16, 256, 512, 4096}) {
    INFO("N = " << n);
    const auto d = scanner(n);
    const vts::Pose pose = some_pose();
    const Eigen::Matrix3d rot = rot_x_deg(20.0);
    const Vector3d point(0, 0, 320);
    vts::Profile p;
    vts::make_raster_source(d, plane_in_sensor(pose, point, rot, 1000.0))->scan(pose, p);
    REQUIRE(p.size() == n);
    CHECK(p.valid_count() == n);
    check_profile(d, p, plane_hits(d, point, rot.col(2)));
  }
}

TEST_CASE("raster: a reused source matches fresh ones", "[gl][raster]") {
  const auto d = scanner(512);
  // A V-groove (two plates at +-45 deg meeting at z = 300) above a base plane.
  vts::Mesh mesh;
  mesh.append(square(Vector3d(0, -50, 250), Vector3d::UnitX(),
                     Vector3d(0, 1, 1).normalized(), 70.0, 8));
  mesh.append(square(Vector3d(0, 50, 250), Vector3d::UnitX(),
                     Vector3d(0, 1, -1).normalized(), 70.0, 8));
  mesh.append(square(Vector3d(0, 0, 340), Vector3d::UnitX(), Vector3d::UnitY(), 400.0, 3));

  std::vector<vts::Pose> poses;
  for (int k = 0; k < 24; ++k)
    poses.push_back(vts::pose_from_xyz_rpy(Vector3d(-60.0 + 5.0 * k, 3.0 * std::sin(k), 0.0),
                                           Vector3d(4.0 * std::cos(k), 2.0 * std::sin(0.7 * k),
                                                    10.0 * k)));

  auto reused = vts::make_raster_source(d, mesh);
  vts::Profile p;
  p.resize(7);  // wrong size on purpose: scan() must fix it
  int total_valid = 0;
  for (int pass = 0; pass < 2; ++pass)
    for (std::size_t k = 0; k < poses.size(); ++k) {
      INFO("pass " << pass << ", pose " << k);
      reused->scan(poses[k], p);
      vts::Profile fresh;
      vts::make_raster_source(d, mesh)->scan(poses[k], fresh);
      REQUIRE(p.size() == d.points);
      CHECK(p.world_from_sensor.isApprox(poses[k]));
      CHECK(p.valid == fresh.valid);
      CHECK(p.range_mm == fresh.range_mm);
      CHECK(p.y_mm == fresh.y_mm);
      CHECK(p.z_mm == fresh.z_mm);
      total_valid += p.valid_count();
    }
  CHECK(total_valid > 0);

  SECTION("scan_batch gives the same profiles") {
    std::vector<vts::Profile> batch(poses.size());
    reused->scan_batch(poses, batch);
    for (std::size_t k = 0; k < poses.size(); ++k) {
      vts::Profile single;
      reused->scan(poses[k], single);
      CHECK(batch[k].range_mm == single.range_mm);
      CHECK(batch[k].valid == single.valid);
    }
  }
}

TEST_CASE("raster: two live sources interleave", "[gl][raster]") {
  const auto d = scanner(128);
  const vts::Pose pose = vts::Pose::Identity();
  const Eigen::Matrix3d flat = Eigen::Matrix3d::Identity();
  auto near = vts::make_raster_source(d, plane_in_sensor(pose, Vector3d(0, 0, 150), flat, 500.0));
  auto far = vts::make_raster_source(d, plane_in_sensor(pose, Vector3d(0, 0, 450), flat, 900.0));
  vts::Profile a, b;
  for (int k = 0; k < 3; ++k) {
    near->scan(pose, a);
    far->scan(pose, b);
    for (int i = 0; i < d.points; ++i) {
      CHECK(std::abs(a.z_mm[i] - 150.0) <= kTolMm);
      CHECK(std::abs(b.z_mm[i] - 450.0) <= kTolMm);
    }
  }
}

TEST_CASE("raster: sources built on one thread scan on others", "[gl][raster]") {
  const auto d = scanner(256);
  const Eigen::Matrix3d rot = rot_x_deg(15.0);
  std::vector<vts::Pose> poses;
  for (int k = 0; k < 40; ++k)
    poses.push_back(vts::pose_from_xyz_rpy(Vector3d(2.0 * k, 0.0, 0.0), Vector3d(0.0, 0.0, 0.0)));
  // Two plane distances, one source each; expected values worked out here.
  const double dists[2] = {180.0, 420.0};
  std::unique_ptr<vts::ProfileSource> sources[2];
  for (int s = 0; s < 2; ++s)
    sources[s] = vts::make_raster_source(
        d, plane_in_sensor(vts::Pose::Identity(), Vector3d(0, 0, dists[s]), rot, 3000.0));
  std::vector<vts::Profile> out[2];
  std::thread workers[2];
  for (int s = 0; s < 2; ++s) {
    out[s].resize(poses.size());
    workers[s] = std::thread([&, s] { sources[s]->scan_batch(poses, out[s]); });
  }
  for (auto& w : workers) w.join();
  for (int s = 0; s < 2; ++s)
    for (std::size_t k = 0; k < poses.size(); ++k) {
      INFO("source " << s << ", pose " << k);
      // Moving along x (in the plane's tilt axis) does not change the slice.
      check_profile(d, out[s][k], plane_hits(d, Vector3d(0, 0, dists[s]), rot.col(2)));
    }
}

TEST_CASE("raster: bad input is rejected where it enters", "[gl][raster]") {
  auto d = scanner(8);
  CHECK_THROWS_AS(vts::make_raster_source(d, vts::Mesh{}), std::invalid_argument);
  d = scanner(64);
  vts::Mesh mesh;
  mesh.vertices = {Eigen::Vector3f(0, 0, 100), Eigen::Vector3f(1, 0, 100)};
  mesh.triangles = {{0, 1, 2}};
  CHECK_THROWS_AS(vts::make_raster_source(d, mesh), std::invalid_argument);
  // Zero-area triangles are skipped, not drawn.
  mesh.vertices.push_back(Eigen::Vector3f(2, 0, 100));
  vts::Profile p;
  vts::make_raster_source(d, mesh)->scan(vts::Pose::Identity(), p);
  CHECK(p.valid_count() == 0);
}
