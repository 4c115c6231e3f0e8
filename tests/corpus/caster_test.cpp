// The corpus' own 2D ray caster: distances, vertices, camera shadow, noise.
#include <catch2/catch.hpp>

#include "corpus.h"
#include "dmath.h"
#include "random.h"

#include <cmath>
#include <numbers>
#include <vector>

namespace vc = vts_corpus;
using vc::Vec2;

namespace {

vc::Polygon box(double y0, double z0, double y1, double z1, int face = vc::kFaceOther) {
  vc::Polygon p;
  p.pts = {{y0, z0}, {y1, z0}, {y1, z1}, {y0, z1}};
  p.faces.assign(4, face);
  return p;
}

vc::Sensor sensor(int columns, double fan_deg, bool tangent) {
  vc::Sensor s;
  s.columns = columns;
  s.fan_deg = fan_deg;
  s.tangent_spacing = tangent;
  s.camera_yz = Vec2(60, 0);
  return s;
}

}  // namespace

TEST_CASE("caster: a flat plate at a known distance gives the range d/cos of each ray", "[corpus][caster]") {
  for (const bool tangent : {true, false}) {
    const double d = 137.25;
    vc::Scene scene;
    scene.add(box(-1000, d, 1000, d + 8, vc::kFaceTop1));
    vc::Sensor s = sensor(701, 44, tangent);
    s.camera_yz = Vec2(0.0, 0.0);  // straight above: nothing shadows a flat plate
    const vc::Profile p = vc::render_scene(scene, s, 0.0, 1);
    REQUIRE(p.y.size() == 701u);
    for (std::size_t i = 0; i < p.y.size(); ++i) {
      const Vec2 dir = p.debug->ray_dir[i];
      REQUIRE(p.valid[i] == 1);
      CHECK(p.debug->ideal_range_mm[i] == Approx(d / dir.y()).epsilon(1e-13));
      CHECK(std::abs(p.z[i] - d) < 2e-5);  // float
      CHECK(std::abs(p.y[i] - d * dir.x() / dir.y()) < 2e-5);
      CHECK(p.debug->hit_face[i] == vc::kFaceTop1);
    }
    // Scan order: y increases with the column; the fan is symmetric.
    CHECK(p.y.front() < 0);
    CHECK(p.y.back() == Approx(-p.y.front()).epsilon(1e-6));
    CHECK(std::atan2(p.y.back(), p.z.back()) == Approx(vc::dm::deg_to_rad(22)).epsilon(1e-6));
  }
}

TEST_CASE("caster: rays through vertices do not slip through", "[corpus][caster]") {
  // A saw-tooth surface whose every vertex lies on a column's ray (as exactly as
  // floating point puts it there): each ray meets the surface at a vertex,
  // between two edges, and must hit it.
  for (const bool tangent : {true, false}) {
    for (std::uint64_t seed = 1; seed <= 40; ++seed) {
      vc::Rng rng(seed);
      const vc::Sensor s = sensor(257 + static_cast<int>(seed) * 13, 30 + seed % 20, tangent);
      const std::vector<Vec2> dirs = vc::column_directions(s);
      vc::Polygon saw;
      const int step = 1 + static_cast<int>(seed % 3);  // a vertex on every 1st, 2nd or 3rd ray
      for (int i = 0; i < s.columns; i += step) saw.pts.push_back(rng.uniform(80, 120) * dirs[i]);
      if ((s.columns - 1) % step) saw.pts.push_back(rng.uniform(80, 120) * dirs.back());
      // Closed far behind, outside the fan (a simple polygon).
      const double u_last = dirs.back().x() / dirs.back().y(), u_first = dirs.front().x() / dirs.front().y();
      saw.pts.push_back(Vec2((u_last + 0.2) * 400, 400));
      saw.pts.push_back(Vec2((u_first - 0.2) * 400, 400));
      saw.faces.assign(saw.pts.size(), vc::kFaceTop1);
      vc::Scene scene;
      scene.add(saw);
      vc::Sensor open = s;
      open.camera_yz = Vec2(0, 0);
      const vc::Profile p = vc::render_scene(scene, open, 0.0, seed);
      for (int i = 0; i < s.columns; ++i) {
        INFO("seed " << seed << " column " << i);
        REQUIRE(p.debug->status[i] != vc::kNoHit);
        // The indexed caster finds what testing every edge finds (at a vertex
        // through either edge: the last bits may differ).
        const double brute = vc::nearest_hit_bruteforce(scene, Vec2(0, 0), dirs[i], 1e-9, nullptr);
        CHECK(p.debug->ideal_range_mm[i] == Approx(brute).epsilon(1e-12));
        if (i % step == 0) CHECK(p.debug->ideal_range_mm[i] == Approx(saw.pts[i / step].norm()).epsilon(1e-12));
      }
    }
  }
}

TEST_CASE("caster: a ray through the vertex where two solids touch hits them", "[corpus][caster]") {
  // Two triangles meeting at one vertex on a column's ray, one on either side
  // of the ray and behind the vertex: the ray meets the surface at the vertex
  // and must not pass between them. Also a diamond with its tip on the ray.
  const vc::Sensor s = sensor(101, 40, true);
  const std::vector<Vec2> dirs = vc::column_directions(s);
  auto rotated = [](const Vec2& v, double deg) {
    const double a = deg * std::numbers::pi / 180;
    return Vec2(std::cos(a) * v.x() - std::sin(a) * v.y(), std::sin(a) * v.x() + std::cos(a) * v.y());
  };
  for (int i = 0; i < s.columns; ++i) {
    const Vec2 d = dirs[i], c = (70.0 + i) * d;
    vc::Polygon left, right, diamond;
    left.pts = {c, c + 20 * rotated(d, 10), c + 20 * rotated(d, 35)};
    right.pts = {c, c + 20 * rotated(d, -35), c + 20 * rotated(d, -10)};
    left.faces.assign(3, vc::kFaceTop1);
    right.faces.assign(3, vc::kFaceTop2);
    diamond.pts = {c, c + 5 * rotated(d, -45), c + 5 * std::sqrt(2.0) * d, c + 5 * rotated(d, 45)};
    diamond.faces.assign(4, vc::kFaceTop1);
    for (int which = 0; which < 2; ++which) {
      vc::Scene scene;
      if (which == 0) {
        scene.add(left);
        scene.add(right);
      } else {
        scene.add(diamond);
      }
      vc::Sensor open = s;
      open.camera_yz = Vec2(0, 0);
      const vc::Profile p = vc::render_scene(scene, open, 0.0, 1);
      INFO("column " << i << (which ? " diamond" : " two triangles"));
      REQUIRE(p.debug->status[i] != vc::kNoHit);
      CHECK(p.debug->ideal_range_mm[i] == Approx(c.norm()).epsilon(1e-12));
      CHECK(vc::nearest_hit_bruteforce(scene, Vec2(0, 0), d, 1e-9, nullptr) == Approx(c.norm()).epsilon(1e-12));
    }
  }
}

TEST_CASE("caster: the indexed caster agrees with testing every edge on random scenes", "[corpus][caster]") {
  for (std::uint64_t seed = 1; seed <= 200; ++seed) {
    vc::Rng rng(seed);
    vc::Scene scene;
    for (int k = 0; k < 6; ++k) {  // random triangles and boxes in front of the sensor
      const Vec2 c(rng.uniform(-60, 60), rng.uniform(60, 160));
      if (rng.chance(0.5)) {
        scene.add(box(c.x(), c.y(), c.x() + rng.uniform(0.1, 30), c.y() + rng.uniform(0.1, 30)));
      } else {
        vc::Polygon tri;
        for (int v = 0; v < 3; ++v) tri.pts.push_back(c + Vec2(rng.uniform(-15, 15), rng.uniform(-15, 15)));
        tri.faces.assign(3, vc::kFaceOther);
        scene.add(tri);
      }
    }
    vc::Sensor s = sensor(300, 45, seed % 2 == 0);
    s.camera_yz = Vec2(rng.uniform(-80, 80), 0);
    const vc::Profile p = vc::render_scene(scene, s, 0.0, seed);
    const std::vector<Vec2> dirs = vc::column_directions(s);
    for (int i = 0; i < s.columns; ++i) {
      INFO("seed " << seed << " column " << i);
      int edge = -1;
      const double t = vc::nearest_hit_bruteforce(scene, Vec2(0, 0), dirs[i], 1e-9, &edge);
      if (edge < 0) {
        CHECK(p.debug->status[i] == vc::kNoHit);
        continue;
      }
      CHECK(p.debug->ideal_range_mm[i] == t);
      const bool blocked = vc::segment_blocker_bruteforce(scene, t * dirs[i], s.camera_yz) >= 0;
      CHECK((p.debug->status[i] == vc::kCameraShadow) == blocked);
    }
  }
}

TEST_CASE("caster: camera shadow appears where a wall stands between the hit and the camera", "[corpus][caster]") {
  // A floor at z = d and a wall [yw - w, yw] of height h standing on it; the
  // camera at (b, 0), b > yw. A floor point at yp < yw - w is hidden when the
  // sight line to the camera passes the wall's far face below its top:
  // d (yw - w - yp) / (b - yp) <= h.
  const double d = 120, h = 9, w = 2, yw = 10, b = 55;
  vc::Scene scene;
  scene.add(box(-500, d, 500, d + 10, vc::kFaceTop1));
  scene.add(box(yw - w, d - h, yw, d + 0.5, vc::kFaceEdge1));
  vc::Sensor s = sensor(1024, 40, true);
  s.camera_yz = Vec2(b, 0);
  const vc::Profile p = vc::render_scene(scene, s, 0.0, 1);
  int shadowed = 0, lit_far = 0;
  for (int i = 0; i < s.columns; ++i) {
    if (p.debug->hit_face[i] != vc::kFaceTop1) continue;
    const double yp = p.debug->ideal_range_mm[i] * p.debug->ray_dir[i].x();
    if (yp > yw) {
      CHECK(p.debug->status[i] == vc::kValid);  // the camera's side of the wall
      continue;
    }
    const double clearance = d * (yw - w - yp) / (b - yp) - h;  // < 0: hidden
    if (std::abs(clearance) < 1e-6) continue;
    INFO("column " << i << " y " << yp << " clearance " << clearance);
    if (clearance < 0) {
      CHECK(p.debug->status[i] == vc::kCameraShadow);
      CHECK(p.valid[i] == 0);
      CHECK(std::isnan(p.y[i]));
      ++shadowed;
    } else {
      CHECK(p.debug->status[i] == vc::kValid);
      ++lit_far;
    }
  }
  CHECK(shadowed > 20);  // the shadow is a run of columns, and there is floor beyond it
  CHECK(lit_far > 20);
}

TEST_CASE("caster: range noise of level sigma has sample RMS within 10 percent of sigma", "[corpus][caster]") {
  const double d = 150;
  vc::Scene scene;
  scene.add(box(-1000, d, 1000, d + 8));
  vc::Sensor s = sensor(2048, 40, false);
  s.camera_yz = Vec2(0, 0);
  for (double sigma : vc::kNoiseLevels_mm) {
    const vc::Profile p = vc::render_scene(scene, s, sigma, 42);
    double sum2 = 0, sum = 0;
    for (std::size_t i = 0; i < p.y.size(); ++i) {
      REQUIRE(p.valid[i] == 1);
      // Along the ray: measured range minus d / cos.
      const double r = std::hypot(double(p.y[i]), double(p.z[i])) - p.debug->ideal_range_mm[i];
      sum += r;
      sum2 += r * r;
    }
    const double n = static_cast<double>(p.y.size());
    const double rms = std::sqrt(sum2 / n);
    INFO("sigma " << sigma << " rms " << rms << " mean " << sum / n);
    if (sigma == 0) {
      CHECK(rms < 2e-5);  // float rounding only
    } else {
      CHECK(rms == Approx(sigma).epsilon(0.10));
      CHECK(std::abs(sum / n) < 4 * sigma / std::sqrt(n));
    }
  }
}

TEST_CASE("caster: rounded and chamfered corners stay tangent and inside the sharp corner", "[corpus][caster]") {
  for (auto kind : {vc::CornerKind::Round, vc::CornerKind::Chamfer}) {
    const vc::Polygon p = vc::make_polygon({{Vec2(0, 0), 1, vc::CornerKind::Sharp, 0},
                                            {Vec2(20, 0), 2, kind, 1.5},
                                            {Vec2(20, 10), 3, vc::CornerKind::Sharp, 0},
                                            {Vec2(0, 10), 4, vc::CornerKind::Sharp, 0}});
    // Every new vertex lies within the box and the corner (20, 0) is cut off.
    for (const Vec2& v : p.pts) {
      CHECK(v.x() >= -1e-12);
      CHECK(v.x() <= 20 + 1e-12);
      CHECK(v.y() >= -1e-12);
      CHECK(v.y() <= 10 + 1e-12);
      CHECK((v - Vec2(20, 0)).norm() > 0.5);
    }
    if (kind == vc::CornerKind::Round) {
      // Arc points are 1.5 mm from the centre (18.5, 1.5); segments of <= 6 degrees.
      int arc = 0;
      for (const Vec2& v : p.pts)
        if (v.x() > 18.4 && v.y() < 1.6) {
          CHECK((v - Vec2(18.5, 1.5)).norm() == Approx(1.5).epsilon(1e-12));
          ++arc;
        }
      CHECK(arc >= 16);  // 90 degrees / 6 + 1
    } else {
      CHECK(p.pts.size() == 5u);
    }
  }
  // A zero-length edge (a v-groove root face of 0 mm) is dropped.
  const vc::Polygon q = vc::make_polygon({{Vec2(0, 0), 1}, {Vec2(5, 0), 2}, {Vec2(5, 0), 3}, {Vec2(5, 5), 4}});
  CHECK(q.pts.size() == 3u);
  CHECK(q.faces[1] == 3);
}

TEST_CASE("caster: clipping keeps the part in front of the sensor", "[corpus][caster]") {
  const vc::Polygon c = vc::clipped_above(box(-5, -10, 5, 10, 7), 1.0);
  REQUIRE(c.pts.size() == 4u);
  for (const Vec2& v : c.pts) CHECK(v.y() >= 1.0);
  CHECK(vc::clipped_above(box(-5, -10, 5, -2), 1.0).pts.empty());
}

TEST_CASE("dmath: deterministic functions match libm to 1e-15", "[corpus][dmath]") {
  vc::Rng rng(7);
  for (int i = 0; i < 200000; ++i) {
    const double x = rng.uniform(-1, 1) * (i % 2 ? 8 : 9000);
    REQUIRE(std::abs(vc::dm::sin(x) - std::sin(x)) < 1e-15);
    REQUIRE(std::abs(vc::dm::cos(x) - std::cos(x)) < 1e-15);
    const double t = rng.uniform(-1.5, 1.5);
    REQUIRE(std::abs(vc::dm::tan(t) - std::tan(t)) < 1e-15 * std::max(1.0, std::abs(std::tan(t))));
    const double y = rng.uniform(-100, 100), z = rng.uniform(-100, 100);
    REQUIRE(std::abs(vc::dm::atan2(y, z) - std::atan2(y, z)) < 1e-15);
    const double c = rng.uniform(-1, 1);
    REQUIRE(std::abs(vc::dm::acos(c) - std::acos(c)) < 1e-15);
    const double l = rng.uniform(1e-6, 1e6);
    REQUIRE(std::abs(vc::dm::log(l) - std::log(l)) < 1e-15 * std::max(1.0, std::abs(std::log(l))));
  }
}

TEST_CASE("random: normals have unit variance and uniforms stay in range", "[corpus][random]") {
  vc::Rng rng(99);
  double s1 = 0, s2 = 0;
  const int n = 400000;
  for (int i = 0; i < n; ++i) {
    const double x = rng.normal();
    s1 += x;
    s2 += x * x;
    const double u = rng.uniform();
    REQUIRE(u >= 0.0);
    REQUIRE(u < 1.0);
    const int k = rng.uniform_int(-3, 5);
    REQUIRE(k >= -3);
    REQUIRE(k <= 5);
  }
  CHECK(std::abs(s1 / n) < 0.01);
  CHECK(s2 / n == Approx(1.0).epsilon(0.01));
}
