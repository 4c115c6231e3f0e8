// Lines in normal form and their total least-squares fit.
#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>
#include <vector>

#include "tracker/geometry.h"

using vts::tracker::Line;
using vts::tracker::Vec2;
namespace tk = vts::tracker;

TEST_CASE("fit_line: a vertical wall", "[tracker][geometry]") {
  std::vector<Vec2> pts;
  for (int i = 0; i < 20; ++i) pts.emplace_back(3.5, 90.0 + 0.25 * i);
  const auto f = tk::fit_line(pts);
  REQUIRE(f);
  CHECK(std::abs(f->line.n.x()) == Approx(1.0).margin(1e-12));
  CHECK(std::abs(f->line.n.y()) == Approx(0.0).margin(1e-12));
  CHECK(f->line.distance(Vec2(3.5, 200.0)) == Approx(0.0).margin(1e-9));
  CHECK(f->line.distance(Vec2(4.5, 0.0)) == Approx(1.0).margin(1e-9));
  CHECK(f->rms_mm == Approx(0.0).margin(1e-9));
  CHECK(f->count == 20);
}

TEST_CASE("fit_line: horizontal and tilted lines, rms of known scatter", "[tracker][geometry]") {
  // Pairs of points 0.1 mm either side of z = 50.
  std::vector<Vec2> flat;
  for (int i = 0; i < 10; ++i) {
    flat.emplace_back(i, 50.1);
    flat.emplace_back(i, 49.9);
  }
  const auto f = tk::fit_line(flat);
  REQUIRE(f);
  CHECK(std::abs(f->line.n.y()) == Approx(1.0).margin(1e-12));
  CHECK(f->rms_mm == Approx(0.1).margin(1e-9));  // every point 0.1 off z = 50

  // 30 degrees through (1, 2).
  std::vector<Vec2> tilted;
  const Vec2 d(std::cos(std::numbers::pi / 6), std::sin(std::numbers::pi / 6));
  for (int i = -5; i <= 5; ++i) tilted.push_back(Vec2(1.0, 2.0) + 0.7 * i * d);
  const auto g = tk::fit_line(tilted);
  REQUIRE(g);
  CHECK(std::abs(g->line.direction().dot(d)) == Approx(1.0).margin(1e-12));
  CHECK(g->line.distance(Vec2(1.0, 2.0)) == Approx(0.0).margin(1e-12));
}

TEST_CASE("fit_line: degenerate input", "[tracker][geometry]") {
  CHECK_FALSE(tk::fit_line(std::vector<Vec2>{}));
  CHECK_FALSE(tk::fit_line(std::vector<Vec2>{Vec2(1, 2)}));
  CHECK_FALSE(tk::fit_line(std::vector<Vec2>{Vec2(1, 2), Vec2(1, 2), Vec2(1, 2)}));
}

TEST_CASE("intersect: lines meet where expected and parallel lines do not", "[tracker][geometry]") {
  Line vertical{Vec2(1, 0), 2.0};   // y = 2
  Line horizontal{Vec2(0, -1), -100.0};  // z = 100
  const auto x = tk::intersect(vertical, horizontal);
  REQUIRE(x);
  CHECK(x->x() == Approx(2.0));
  CHECK(x->y() == Approx(100.0));
  Line parallel{Vec2(1, 0), 5.0};
  CHECK_FALSE(tk::intersect(vertical, parallel));
  CHECK(tk::acute_angle_deg(vertical, horizontal) == Approx(90.0));
  CHECK(tk::angle_between_deg(Vec2(1, 0), Vec2(-1, 0)) == Approx(180.0));
}

TEST_CASE("Line::orient_towards puts the point on the positive side", "[tracker][geometry]") {
  Line l{Vec2(0, 1), 100.0};  // z = 100, normal +z
  l.orient_towards(Vec2::Zero());
  CHECK(l.n.y() == Approx(-1.0));
  CHECK(l.signed_distance(Vec2::Zero()) > 0.0);
  CHECK(l.signed_distance(Vec2(0, 101)) == Approx(-1.0));  // behind the surface
}
