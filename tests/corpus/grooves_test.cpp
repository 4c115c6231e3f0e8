// The groove joints (docs/design/grooves.md, issue 18): truth worked out by
// hand for fixed shapes, ideal points on the exact section, the camera's
// occlusion in a deep narrow U, determinism, every variant.
#include <catch2/catch.hpp>

#include "corpus.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

namespace vc = vts_corpus;
using vc::Vec2;

namespace {

constexpr double kS = 300;  // the root's standoff in the hand-worked profiles

// Straight down at 300 mm, 2048 columns over 40 degrees. The camera at the
// laser (every lit point seen) unless a test moves it.
vc::Sensor straight_down(double camera_y = 0) {
  vc::Sensor s;
  s.columns = 2048;
  s.fan_deg = 40;
  s.camera_yz = Vec2(camera_y, 0);
  return s;
}

// Joint frame -> sensor frame of make_groove_profile: y kept, z = S - z.
Vec2 J(double y, double z) { return Vec2(y, kS - z); }

Vec2 bp(const vc::Truth& t, const char* name) {
  const auto* p = t.break_point(name);
  REQUIRE(p != nullptr);
  return Vec2((*p)[0], (*p)[1]);
}

void check_point(const Vec2& got, const Vec2& want, double tol = 1e-9) {
  INFO("got (" << got.x() << ", " << got.y() << "), want (" << want.x() << ", " << want.y() << ")");
  CHECK((got - want).norm() < tol);
}

// The exact section of a hand-worked groove, face by face (joint frame):
// lines through two points, circles, levels.
struct Exact {
  double top_a = 0, top_b = 0;        // the plate tops' z
  Vec2 wall_a[2], wall_b[2];          // two points on each wall's straight line
  Vec2 arc_a_c{0, 0}, arc_b_c{0, 0};  // arc centres (radius r_arc)
  double r_arc = 0;
  Vec2 cap_c{0, 0};  // the cap's circle
  double r_cap = 0;
};

double line_dist(const Vec2& q, const Vec2& p0, const Vec2& p1) {
  return std::abs(vc::cross((p1 - p0).normalized(), q - p0));
}

// Every valid point of an ideal hand-worked profile lies on the exact face it
// hit (the polygon's arcs are chords of at most 2 degrees: R (1 - cos 1 deg)).
void check_on_exact_section(const vc::Profile& p, const Exact& x) {
  const vc::Debug& d = *p.debug;
  int checked = 0;
  for (std::size_t i = 0; i < p.y.size(); ++i) {
    if (!p.valid[i]) continue;
    const Vec2 s = d.ideal_range_mm[i] * d.ray_dir[i];
    const Vec2 q(s.x(), kS - s.y());
    double err = 1e300;
    const double chord = x.r_arc * (1 - std::cos(std::numbers::pi / 180));
    switch (d.hit_face[i]) {
      case vc::kFaceTop1: err = std::abs(q.y() - x.top_a); break;
      case vc::kFaceTop2: err = std::abs(q.y() - x.top_b); break;
      case vc::kFaceBevel1: err = line_dist(q, x.wall_a[0], x.wall_a[1]); break;
      case vc::kFaceBevel2: err = line_dist(q, x.wall_b[0], x.wall_b[1]); break;
      case vc::kFaceArc1: err = std::abs((q - x.arc_a_c).norm() - x.r_arc) - chord; break;
      case vc::kFaceArc2: err = std::abs((q - x.arc_b_c).norm() - x.r_arc) - chord; break;
      case vc::kFaceCap:  // chords of at most 0.2 mm
        err = std::abs((q - x.cap_c).norm() - x.r_cap) - 0.2 * 0.2 / (8 * x.r_cap);
        break;
      default: break;
    }
    INFO("column " << i << " face " << vc::face_name(d.hit_face[i]) << " at (" << q.x() << ", " << q.y() << ")");
    CHECK(err < 1e-9);
    ++checked;
  }
  CHECK(checked > 1000);
}

// Truth worked out by hand, joint frame (J() maps it).
struct Expected {
  Vec2 b1, b2, b3, b4, b5, lowest;
  double depth, area, width, wall_a, wall_b, gap, mismatch;
  int passes;
};

void check_truth(const vc::Truth& t, const Expected& e) {
  check_point(bp(t, "B1"), J(e.b1.x(), e.b1.y()));
  check_point(bp(t, "B2"), J(e.b2.x(), e.b2.y()));
  check_point(bp(t, "B3"), J(e.b3.x(), e.b3.y()));
  check_point(bp(t, "B4"), J(e.b4.x(), e.b4.y()));
  check_point(bp(t, "B5"), J(e.b5.x(), e.b5.y()));
  check_point(Vec2(t.track_y_mm, t.track_z_mm), J(e.b3.x(), e.b3.y()));
  check_point(Vec2(t.fill_lowest_y_mm, t.fill_lowest_z_mm), J(e.lowest.x(), e.lowest.y()));
  CHECK(t.depth_mm == Approx(e.depth).margin(1e-9));
  CHECK(t.area_mm2 == Approx(e.area).margin(1e-6));
  CHECK(t.top_width_mm == Approx(e.width).margin(1e-9));
  CHECK(t.wall_angle_a_deg == Approx(e.wall_a).margin(1e-9));
  CHECK(t.wall_angle_b_deg == Approx(e.wall_b).margin(1e-9));
  CHECK(t.angle_deg == Approx(180 - e.wall_a - e.wall_b).margin(1e-9));
  CHECK(t.gap_mm == Approx(e.gap).margin(1e-12));
  CHECK(t.mismatch_mm == Approx(e.mismatch).margin(1e-12));
  CHECK(t.passes == e.passes);
}

vc::GrooveShape shape(vc::Joint joint, double thickness, double angle, double root_face, double gap, double radius = 0) {
  vc::GrooveShape g;
  g.joint = joint;
  g.thickness_mm = thickness;
  g.angle_deg = angle;
  g.root_face_mm = root_face;
  g.gap_mm = gap;
  g.radius_mm = radius;
  return g;
}

}  // namespace

TEST_CASE("grooves: a 60-degree V in 40 mm plate with 3 passes, truth worked by hand", "[corpus][grooves]") {
  // Root face 2, gap 2, 3 passes of 4 mm, crown 0.8 (joint frame, root edges
  // at (-1, 0) and (1, 0)):
  //   groove depth D = 40 - 2 = 38; each wall 30 deg from vertical, tan 30 = 0.577350.
  //   B1 = (-1 - 38 tan 30, 38) = (-22.939310, 38), B5 = (22.939310, 38).
  //   level h3 = 3 x 4 = 12: toes B2 = (-1 - 12 tan 30, 12) = (-7.928203, 12), B4 = (7.928203, 12).
  //   cap: chord c = 15.856406, sagitta 0.8: r = (c^2/4 + 0.8^2) / 1.6 = 39.685254,
  //        centre (0, 12.8 - r) = (0, -26.885254); B3 = its top (0, 12.8).
  //   lowest: a convex cap's toes tie at z = 12: side a's, B2; depth 38 - 12 = 26.
  //   area: trapezoid B1-B2-B4-B5 (45.878620 + 15.856406) / 2 x 26 = 802.555350
  //         minus the cap's segment r^2 (a - sin a cos a), sin a = (c/2)/r: 8.473946 -> 794.081404.
  //   wall angles 60 and 60, included 60, top width 45.878620.
  vc::GrooveShape g = shape(vc::Joint::VGrooveThick, 40, 60, 2, 2);
  g.passes = 3;
  g.layer_mm = 4;
  g.crown_mm = 0.8;
  const vc::Profile p = vc::make_groove_profile(g, straight_down(), kS);
  check_truth(p.truth, {{-22.939310229205777, 38}, {-7.928203230275509, 12}, {0, 12.8}, {7.928203230275509, 12},
                        {22.939310229205777, 38}, {-7.928203230275509, 12}, 26, 794.081403578771,
                        45.878620458411554, 60, 60, 2, 0, 3});
  const double t30 = std::tan(std::numbers::pi / 6);
  Exact x;
  x.top_a = x.top_b = 38;
  x.wall_a[0] = Vec2(-1, 0), x.wall_a[1] = Vec2(-1 - 38 * t30, 38);
  x.wall_b[0] = Vec2(1, 0), x.wall_b[1] = Vec2(1 + 38 * t30, 38);
  x.cap_c = Vec2(0, -26.88525403784438), x.r_cap = 39.68525403784438;
  check_on_exact_section(p, x);
}

TEST_CASE("grooves: an empty single bevel with mismatch, truth worked by hand", "[corpus][grooves]") {
  // 20 mm plate, root face 1.5, gap 2.5, 45 degrees, plate b raised 1 mm:
  //   D = 18.5; root edges Ra = (-1.25, 0), Rb = (1.25, 1); side a square,
  //   B1 = (-1.25, 18.5); side b at 45 deg from vertical, B5 = (1.25 + 18.5, 19.5) = (19.75, 19.5).
  //   Empty: toes = root edges; bottom = the segment Ra-Rb; B3 midway in y: (0, 0.5).
  //   The top line B1-B5 rises 1 in 21: Ra is 18.479061 below it, Rb 17.599105: lowest Ra, depth 18.479061.
  //   area B1-Ra-Rb-B5 (shoelace) 208.125; wall angles 90 and 45, included 45;
  //   top width sqrt(21^2 + 1) = 21.023796; mismatch +1 (b's top above a's); gap 2.5.
  vc::GrooveShape g = shape(vc::Joint::Bevel, 20, 45, 1.5, 2.5);
  g.mismatch_mm = 1;
  const vc::Profile p = vc::make_groove_profile(g, straight_down(), kS);
  check_truth(p.truth, {{-1.25, 18.5}, {-1.25, 0}, {0, 0.5}, {1.25, 1}, {19.75, 19.5}, {-1.25, 0}, 18.479060547902094,
                        208.125, 21.023796041628636, 90, 45, 2.5, 1, 0});
  Exact x;
  x.top_a = 18.5, x.top_b = 19.5;
  x.wall_a[0] = Vec2(-1.25, 0), x.wall_a[1] = Vec2(-1.25, 18.5);
  x.wall_b[0] = Vec2(1.25, 1), x.wall_b[1] = Vec2(19.75, 19.5);
  check_on_exact_section(p, x);
}

TEST_CASE("grooves: an empty U 35 mm deep, truth worked by hand", "[corpus][grooves]") {
  // D = 35 (no root face), no gap, radius 7, included 18 (each wall 9 deg from vertical):
  //   arc centres (0, 7) (both: the root edges meet at (0, 0)); the tangent points at
  //   height 7 (1 - sin 9) = 5.904959, 7 cos 9 = 6.913818 out: B2 = (-6.913818, 5.904959), B4 mirrored.
  //   B1 = -(6.913818 + (35 - 5.904959) tan 9) = -11.522020: top width 23.044040.
  //   B3 = the bottom below the middle: (0, 0); lowest (0, 0), depth 35.
  //   area: trapezoid B1-B2-B4-B5 (23.044040 + 13.827637) / 2 x 29.095041 = 536.391484, plus
  //         below the chord B2-B4 and above the arcs 2 [(h - 7) x + (x sqrt(49 - x^2) + 49 asin(x/7)) / 2]
  //         at x = 6.913818, h = 5.904959: 61.701202 -> 598.092686.
  //   wall angles 81 and 81, included 18.
  const vc::Profile p = vc::make_groove_profile(shape(vc::Joint::UGroove, 35, 18, 0, 0, 7), straight_down(), kS);
  check_truth(p.truth, {{-11.522020209603035, 35}, {-6.913818384165964, 5.9049587447183844}, {0, 0},
                        {6.913818384165964, 5.9049587447183844}, {11.522020209603035, 35}, {0, 0}, 35,
                        598.0926861108908, 23.04404041920607, 81, 81, 0, 0, 0});
  const double t9 = std::tan(9 * std::numbers::pi / 180);
  Exact x;
  x.top_a = x.top_b = 35;
  x.wall_a[0] = Vec2(-6.913818384165964, 5.9049587447183844), x.wall_a[1] = Vec2(-6.913818384165964 - t9, 6.9049587447183844);
  x.wall_b[0] = Vec2(6.913818384165964, 5.9049587447183844), x.wall_b[1] = Vec2(6.913818384165964 + t9, 6.9049587447183844);
  x.arc_a_c = x.arc_b_c = Vec2(0, 7);
  x.r_arc = 7;
  check_on_exact_section(p, x);
}

TEST_CASE("grooves: a J with one pass ending on its arc, truth worked by hand", "[corpus][grooves]") {
  // 30 mm plate, root face 2 (D = 28), gap 1, wall b 15 deg from vertical, radius 6,
  // one pass of 3 mm, crown 0.5:
  //   side a square: B1 = (-0.5, 28); arc b centre (0.5, 6), tangent at height 6 (1 - sin 15)
  //   = 4.447086, out 6 cos 15 = 5.795555: (6.295555, 4.447086); B5 = 6.295555 + 23.552914 tan 15
  //   = (12.606539, 28).
  //   level 3 < 4.447086: toe b on the arc, out sqrt(36 - 3^2) = 5.196152: B4 = (5.696152, 3); B2 = (-0.5, 3).
  //   cap chord 6.196152, sagitta 0.5: r = (9.598076 + 0.25) / 1 = 9.848076; B3 = (2.598076, 3.5).
  //   lowest: toes tie, B2 (side a); depth 25.
  //   area: polygon B1-B2-B4-T-B5 243.776217, minus the cap's segment 2.076104, plus
  //         the arc's segment between B4 and T (the arc bulges into plate b) 0.053646: 241.753760.
  //   wall angles 90 and 75, included 15, top width 13.106539.
  vc::GrooveShape g = shape(vc::Joint::JGroove, 30, 15, 2, 1, 6);
  g.passes = 1;
  g.layer_mm = 3;
  g.crown_mm = 0.5;
  const vc::Profile p = vc::make_groove_profile(g, straight_down(), kS);
  check_truth(p.truth, {{-0.5, 28}, {-0.5, 3}, {2.598076211353316, 3.5}, {5.696152422706632, 3},
                        {12.606539315945199, 28}, {-0.5, 3}, 25, 241.7537596464612, 13.106539315945199, 90, 75, 1,
                        0, 1});
  Exact x;
  x.top_a = x.top_b = 28;
  x.wall_a[0] = Vec2(-0.5, 0), x.wall_a[1] = Vec2(-0.5, 28);
  x.wall_b[0] = Vec2(6.29555495773441, 4.447085729384876), x.wall_b[1] = Vec2(12.606539315945199, 28);
  x.arc_b_c = Vec2(0.5, 6);
  x.r_arc = 6;
  x.cap_c = Vec2(2.598076211353316, -6.348076211353316), x.r_cap = 9.848076211353316;
  check_on_exact_section(p, x);
}

TEST_CASE("grooves: a fill that reaches the tops is refused", "[corpus][grooves]") {
  vc::GrooveShape g;
  g.thickness_mm = 12;
  g.passes = 4;
  g.layer_mm = 3;  // level 12 >= D = 12
  CHECK_THROWS_AS(vc::make_groove_profile(g, straight_down(), kS), std::invalid_argument);
  g.passes = 3;
  g.crown_mm = 3.5;  // 9 + 3.5 >= 12
  CHECK_THROWS_AS(vc::make_groove_profile(g, straight_down(), kS), std::invalid_argument);
  g.crown_mm = 2.5;
  CHECK_NOTHROW(vc::make_groove_profile(g, straight_down(), kS));
  g.joint = vc::Joint::Butt;
  CHECK_THROWS_AS(vc::make_groove_profile(g, straight_down(), kS), std::invalid_argument);
}

TEST_CASE("grooves: the camera's occlusion in a U 35 mm deep and 23 mm wide seen from 300 mm", "[corpus][grooves]") {
  // The U of the test above (B1, B5 = (-+11.522020, 35), tangent points at
  // height 5.904959, arcs about (0, 7) of radius 7), its root 300 mm below the
  // laser; sensor frame: B5 = (11.522020, 265).
  // Laser: the rays into the opening lean at most atan(11.52 / 265) = 2.5 deg
  // from vertical, the walls 9 deg outwards: the laser lights all of both walls.
  // Camera in the laser plane at y = +140 (25 deg baseline): wall b faces away
  // from it (its sight lines, 28 deg from vertical, go into plate b): all of
  // wall b and arc b are hidden. Wall a is seen down to the line from the
  // camera over B5: that line, (140, 0) + s (-128.478, 265), meets wall a's
  // straight line below the root (at sensor z 300.83), so the whole straight
  // part is seen, and it meets arc a at (-4.607807, 298.269546), joint height
  // 1.730454 (41.2 deg up the arc from the bottom): arc a is hidden below that.
  // At y = +210 (35 deg) the line meets wall a at (-7.499553, 290.396857),
  // joint height 9.603143: wall a hidden below it, all arcs hidden.
  // At y = -140 the mirror image: wall a and arc a hidden, arc b seen down to 1.730454.
  const vc::GrooveShape g = shape(vc::Joint::UGroove, 35, 18, 0, 0, 7);
  struct Case {
    double camera_y, limit_z;  // joint height below which the seen wall is hidden
    int seen_arc, seen_wall, hidden_arc, hidden_wall;
  };
  for (const Case c : {Case{140, 1.7304536742981327, vc::kFaceArc1, vc::kFaceBevel1, vc::kFaceArc2, vc::kFaceBevel2},
                       Case{210, 9.60314262367217, vc::kFaceArc1, vc::kFaceBevel1, vc::kFaceArc2, vc::kFaceBevel2},
                       Case{-140, 1.7304536742981327, vc::kFaceArc2, vc::kFaceBevel2, vc::kFaceArc1, vc::kFaceBevel1}}) {
    INFO("camera at y = " << c.camera_y);
    const vc::Profile p = vc::make_groove_profile(g, straight_down(c.camera_y), kS);
    const vc::Debug& d = *p.debug;
    double lowest_seen = 1e9, highest_hidden = -1e9;
    int lit = 0;
    for (std::size_t i = 0; i < p.y.size(); ++i) {
      const int f = d.hit_face[i];
      if (f != vc::kFaceArc1 && f != vc::kFaceArc2 && f != vc::kFaceBevel1 && f != vc::kFaceBevel2) continue;
      ++lit;  // the laser reaches the groove's every face
      const double z = kS - d.ideal_range_mm[i] * d.ray_dir[i].y();
      const bool shadow = d.status[i] == vc::kCameraShadow;
      CHECK((shadow || d.status[i] == vc::kValid));
      if (f == c.hidden_arc || f == c.hidden_wall) {
        CHECK(shadow);
      } else if (shadow) {
        highest_hidden = std::max(highest_hidden, z);
      } else {
        lowest_seen = std::min(lowest_seen, z);
      }
    }
    // About 0.1 mm between columns across the 23 mm opening; on a wall 9 deg
    // from vertical one column is 0.1 / tan 9 = 0.6 mm of height: the boundary
    // within a column.
    CHECK(lit > 200);
    CHECK(lowest_seen >= c.limit_z - 1e-6);
    CHECK(lowest_seen < c.limit_z + 0.7);
    CHECK(highest_hidden <= c.limit_z + 1e-6);
    CHECK(highest_hidden > c.limit_z - 0.7);
  }
}

TEST_CASE("grooves: ideal profiles put their points on the section and none below the lowest point", "[corpus][grooves]") {
  for (vc::Joint joint : vc::kGrooveJoints)
    for (std::uint64_t seed = 1; seed <= 120; ++seed) {
      vc::Options o;
      o.imperfections = false;
      o.keep_debug = true;
      o.decoy = seed % 5 == 0;
      const vc::Profile p = vc::make_profile(joint, seed, o);
      const vc::Truth& t = p.truth;
      const vc::Debug& d = *p.debug;
      INFO(vc::joint_name(joint) << " seed " << seed);
      // The top line and the remaining depth below it (the fill's ripples may
      // go 0.2 mm lower; the polygon's chords of the arcs 0.01 mm).
      const Vec2 b1 = bp(t, "B1"), b5 = bp(t, "B5"), e = (b5 - b1).normalized();
      const double slack = t.param("ripple_mm") + 0.01;
      for (std::size_t i = 0; i < p.y.size(); ++i) {
        if (!p.valid[i]) continue;
        const Vec2 q = d.ideal_range_mm[i] * d.ray_dir[i];
        double nearest = 1e300;
        for (const auto& edge : d.scene.edges) {
          const Vec2 ab = edge.b - edge.a;
          const double s = std::clamp((q - edge.a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
          nearest = std::min(nearest, (q - (edge.a + s * ab)).norm());
        }
        CHECK(nearest < 1e-6);
        const int f = d.hit_face[i];
        if (f == vc::kFaceCap || f == vc::kFaceArc1 || f == vc::kFaceArc2 || f == vc::kFaceBevel1 || f == vc::kFaceBevel2)
          CHECK(vc::cross(e, q - b1) <= t.depth_mm + slack);  // how far below the top line
      }
      // The lowest point is at the remaining depth, the track point on the bottom between the toes.
      const Vec2 low(t.fill_lowest_y_mm, t.fill_lowest_z_mm), b2 = bp(t, "B2"), b3 = bp(t, "B3"), b4 = bp(t, "B4");
      CHECK(vc::cross(e, low - b1) == Approx(t.depth_mm).margin(1e-9));
      // (b2 and b4 are one point, or one above the other, in a V closed at the root.)
      CHECK(b3.dot(e) >= std::min(b2.dot(e), b4.dot(e)) - 1e-9);
      CHECK(b3.dot(e) <= std::max(b2.dot(e), b4.dot(e)) + 1e-9);
      CHECK(vc::cross(e, b3 - b1) <= t.depth_mm + 1e-9);
      CHECK(t.angle_deg == Approx(180 - t.wall_angle_a_deg - t.wall_angle_b_deg).margin(1e-9));
      CHECK(t.top_width_mm == Approx((b5 - b1).norm()).margin(1e-12));
      CHECK(t.area_mm2 > 0);
      CHECK(t.passes == static_cast<int>(t.param("passes")));
      if (t.passes > 0) CHECK(t.depth_mm > 1.5);  // the fill stays 2 mm below the tops (less a concave cap, the cut's stretch)
      CHECK(t.standoff_mm == t.track_z_mm);
    }
}

TEST_CASE("grooves: parameters stay in their ranges and the groove fits the field", "[corpus][grooves]") {
  for (vc::Joint joint : vc::kGrooveJoints) {
    int thick = 0, with_passes = 0, seen_tops = 0, far = 0;
    const int n = 300;
    for (std::uint64_t seed = 1; seed <= n; ++seed) {
      vc::Options o;
      o.imperfections = false;
      const vc::Truth t = vc::make_profile(joint, seed, o).truth;
      INFO(vc::joint_name(joint) << " seed " << seed);
      const double th = t.param("thickness_mm"), a = t.param("included_angle_deg");
      if (t.has_tag("thick")) {
        ++thick;
        CHECK(th >= 20);
        CHECK(th <= 80);
        CHECK(t.param("standoff_drawn_mm") >= 100);
        CHECK(t.param("standoff_drawn_mm") <= 400);
      } else {
        CHECK(th >= 8);
        CHECK(th <= 15);
        CHECK(t.param("standoff_drawn_mm") <= 250);
      }
      far += t.standoff_mm > 250;
      switch (joint) {
        case vc::Joint::Bevel: CHECK((a >= 30 && a <= 50)); break;
        case vc::Joint::UGroove: CHECK((a >= 8 && a <= 20)); break;
        case vc::Joint::JGroove: CHECK((a >= 10 && a <= 25)); break;
        default: CHECK((a >= 40 && a <= 70)); break;
      }
      CHECK(t.param("root_face_mm") <= 3);
      CHECK(t.param("gap_joint_mm") <= 3);
      CHECK(std::abs(t.param("mismatch_joint_mm")) <= 2);
      if (joint == vc::Joint::UGroove || joint == vc::Joint::JGroove) {
        CHECK(t.param("radius_mm") <= 8);
        CHECK((t.param("radius_mm") >= 3 || t.has_tag("radius_limited")));
      }
      if (t.passes > 0) {
        ++with_passes;
        CHECK(t.param("layer_mm") >= 2);
        CHECK(t.param("layer_mm") <= 5);
        CHECK(t.param("crown_mm") >= -0.5);
        CHECK(t.param("crown_mm") <= 1.5);
        // The fill at least 2 mm below the lower top.
        const double D = t.param("depth_joint_mm"), m = t.param("mismatch_joint_mm");
        CHECK(t.param("fill_level_mm") + std::max(0.0, t.param("crown_mm")) <= D + std::min(0.0, m) - 2 + 1e-9);
      }
      // The whole groove and 10 mm of each top in view: both tops measured.
      seen_tops += !t.has_tag("plate_unseen") && !t.has_tag("hidden_B1") && !t.has_tag("hidden_B5");
    }
    INFO(vc::joint_name(joint) << ": thick " << thick << ", passes " << with_passes << ", tops seen " << seen_tops);
    if (joint == vc::Joint::VGrooveThick) CHECK(thick == n);
    else CHECK((thick > n / 3 && thick < 2 * n / 3));
    CHECK(with_passes > n / 2);
    CHECK(with_passes < n);  // sometimes none
    CHECK(far > 0);
    CHECK(seen_tops > n * 8 / 10);
  }
}

TEST_CASE("grooves: every variant occurs, and each forced one shows in the tags", "[corpus][grooves]") {
  for (vc::Joint joint : vc::kGrooveJoints) {
    std::vector<std::string> variants = vc::variant_names(joint);
    for (const std::string& variant : variants) {
      vc::Options o;
      o.columns = 256;
      o.probability[variant] = 1.0;
      if (variant == "bead_ripples") o.probability["passes"] = 1.0;  // ripples on a cap
      int tagged = 0, possible = 0;
      for (std::uint64_t seed = 1; seed <= 200; ++seed) {
        const vc::Truth t = vc::make_profile(joint, seed, o).truth;
        INFO(vc::joint_name(joint) << " variant " << variant << " seed " << seed);
        REQUIRE(std::isfinite(t.track_y_mm));
        REQUIRE(std::isfinite(t.depth_mm));
        REQUIRE(std::isfinite(t.area_mm2));
        for (const auto& [name, v] : t.params) REQUIRE(std::isfinite(v));
        // A bead needs room: up to 5 mm, 1.5 mm of crown and 2 mm below the
        // lower top (a thin plate with a deep root face may have none).
        const double room = t.param("depth_joint_mm") + std::min(0.0, t.param("mismatch_joint_mm")) - 3.5;
        const bool can = variant != "passes" && variant != "bead_ripples" ? true : room >= 5;
        possible += can;
        if (variant == "reflections")
          tagged += t.has_tag("reflection_front") || t.has_tag("reflection_behind");
        else
          tagged += can && t.has_tag(variant == "mirror" ? "mirrored" : variant);
      }
      INFO(vc::joint_name(joint) << " variant " << variant << " tagged " << tagged << " of " << possible);
      const int expected = variant == "shadow" || variant == "reflections" ? possible * 3 / 4 : possible;
      CHECK(tagged >= expected);
    }
    // With the default probabilities every variant turns up.
    for (const std::string& variant : variants) {
      int tagged = 0;
      for (std::uint64_t seed = 1; seed <= 300 && tagged == 0; ++seed) {
        const vc::Truth t = vc::make_profile(joint, seed, vc::Options{}).truth;
        tagged += variant == "reflections" ? t.has_tag("reflection_front") || t.has_tag("reflection_behind")
                                           : t.has_tag(variant == "mirror" ? "mirrored" : variant);
      }
      INFO(vc::joint_name(joint) << " variant " << variant);
      CHECK(tagged > 0);
    }
  }
}

TEST_CASE("grooves: names, and recordings keep the groove's shape", "[corpus][grooves]") {
  for (vc::Joint joint : vc::kGrooveJoints) {
    CHECK(vc::joint_from_name(vc::joint_name(joint)) == joint);
    CHECK(vc::is_groove(joint));
    vc::RecordingOptions r;
    r.ds_mm = 0.5;
    r.gap_opening_mm = 0;
    const std::vector<vc::Profile> rec = vc::make_recording(joint, 4, 40, r);
    for (std::size_t i = 1; i < rec.size(); ++i) {
      CHECK(rec[i].truth.angle_deg == Approx(rec[0].truth.angle_deg).margin(1e-9));
      CHECK(rec[i].truth.passes == rec[0].truth.passes);
      CHECK(std::hypot(rec[i].truth.track_y_mm - rec[i - 1].truth.track_y_mm,
                       rec[i].truth.track_z_mm - rec[i - 1].truth.track_z_mm) < 0.5);
    }
  }
  for (vc::Joint joint : vc::kAllJoints) CHECK_FALSE(vc::is_groove(joint));
  CHECK(vc::joint_from_name("vgroove-thick") == vc::Joint::VGrooveThick);
}
