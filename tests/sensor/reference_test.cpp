#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>
#include <vector>

#include "sensor/mesh.h"
#include "sensor/pose.h"
#include "sensor/ray_scene.h"
#include "sensor/reference_source.h"

namespace {

using vts::Mesh;
using vts::Pose;
using vts::Profile;
using vts::ScannerDesc;
using vts::Vec3;

// Column tangent worked out here, independently of sensor/rays.cpp.
double tan_of(const ScannerDesc& d, int i) {
  return std::tan(0.5 * d.fan_deg * std::numbers::pi / 180.0) *
         (2.0 * (i + 0.5) / d.points - 1.0);
}

// Appends the quad a-b-c-d (world, mm) as two triangles.
void add_quad(Mesh& m, const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  const auto base = static_cast<std::uint32_t>(m.vertices.size());
  for (const Vec3* v : {&a, &b, &c, &d}) m.vertices.push_back(v->cast<float>());
  m.triangles.push_back({base, base + 1, base + 2});
  m.triangles.push_back({base, base + 2, base + 3});
}

// The square |x|, |y| <= half in the sensor plane z = d, mapped to the world.
Mesh plane_at(double d, const Pose& world_from_sensor = Pose::Identity(), double half = 2000.0) {
  Mesh m;
  const Pose& p = world_from_sensor;
  add_quad(m, p * Vec3(-half, -half, d), p * Vec3(half, -half, d), p * Vec3(half, half, d),
           p * Vec3(-half, half, d));
  return m;
}

void check_plane(const ScannerDesc& desc, const Profile& prof, double d) {
  REQUIRE(prof.size() == desc.points);
  for (int i = 0; i < desc.points; ++i) {
    const double t = tan_of(desc, i);
    INFO("D = " << d << ", column " << i);
    REQUIRE(prof.valid[i] == 1);
    CHECK(prof.range_mm[i] == Approx(d * std::sqrt(1.0 + t * t)).margin(1e-3).epsilon(0));
    CHECK(prof.y_mm[i] == Approx(d * t).margin(1e-3).epsilon(0));
    CHECK(prof.z_mm[i] == Approx(d).margin(1e-3).epsilon(0));
  }
}

}  // namespace

TEST_CASE("reference: plane perpendicular to the optical axis", "[reference]") {
  ScannerDesc desc;
  desc.points = 512;
  desc.fan_deg = 40.0;
  for (double d : {100.0, 300.0}) {
    auto src = vts::make_reference_source(desc, plane_at(d));
    CHECK(src->kind() == "reference");
    CHECK(src->scanner().points == 512);
    Profile prof;
    src->scan(Pose::Identity(), prof);
    check_plane(desc, prof, d);
  }
}

TEST_CASE("reference: the pose moves and turns the rays", "[reference]") {
  ScannerDesc desc;
  desc.points = 200;
  desc.fan_deg = 60.0;
  const Pose world_from_sensor = vts::pose_from_xyz_rpy(Vec3(120.0, -40.0, 350.0),
                                                        Vec3(170.0, 20.0, -35.0));
  const double d = 250.0;
  auto src = vts::make_reference_source(desc, plane_at(d, world_from_sensor));
  Profile prof;
  src->scan(world_from_sensor, prof);
  check_plane(desc, prof, d);
  CHECK(prof.world_from_sensor.isApprox(world_from_sensor, 0.0));
}

TEST_CASE("reference: tilted plane", "[reference]") {
  ScannerDesc desc;
  desc.points = 333;
  desc.fan_deg = 50.0;
  // Plane through p0 with normal n (sensor frame = world frame here).
  const Vec3 p0(5.0, 10.0, 200.0);
  const Vec3 n = Vec3(0.3, 0.5, 1.0).normalized();
  Mesh mesh;
  const Vec3 u = n.cross(Vec3::UnitX()).normalized(), v = n.cross(u);
  const double h = 3000.0;
  add_quad(mesh, p0 - h * u - h * v, p0 + h * u - h * v, p0 + h * u + h * v, p0 - h * u + h * v);
  auto src = vts::make_reference_source(desc, mesh);
  Profile prof;
  src->scan(Pose::Identity(), prof);
  for (int i = 0; i < desc.points; ++i) {
    const Vec3 dir = Vec3(0.0, tan_of(desc, i), 1.0).normalized();
    const double s = n.dot(p0) / n.dot(dir);
    INFO("column " << i << ", expected range " << s);
    REQUIRE(prof.valid[i] == 1);
    CHECK(prof.range_mm[i] == Approx(s).margin(1e-3).epsilon(0));
    CHECK(prof.y_mm[i] == Approx(s * dir.y()).margin(1e-3).epsilon(0));
    CHECK(prof.z_mm[i] == Approx(s * dir.z()).margin(1e-3).epsilon(0));
  }
}

TEST_CASE("reference: nothing to measure gives invalid columns", "[reference]") {
  ScannerDesc desc;  // max_hit 1200, depth of field 20..1000
  Profile prof;

  SECTION("empty scene") {
    auto src = vts::make_reference_source(desc, Mesh{});
    src->scan(Pose::Identity(), prof);
  }
  SECTION("plane beyond the depth of field") {
    auto src = vts::make_reference_source(desc, plane_at(1100.0));
    src->scan(Pose::Identity(), prof);
  }
  SECTION("plane nearer than the depth of field") {
    auto src = vts::make_reference_source(desc, plane_at(10.0));
    src->scan(Pose::Identity(), prof);
  }
  SECTION("plane beyond the maximum hit distance") {
    desc.max_hit_mm = 250.0;
    auto src = vts::make_reference_source(desc, plane_at(300.0));
    src->scan(Pose::Identity(), prof);
  }
  SECTION("plane behind the laser") {
    auto src = vts::make_reference_source(desc, plane_at(-300.0));
    src->scan(Pose::Identity(), prof);
  }
  REQUIRE(prof.size() == desc.points);
  CHECK(prof.valid_count() == 0);
  for (int i = 0; i < prof.size(); ++i) {
    INFO("column " << i);
    REQUIRE(prof.range_mm[i] == 0.0f);
    REQUIRE(prof.y_mm[i] == 0.0f);
    REQUIRE(prof.z_mm[i] == 0.0f);
  }
}

TEST_CASE("reference: maximum hit distance cuts the outer columns", "[reference]") {
  ScannerDesc desc;
  desc.fan_deg = 60.0;
  desc.max_hit_mm = 320.0;
  const double d = 300.0;
  auto src = vts::make_reference_source(desc, plane_at(d));
  Profile prof;
  src->scan(Pose::Identity(), prof);
  int inside = 0, outside = 0;
  for (int i = 0; i < desc.points; ++i) {
    const double t = tan_of(desc, i);
    const double range = d * std::sqrt(1.0 + t * t);
    if (std::abs(range - desc.max_hit_mm) < 0.01) continue;  // too close to call
    INFO("column " << i << ", range " << range);
    CHECK(prof.valid[i] == (range < desc.max_hit_mm ? 1 : 0));
    (range < desc.max_hit_mm ? inside : outside)++;
  }
  CHECK(inside > 0);
  CHECK(outside > 0);
}

TEST_CASE("reference: laser plane along a row of mesh edges misses nothing", "[reference]") {
  // The sensor looks straight down at the plate z = 0 from 250 mm; the plate
  // is cut into 10 x 5 mm quads whose edges run along the laser line, so one
  // row of edges lies in the laser plane and every ray grazes a shared edge.
  // Without RTC_SCENE_FLAG_ROBUST Embree drops 40-80 of 512 such rays.
  const double h = 250.0;
  for (int points : {512, 1000}) {
    for (double yaw : {0.0, 17.0, 45.0}) {
      const Pose world_from_sensor =
          vts::pose_from_xyz_rpy(Vec3(13.7, -20.3, h), Vec3(180.0, 0.0, yaw));
      const Vec3 normal = world_from_sensor.linear().col(0);  // of the laser plane
      const Vec3 along = normal.cross(Vec3::UnitZ()).normalized();
      const Vec3 across = Vec3::UnitZ().cross(along);
      const Vec3 p0(world_from_sensor.translation().x(), world_from_sensor.translation().y(), 0.0);
      Mesh mesh;
      for (int i = -5; i < 5; ++i)
        for (int j = -100; j < 100; ++j) {
          const Vec3 a = p0 + 10.0 * i * across + 5.0 * j * along;
          add_quad(mesh, a, a + 10.0 * across, a + 10.0 * across + 5.0 * along, a + 5.0 * along);
        }
      ScannerDesc desc;
      desc.points = points;
      auto src = vts::make_reference_source(desc, mesh);
      Profile prof;
      src->scan(world_from_sensor, prof);
      INFO("points " << points << ", yaw " << yaw);
      CHECK(prof.valid_count() == points);
      check_plane(desc, prof, h);
    }
  }
}

TEST_CASE("reference: batch equals single scans and reuses the profile", "[reference]") {
  ScannerDesc desc;
  desc.points = 256;
  Mesh mesh = plane_at(300.0);
  mesh.append(plane_at(150.0, Pose::Identity(), 30.0));  // a small plate in front
  auto src = vts::make_reference_source(desc, mesh);

  std::vector<Pose> poses;
  for (int k = 0; k < 300; ++k)
    poses.push_back(vts::pose_from_xyz_rpy(Vec3(0.2 * k - 30.0, 0.0, 0.0),
                                           Vec3(0.0, 0.0, 0.5 * k)));
  std::vector<Profile> batch(poses.size());
  src->scan_batch(poses, batch);

  Profile one;
  src->scan(poses[0], one);
  const float* data = one.range_mm.data();
  for (std::size_t k = 0; k < poses.size(); ++k) {
    src->scan(poses[k], one);
    INFO("pose " << k);
    REQUIRE(one.range_mm == batch[k].range_mm);
    REQUIRE(one.valid == batch[k].valid);
  }
  CHECK(one.range_mm.data() == data);  // no reallocation after the first profile
  CHECK(batch[0].valid_count() > 0);
}

TEST_CASE("reference: bad input is rejected", "[reference]") {
  ScannerDesc desc;
  Mesh mesh = plane_at(100.0);
  mesh.triangles.push_back({0, 1, 99});
  CHECK_THROWS_WITH(vts::make_reference_source(desc, mesh),
                    Catch::Contains("triangle 2") && Catch::Contains("vertex 99"));
  desc.points = 8;
  CHECK_THROWS_WITH(vts::make_reference_source(desc, Mesh{}), Catch::Contains("points = 8"));
}

TEST_CASE("reference: a moving part is scanned where move_part puts it, with its normals turned", "[reference]") {
  ScannerDesc desc;
  desc.points = 128;
  desc.fan_deg = 40.0;
  // The fixed part: a plane 400 mm away. The moving part: a plane 100 mm
  // away, as given (sensor at the identity).
  const Mesh fixed = plane_at(400.0);
  const Mesh moving = plane_at(100.0, Pose::Identity(), 300.0);
  auto src = vts::make_reference_source(desc, fixed, 1, &moving);
  Profile prof;
  src->scan(Pose::Identity(), prof);
  check_plane(desc, prof, 100.0);

  // Moved 150 mm further away: seen at 250 mm.
  Pose away = Pose::Identity();
  away.translation() = Vec3(0.0, 0.0, 150.0);
  src->move_part(away);
  src->scan(Pose::Identity(), prof);
  check_plane(desc, prof, 250.0);

  // Turned and moved with the sensor (the motion is the sensor's pose): the
  // plane lies 100 mm in front of the sensor again, and the incidence is
  // that of a plane square to the optical axis only if the hit's normal is
  // turned into the world (Embree reports it in the instanced mesh's frame).
  const Pose w = vts::pose_from_xyz_rpy(Vec3(120.0, -40.0, 350.0), Vec3(170.0, 20.0, -35.0));
  src->move_part(w);
  src->scan(w, prof);
  check_plane(desc, prof, 100.0);
  for (int i = 0; i < desc.points; ++i) {
    const double t = tan_of(desc, i);
    INFO("column " << i);
    CHECK(prof.cos_incidence[i] == Approx(1.0 / std::sqrt(1.0 + t * t)).margin(1e-5));
  }

  // Moved out of the fan: the fixed plane behind it.
  Pose gone = Pose::Identity();
  gone.translation() = Vec3(5000.0, 0.0, 0.0);
  src->move_part(gone);
  src->scan(Pose::Identity(), prof);
  check_plane(desc, prof, 400.0);

  // A source without a moving part refuses to move one.
  auto rigid = vts::make_reference_source(desc, fixed);
  CHECK_THROWS_AS(rigid->move_part(away), std::logic_error);
}

TEST_CASE("ray scene: a turned moving part's hits have world normals, single rays and 8 at a time", "[reference]") {
  // The moving part: the plane z = 100 (normal +-z as given), turned by w.
  const Pose w = vts::pose_from_xyz_rpy(Vec3(10.0, -20.0, 30.0), Vec3(25.0, -40.0, 60.0));
  vts::RayScene scene(Mesh{}, plane_at(100.0, Pose::Identity(), 300.0), "test");
  scene.move_part(w);
  const Vec3 n_world = w.linear() * Vec3::UnitZ();
  std::vector<vts::RayScene::Segment> rays;
  for (int k = 0; k < 11; ++k) {
    // From the sensor at w, fanned in its x-z plane, towards the plane.
    const Vec3 d = w.linear() * Vec3(0.05 * (k - 5), 0.0, 1.0).normalized();
    rays.push_back({w.translation().cast<float>(), d.cast<float>(), 0.0f, 1000.0f});
  }
  std::vector<vts::RayScene::Hit> hits(rays.size());
  std::vector<unsigned char> found(rays.size());
  scene.intersect(rays.data(), rays.size(), hits.data(), found.data());
  for (std::size_t k = 0; k < rays.size(); ++k) {
    INFO("ray " << k);
    vts::RayScene::Hit one;
    REQUIRE(scene.intersect(rays[k].o, rays[k].d, rays[k].tnear, rays[k].tfar, one));
    REQUIRE(found[k] == 1);
    const double cos_k = rays[k].d.cast<double>().dot(n_world);
    CHECK(one.t == Approx(100.0 / cos_k).margin(1e-3));
    CHECK(hits[k].t == one.t);
    // Facing the ray's origin: -n_world.
    CHECK((one.normal.cast<double>() + n_world).norm() < 1e-5);
    CHECK((hits[k].normal.cast<double>() + n_world).norm() < 1e-5);
  }
}
