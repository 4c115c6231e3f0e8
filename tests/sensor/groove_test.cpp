// The groove joints (docs/design/grooves.md): their truth worked out by hand,
// their plates, the validation messages, and scanned profiles lying on the
// analytic cross-section (the test's own outline, from the parameters).
#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "sensor/cell.h"
#include "sensor/mesh_file.h"
#include "sensor/presets.h"
#include "sensor/reference_source.h"
#include "sensor/workpiece.h"

using namespace vts;

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;
constexpr double kTol = 1e-4;  // the hand values are given to 5 decimals
const char* const kGrooveCells[] = {"vgroove-thick", "bevel", "bevel-thick", "ugroove", "ugroove-fill", "jgroove"};

void check_yz(const Vec2& got, double y, double z, double tol = kTol) {
  INFO("got (" << got.x() << ", " << got.y() << "), expected (" << y << ", " << z << ")");
  CHECK(std::abs(got.x() - y) <= tol);
  CHECK(std::abs(got.y() - z) <= tol);
}

struct Expected {
  const char* cell;
  double b1y, b1z, b5y, b5z, width;  // top edges, top width
  double b2y, b2z, b4y, b4z;         // toes
  double b3y, b3z;                   // track point
  double ly, lz;                     // fill_lowest
  double depth, area, wall_a, wall_b;
};

void check_truth(const JointTruth& t, const Expected& e) {
  INFO(e.cell);
  check_yz(t.top_a_yz, e.b1y, e.b1z);
  check_yz(t.top_b_yz, e.b5y, e.b5z);
  CHECK(t.top_width_mm == Approx(e.width).margin(kTol));
  check_yz(t.toe_a_yz, e.b2y, e.b2z);
  check_yz(t.toe_b_yz, e.b4y, e.b4z);
  check_yz(t.track_yz, e.b3y, e.b3z);
  check_yz(t.fill_lowest_yz, e.ly, e.lz);
  CHECK(t.depth_mm == Approx(e.depth).margin(kTol));
  CHECK(t.area_mm2 == Approx(e.area).margin(1e-3));
  CHECK(t.wall_angle_a_deg == Approx(e.wall_a).margin(1e-9));
  CHECK(t.wall_angle_b_deg == Approx(e.wall_b).margin(1e-9));
  CHECK(t.angle_deg == Approx(180.0 - e.wall_a - e.wall_b).margin(1e-9));
}

// The test's own analytic outline of a groove section (joint frame): the
// plates' faces (tops, walls with their arcs, lands, bottoms, outer ends) and
// the last bead's cap, from the parameters alone.
struct Outline {
  struct Arc {
    Vec2 c;
    double r, t0, t1;  // points at angles t0..t1 about c
  };
  std::vector<std::pair<Vec2, Vec2>> segs;
  std::vector<Arc> arcs;

  static double to_seg(const Vec2& p, const Vec2& a, const Vec2& b) {
    const Vec2 d = b - a;
    const double s = d.squaredNorm() > 0.0 ? std::clamp((p - a).dot(d) / d.squaredNorm(), 0.0, 1.0) : 0.0;
    return (p - a - s * d).norm();
  }
  double distance(const Vec2& p) const {
    double best = 1e300;
    for (const auto& [a, b] : segs) best = std::min(best, to_seg(p, a, b));
    for (const Arc& arc : arcs) {
      const Vec2 q = p - arc.c;
      const double t = std::atan2(q.y(), q.x());
      if (t >= arc.t0 && t <= arc.t1) best = std::min(best, std::abs(q.norm() - arc.r));
      for (const double e : {arc.t0, arc.t1})
        best = std::min(best, (p - arc.c - arc.r * Vec2(std::cos(e), std::sin(e))).norm());
    }
    return best;
  }
};

Outline outline_of(const Workpiece& w) {
  const JointParams& p = w.params;
  const double g = p.gap_mm, m = p.mismatch_mm, rf = p.root_face_mm, D = p.thickness_mm - p.root_face_mm;
  const double W = p.width_mm, R = p.radius_mm, a = p.angle_deg * kDeg;
  // Per side: wall's straight part from vertical, arc radius (0: none).
  double beta[2] = {0.5 * a, 0.5 * a}, radius[2] = {0.0, 0.0};
  if (w.type == JointType::Bevel) beta[0] = 0.0, beta[1] = a;
  if (w.type == JointType::UGroove) radius[0] = radius[1] = R;
  if (w.type == JointType::JGroove) beta[0] = 0.0, beta[1] = a, radius[1] = R;
  Outline o;
  Vec2 toe[2];
  const double h = p.passes * p.layer_mm;
  for (int side = 0; side < 2; ++side) {
    const double s = side == 0 ? -1.0 : 1.0, z0 = side == 0 ? 0.0 : m, r = radius[side], b = beta[side];
    const Vec2 root(s * 0.5 * g, z0);
    const Vec2 foot = root + Vec2(0.0, -rf), far_foot = foot + Vec2(s * W, 0.0);
    o.segs.push_back({root, foot});
    o.segs.push_back({foot, far_foot});
    o.segs.push_back({far_foot, far_foot + Vec2(0.0, rf + D)});
    // Tangent point (the root edge when there is no arc), then straight up to z0 + D.
    const Vec2 tan_pt = root + Vec2(s * r * std::cos(b), r * (1.0 - std::sin(b)));
    const Vec2 top = tan_pt + (z0 + D - tan_pt.y()) * Vec2(s * std::tan(b), 1.0);
    o.segs.push_back({tan_pt, top});
    o.segs.push_back({top, far_foot + Vec2(0.0, rf + D)});
    if (r > 0.0) {
      const Vec2 c = root + Vec2(0.0, r);
      if (side == 0) o.arcs.push_back({c, r, -kPi + b, -0.5 * kPi});
      else o.arcs.push_back({c, r, -0.5 * kPi, -b});
    }
    // The toe at level h: on the arc if below the tangent point, else on the straight part.
    const double v = h - z0, v_t = tan_pt.y() - z0, u_t = std::abs(tan_pt.x() - root.x());
    const double u = (r > 0.0 && v < v_t) ? std::sqrt(r * r - (r - v) * (r - v)) : u_t + (v - v_t) * std::tan(b);
    toe[side] = Vec2(root.x() + s * u, h);
  }
  if (p.passes > 0) {
    const double c = p.crown_mm, half = 0.5 * (toe[1].x() - toe[0].x());
    if (c == 0.0) {
      o.segs.push_back({toe[0], toe[1]});
    } else {
      const double rho = (half * half + c * c) / (2.0 * std::abs(c));
      const Vec2 centre(0.5 * (toe[0].x() + toe[1].x()), h + c - (c > 0 ? rho : -rho));
      const double t_a = std::atan2(toe[0].y() - centre.y(), toe[0].x() - centre.x());
      const double t_b = std::atan2(toe[1].y() - centre.y(), toe[1].x() - centre.x());
      o.arcs.push_back({centre, rho, std::min(t_a, t_b), std::max(t_a, t_b)});
    }
  }
  return o;
}

// Shoelace over a section polygon (counter-clockwise positive).
double section_area(const std::vector<Vec2>& poly) {
  double a = 0.0;
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const Vec2 &p = poly[i], &q = poly[(i + 1) % poly.size()];
    a += p.x() * q.y() - q.x() * p.y();
  }
  return 0.5 * a;
}

}  // namespace

// Values worked out by hand (and checked against a dense polygon: every arc
// sampled at 20000 points, area by shoelace, the lowest point by brute force;
// not with the code's closed forms). Wall a straight part beta_a from
// vertical, wall b beta_b; D = thickness - root face; h = passes x layer.
//
// vgroove-thick: t 40, rf 2 (D 38), 60 deg (beta 30), gap 2, 3 x 4 mm (h 12),
//   crown 0.8. B1 = (-1 - 38 tan 30, 38) = (-22.93931, 38); toes at z 12:
//   y = +-(1 + 12 tan 30) = +-7.92820; B3 = (0, 12 + 0.8). Convex cap: the
//   toes tie as lowest, side a wins: depth 38 - 12 = 26. Area: the trapezoid
//   between z 12 and 38, (15.85641 + 45.87862) / 2 x 26 = 802.55542, less the
//   cap's segment (chord 15.85641, sagitta 0.8: rho = (7.92820^2 + 0.64) /
//   1.6 = 39.68503, central angle 4 atan(0.8 / 7.92820) = 0.402259,
//   rho^2 / 2 (theta - sin theta) = 8.47402): 794.08140.
// bevel: t 12, rf 1.5 (D 10.5), 45 deg, gap 1, empty: B1 = (-0.5, 10.5)
//   (square wall), B5 = (0.5 + 10.5, 10.5); toes the root edges; B3 the
//   root centre; area the trapezoid (1 + 11.5) / 2 x 10.5 = 65.625.
// bevel-thick: t 30 (D 28.5), 2 x 4 mm (h 8), crown 0.8: toes (-0.5, 8) and
//   (0.5 + 8, 8), B3 (4, 8.8); area (9 + 29.5) / 2 x 20.5 = 394.625 less the
//   segment of chord 9, sagitta 0.8 (4.83021): 389.79479.
// ugroove: t 30, rf 2 (D 28), 16 deg (beta 8), R 6, gap 1: tangent points
//   +-(0.5 + 6 cos 8, 6 (1 - sin 8)) = +-(6.44161, 5.16496); tops at
//   +-(6.44161 + 22.83504 tan 8) = +-9.65086. The lowest point: the root (z 0),
//   ties to side a's root edge (-0.5, 0). Area: the polygon B1 T_a R_a R_b
//   T_b B5 (403.32540) plus two arc segments 36 / 2 (82 deg - sin 82 deg) =
//   7.93622 each: 419.19783.
// ugroove-fill: the ugroove with 4 x 3.5 mm (h 14 > 5.16496: toes on the
//   straight parts at +-(6.44161 + 8.83504 tan 8) = +-7.68329), crown 0.6.
// jgroove: t 25, rf 2 (D 23), wall b 20 deg from vertical, R 6, gap 1: side
//   a square (B1 = (-0.5, 23) straight above B2 = (-0.5, 0)), T_b = (0.5 + 6 cos 20, 6 (1 -
//   sin 20)) = (6.13816, 3.94788), B5 = (6.13816 + 19.05212 tan 20, 23) =
//   (13.07256, 23). B3 at y = (-0.5 + 6.13816) / 2 = 2.81908 lies on arc b:
//   z = 6 - sqrt(36 - 2.31908^2) = 0.46630.
TEST_CASE("grooves: the built-in cells' truth by hand", "[geometry][groove]") {
  const Expected cases[] = {
      {"vgroove-thick", -22.93931, 38, 22.93931, 38, 45.87862, -7.92820, 12, 7.92820, 12, 0, 12.8, -7.92820, 12,
       26, 794.08140, 60, 60},
      {"bevel", -0.5, 10.5, 11, 10.5, 11.5, -0.5, 0, 0.5, 0, 0, 0, -0.5, 0, 10.5, 65.625, 90, 45},
      {"bevel-thick", -0.5, 28.5, 29, 28.5, 29.5, -0.5, 8, 8.5, 8, 4, 8.8, -0.5, 8, 20.5, 389.79479, 90, 45},
      {"ugroove", -9.65086, 28, 9.65086, 28, 19.30173, -6.44161, 5.16496, 6.44161, 5.16496, 0, 0, -0.5, 0, 28,
       419.19783, 82, 82},
      {"ugroove-fill", -9.65086, 28, 9.65086, 28, 19.30173, -7.68329, 14, 7.68329, 14, 0, 14.6, -7.68329, 14, 14,
       236.52406, 82, 82},
      {"jgroove", -0.5, 23, 13.07256, 23, 13.57256, -0.5, 0, 6.13816, 3.94788, 2.81908, 0.46630, -0.5, 0, 23,
       212.68244, 90, 70},
  };
  for (const Expected& e : cases) {
    const auto cell = builtin_cell(e.cell);
    REQUIRE(cell);
    check_truth(cell->workpieces.at(0).truth, e);
  }
}

// Cases off the built-in cells, by the same dense polygons:
// - a J-groove with one 3 mm pass and a concave cap (-0.3): toe b on the arc
//   at v 3: (0.5 + sqrt(36 - 9), 3) = (5.69615, 3); the lowest point is the
//   cap's middle (2.59808, 2.7); depth 23 - 2.7.
// - a bevel with b raised 1 mm: the line B1-B5 rises 1 in 11.5; the lowest is
//   root edge a, (0, -10.5) from B1, at 120.75 / sqrt(133.25) = 10.46053 from
//   the line; area: the polygon B1 R_a R_b B5 by shoelace, 60.375.
// - a U-groove with b raised 0.5 and two 2 mm passes (h 4 below the tangent
//   points: both toes on the arcs), crown 0.4: toe a (-0.5 - sqrt(36 - 4),
//   4) = (-6.15685, 4), toe b at v 3.5: (0.5 + sqrt(36 - 6.25), 4) =
//   (5.95436, 4); the flat-topped cap's toes are equally high, but the line
//   B1-B5 rises to side b, so toe b is the farther: depth 24.39606.
TEST_CASE("grooves: concave cap, toes on the arcs, mismatch", "[geometry][groove]") {
  JointParams j = default_params(JointType::JGroove);
  j.thickness_mm = 25.0, j.root_face_mm = 2.0, j.radius_mm = 6.0, j.passes = 1, j.layer_mm = 3.0, j.crown_mm = -0.3;
  REQUIRE(validate(JointType::JGroove, j).empty());
  check_truth(build_workpiece(JointType::JGroove, j).truth,
              {"jgroove concave", -0.5, 23, 13.07256, 23, 13.57256, -0.5, 3, 5.69615, 3, 2.59808, 2.7, 2.59808, 2.7,
               20.3, 199.86867, 90, 70});

  JointParams b = default_params(JointType::Bevel);
  b.mismatch_mm = 1.0;
  REQUIRE(validate(JointType::Bevel, b).empty());
  const JointTruth bt = build_workpiece(JointType::Bevel, b).truth;
  check_truth(bt, {"bevel mismatch", -0.5, 10.5, 11, 11.5, 11.54340, -0.5, 0, 0.5, 1, 0, 0, -0.5, 0, 10.46053,
                   60.375, 90, 45});
  CHECK(bt.area_mm2 == Approx(std::abs(section_area({{-0.5, 10.5}, {-0.5, 0}, {0.5, 1}, {11, 11.5}}))));

  JointParams u = default_params(JointType::UGroove);
  u.thickness_mm = 30.0, u.radius_mm = 6.0, u.mismatch_mm = 0.5, u.passes = 2, u.layer_mm = 2.0, u.crown_mm = 0.4;
  REQUIRE(validate(JointType::UGroove, u).empty());
  check_truth(build_workpiece(JointType::UGroove, u).truth,
              {"ugroove mismatch", -9.65086, 28, 9.65086, 28.5, 19.30820, -6.15685, 4, 5.95436, 4, -0.10125, 4.4,
               5.95436, 4, 24.39606, 381.99451, 82, 82});
}

TEST_CASE("grooves: an empty v-groove is built as before the beads", "[geometry][groove]") {
  for (const double mismatch : {0.0, 1.0}) {
    JointParams p = default_params(JointType::VGroove);
    p.mismatch_mm = mismatch;
    const Workpiece w = build_workpiece(JointType::VGroove, p);
    // Two five-sided plates, depth thickness - root face even with mismatch
    // (the tracker's reading of it), the open trapezoid's area.
    REQUIRE(w.plates.size() == 2);
    CHECK(w.plates[0].section_yz.size() == 5);
    CHECK(w.truth.depth_mm == 12.0 - 1.5);
    const double run = 10.5 * std::tan(30.0 * kDeg);
    CHECK(w.truth.area_mm2 ==
          Approx(std::abs(section_area({{-0.5, 0}, {0.5, mismatch}, {0.5 + run, mismatch + 10.5}, {-0.5 - run, 10.5}}))));
    CHECK(w.truth.root_yz == Vec2::Zero());
    CHECK(w.truth.track_yz == Vec2::Zero());
    check_yz(w.truth.fill_lowest_yz, -0.5, 0.0);
  }
  // The default cell as the hand values of workpiece_test.cpp.
  check_truth(builtin_cell("vgroove")->workpieces.at(0).truth,
              {"vgroove", -6.56218, 10.5, 6.56218, 10.5, 13.12436, -0.5, 0, 0.5, 0, 0, 0, -0.5, 0, 10.5, 74.15287, 60,
               60});
}

TEST_CASE("grooves: plates are convex, closed, and the beads fill what the truth says", "[geometry][groove]") {
  for (const std::string name : kGrooveCells) {
    INFO(name);
    const Cell cell = *builtin_cell(name);
    const Workpiece& w = cell.workpieces.at(0);
    for (const Plate& plate : w.plates) {
      const auto& s = plate.section_yz;
      REQUIRE(s.size() >= 3);
      CHECK(section_area(s) > 0.0);
      for (std::size_t i = 0; i < s.size(); ++i) {  // every corner turns left: convex
        const Vec2 d1 = s[(i + 1) % s.size()] - s[i], d2 = s[(i + 2) % s.size()] - s[(i + 1) % s.size()];
        CHECK(d1.x() * d2.y() - d1.y() * d2.x() > -1e-9);
      }
      CHECK(mesh_edge_stats(plate_mesh(plate, w.params.segment_mm, Pose::Identity())).closed());
    }
    // The sections' total area: both plates (W x thickness each, less what
    // the groove takes of them: the empty groove's open area, the same
    // joint's truth with passes 0, less the gap's g x D above the root) plus
    // the beads (that open area less what remains, plus the gap between the
    // lands, g x root face). No mismatch in these cells.
    REQUIRE(w.params.mismatch_mm == 0.0);
    JointParams empty = w.params;
    empty.passes = 0;
    const Workpiece e = build_workpiece(w.type, empty);
    const double g = w.params.gap_mm, D = w.params.thickness_mm - w.params.root_face_mm;
    const double beads =
        w.params.passes == 0 ? 0.0 : e.truth.area_mm2 - w.truth.area_mm2 + g * w.params.root_face_mm;
    double total = 0.0;
    for (const Plate& plate : w.plates) total += section_area(plate.section_yz);
    const double plates = 2.0 * w.params.width_mm * w.params.thickness_mm;
    // Arcs as polylines: each chord cuts at most 2/3 x chord x 0.002 mm off.
    CHECK(total == Approx(plates - (e.truth.area_mm2 - g * D) + beads).margin(0.05));
  }
}

TEST_CASE("grooves: invalid parameters are named with their value", "[geometry][groove]") {
  // Each case: a joint's defaults changed by `change`, and the message's start.
  struct Case {
    JointType type;
    void (*change)(JointParams&);
    const char* message;
  };
  const Case cases[] = {
      {JointType::VGroove, [](JointParams& p) { p.passes = -1; }, "passes = -1: must be >= 0 (0: an empty groove)"},
      // D = 10.5: three 3.5 mm passes reach the tops.
      {JointType::VGroove, [](JointParams& p) { p.passes = 3, p.layer_mm = 3.5; },
       "passes = 3: the fill (passes x layer_mm = 10.5 mm, crown_mm 0.5) must stay below the plate tops (10.5 mm "
       "above the root)"},
      {JointType::VGroove, [](JointParams& p) { p.passes = 3, p.layer_mm = 0.0; }, "layer_mm = 0: must be > 0"},
      // D = 23, beta 8 deg: an arc of 30 meets the wall 25.8 mm up.
      {JointType::UGroove, [](JointParams& p) { p.radius_mm = 30.0; }, "radius_mm = 30: the bottom arc does not fit"},
      {JointType::UGroove, [](JointParams& p) { p.radius_mm = -2.0; }, "radius_mm = -2: must be > 0"},
      {JointType::Bevel, [](JointParams& p) { p.angle_deg = 90.0; }, "angle_deg = 90: bevel angle"},
      {JointType::JGroove, [](JointParams& p) { p.root_face_mm = 20.0; },
       "root_face_mm = 20: must be >= 0 and smaller than thickness_mm"},
      {JointType::JGroove, [](JointParams& p) { p.width_mm = 5.0; },
       "width_mm = 5: must exceed the groove wall's width"},
      // One 3 mm pass in the bevel: toes (-0.5, 3) and (3.5, 3), 2 mm half chord.
      {JointType::Bevel, [](JointParams& p) { p.passes = 1, p.crown_mm = 5.0; },
       "crown_mm = 5: must be smaller in size than half the cap's width"},
      // Concave 1.9 mm: the circle (radius 2.0026) is below the 45-degree wall near toe b.
      {JointType::Bevel, [](JointParams& p) { p.passes = 1, p.crown_mm = -1.9; },
       "crown_mm = -1.9: the concave cap dips below the groove's wall"},
      {JointType::Bevel, [](JointParams& p) { p.mismatch_mm = 2.0, p.passes = 1, p.layer_mm = 1.5; },
       "passes = 1: the fill level (passes x layer_mm = 1.5 mm) must be above side b's root edge"},
  };
  for (const Case& c : cases) {
    JointParams p = default_params(c.type);
    c.change(p);
    CHECK(validate(c.type, p).rfind(c.message, 0) == 0);
  }
  for (JointType t : {JointType::VGroove, JointType::Bevel, JointType::UGroove, JointType::JGroove}) {
    CHECK(validate(t, default_params(t)).empty());
    CHECK(is_groove(t));
    CHECK(joint_type_from_string(to_string(t)) == t);
    CHECK(tracker_joint(t).has_value());
  }
  CHECK(to_string(JointType::Bevel) == "bevel");
  CHECK(to_string(JointType::UGroove) == "ugroove");
  CHECK(to_string(JointType::JGroove) == "jgroove");
  CHECK_FALSE(is_groove(JointType::Butt));
}

// Every valid point of an ideal profile (Embree reference) lies on the
// outline above: within 0.001 mm (the plane tolerance of the cross-checks)
// plus the arcs' chord error. The cells' own poses, and each groove seen by
// lps-2048-short (range 60-100 mm) at 95 mm, lps-1280-mid at 150 and 250 mm
// and the default mspot at 400 mm.
TEST_CASE("grooves: scanned profile points lie on the analytic section", "[geometry][groove][reference]") {
  struct View {
    const char* preset;  // nullptr: the cell's own scanner and path
    double standoff_mm;
  };
  const View views[] = {{nullptr, 0.0}, {"lps-2048-short", 95.0}, {"lps-1280-mid", 150.0}, {"lps-1280-mid", 250.0},
                        {"mspot", 400.0}};
  for (const std::string name : kGrooveCells) {
    const Cell cell = *builtin_cell(name);
    const Workpiece& w = cell.workpieces.at(0);
    const Outline outline = outline_of(w);
    const Mesh mesh = cell.mesh();
    for (const View& v : views) {
      ScannerDesc desc = v.preset ? *sensor_preset(v.preset) : cell.scanner;
      const ScanPath path = v.preset ? default_path(w, v.standoff_mm) : cell.path;
      auto source = make_reference_source(desc, mesh);
      Profile prof;
      const Pose pose = path.pose_at(10);
      source->scan(pose, prof);
      int valid = 0, in_groove = 0;
      double worst = 0.0;
      for (int i = 0; i < prof.size(); ++i) {
        if (!prof.valid[i]) continue;
        const Vec3 j = w.world_from_joint.inverse() * (pose * Vec3(0.0, prof.y_mm[i], prof.z_mm[i]));
        const Vec2 yz(j.y(), j.z());
        ++valid;
        in_groove += yz.x() > w.truth.top_a_yz.x() && yz.x() < w.truth.top_b_yz.x();
        worst = std::max(worst, outline.distance(yz));
      }
      INFO(name << " seen by " << desc.name << " at " << (v.preset ? v.standoff_mm : 0.0) << " mm: " << valid
                << " valid points, " << in_groove << " in the groove, farthest " << worst << " mm off the section");
      CHECK(worst <= 0.001 + kArcChordErrorMm);
      CHECK(in_groove > 0);
      if (!v.preset) {
        // The cells see the whole section: both plate tops beyond the groove.
        CHECK(valid > desc.points * 9 / 10);
        WARN(name << ": " << desc.name << ", " << in_groove << " of " << valid << " valid points in the groove");
      }
    }
  }
}
