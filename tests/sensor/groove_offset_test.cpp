// A bead laid off-centre (JointParams::bead_offsets_mm, sensor/groove.cpp,
// docs/CELLS.md "Beads laid off-centre"): the groove's truth and plates
// against the test's own cross-section. Truth here: the 60-degree V of
// vgroove-thick (40 mm plate, root face 2, gap 2, no mismatch) with 4 mm
// layers and a flat cap; the walls are y = -+(1 + z tan 30). Two beads centred
// leave the fill flat at z = 8; the third, laid 1 mm towards side b, deposits
// what its flat layer would (z = 8..12) under a chord whose slope is
// 12 t delta / w^2 (t = 4, w the layer's top width 2 + 24 tan 30), the
// documented model. The test finds that chord's level itself, by bisection
// on the area between z = 8 and the chord inside the walls integrated
// numerically over the height (nothing from sensor/groove.cpp), and derives
// the toes, B3, the depth and the area left from it.
#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>
#include <vector>

#include "sensor/workpiece.h"

using namespace vts;

namespace {

const double kT30 = std::tan(std::numbers::pi / 6.0);
double half_width(double z) { return 1.0 + z * kT30; }

JointParams thick_vgroove() {
  JointParams p = default_params(JointType::VGroove);
  p.thickness_mm = 40.0;
  p.angle_deg = 60.0;
  p.root_face_mm = 2.0;
  p.gap_mm = 2.0;
  p.mismatch_mm = 0.0;
  p.width_mm = 60.0;
  p.layer_mm = 4.0;
  p.crown_mm = 0.0;
  return p;
}

// The area inside the walls between z = 8 and the chord z = c + k y (k > 0),
// by the midpoint rule over z: the slice at height z runs from
// max(-h(z), (z - c) / k) to h(z).
double deposit(double c, double k) {
  constexpr int kSteps = 200000;
  const double z0 = 8.0, z1 = 38.0, dz = (z1 - z0) / kSteps;
  double a = 0.0;
  for (int i = 0; i < kSteps; ++i) {
    const double z = z0 + (i + 0.5) * dz, h = half_width(z);
    a += std::max(0.0, h - std::max(-h, (z - c) / k)) * dz;
  }
  return a;
}

double shoelace(const std::vector<Vec2>& poly) {
  double a = 0.0;
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const Vec2 &p = poly[i], &q = poly[(i + 1) % poly.size()];
    a += p.x() * q.y() - p.y() * q.x();
  }
  return 0.5 * std::abs(a);
}

}  // namespace

TEST_CASE("groove offset: a bead laid 1 mm off-centre against the hand-worked section", "[sensor][groove]") {
  JointParams p = thick_vgroove();
  p.passes = 3;
  p.bead_offsets_mm = {0.0, 0.0, 1.0};
  REQUIRE(validate(JointType::VGroove, p).empty());
  const Workpiece w = build_workpiece(JointType::VGroove, p);
  const JointTruth& t = w.truth;

  // The test's own chord.
  const double layer_area = 2.0 * (4.0 + 0.5 * kT30 * (12.0 * 12.0 - 8.0 * 8.0));  // integral of 2 h(z), 8..12
  const double wl = 2.0 * half_width(12.0);
  const double k = 12.0 * 4.0 * 1.0 / (wl * wl);
  double lo = 8.0, hi = 16.0;
  for (int i = 0; i < 60; ++i) {
    const double mid = 0.5 * (lo + hi);
    (deposit(mid, k) < layer_area ? lo : hi) = mid;
  }
  const double c = 0.5 * (lo + hi);
  // Toes: z = c + k y on y = -h(z) and y = h(z).
  const double za = (c - k) / (1.0 + k * kT30), zb = (c + k) / (1.0 - k * kT30);
  const Vec2 toe_a(-half_width(za), za), toe_b(half_width(zb), zb);
  INFO("chord z = " << c << " + " << k << " y; toes z " << za << ", " << zb);

  CHECK(t.toe_a_yz.x() == Approx(toe_a.x()).margin(1e-4));
  CHECK(t.toe_a_yz.y() == Approx(toe_a.y()).margin(1e-4));
  CHECK(t.toe_b_yz.x() == Approx(toe_b.x()).margin(1e-4));
  CHECK(t.toe_b_yz.y() == Approx(toe_b.y()).margin(1e-4));
  CHECK(zb - za > 1.0);  // side b, where the bead went, is filled higher
  // B3: midway between the toes, on the (flat) cap.
  const double ym = 0.5 * (toe_a.x() + toe_b.x());
  CHECK(t.track_yz.x() == Approx(ym).margin(1e-4));
  CHECK(t.track_yz.y() == Approx(c + k * ym).margin(1e-4));
  CHECK(ym > 0.2);  // the next bead's true place moved towards side b
  // What is left: the polygon B1, B2, B4, B5, and, as a second check, the
  // whole V (0..38) less the three flat layers' deposit (0..12): the area is
  // conserved whatever the tilt.
  const Vec2 top_a(-half_width(38.0), 38.0), top_b(half_width(38.0), 38.0);
  const double left = shoelace({top_a, toe_a, toe_b, top_b});
  const double whole = 2.0 * (38.0 + 0.5 * kT30 * 38.0 * 38.0), filled = 2.0 * (12.0 + 0.5 * kT30 * 144.0);
  CHECK(left == Approx(whole - filled).margin(1e-3));
  CHECK(t.area_mm2 == Approx(left).margin(1e-3));
  // The lowest point is the lower toe (side a); depth from the plate tops.
  CHECK(t.fill_lowest_yz.x() == Approx(toe_a.x()).margin(1e-4));
  CHECK(t.depth_mm == Approx(38.0 - za).margin(1e-4));
  // The mesh: the two plates, then the fill strips, which hold the lands'
  // gap (2 x 2) and the three layers.
  double strips = 0.0;
  for (std::size_t i = 2; i < w.plates.size(); ++i) strips += shoelace(w.plates[i].section_yz);
  CHECK(strips == Approx(4.0 + filled).margin(1e-3));
  // Laid 1 mm off: the deposit's centroid across, from the test's own
  // integration, lies near 1 mm off the middle (the model's rectangle rule;
  // 1.18 mm here, as the V's layer widens upwards, which the rule ignores).
  double m0 = 0.0, m1 = 0.0;
  constexpr int kSteps = 20000;
  for (int i = 0; i < kSteps; ++i) {
    const double z = 8.0 + (i + 0.5) * 8.0 / kSteps, h = half_width(z);
    const double y0 = std::max(-h, (z - c) / k);
    if (y0 >= h) continue;
    m0 += (h - y0), m1 += 0.5 * (h * h - y0 * y0);
  }
  CHECK(m1 / m0 == Approx(1.0).margin(0.25));
}

TEST_CASE("groove offset: beads laid on centre leave every plate and truth as before", "[sensor][groove]") {
  for (const JointType type : {JointType::VGroove, JointType::Bevel, JointType::UGroove, JointType::JGroove}) {
    JointParams p = default_params(type);
    p.thickness_mm = 30.0;
    p.width_mm = 60.0;
    p.passes = 3;
    p.crown_mm = 0.6;
    const Workpiece before = build_workpiece(type, p);
    p.bead_offsets_mm = {0.0, 0.0, 0.0, 0.0};
    const Workpiece after = build_workpiece(type, p);
    INFO(to_string(type));
    REQUIRE(before.plates.size() == after.plates.size());
    bool same = true;
    for (std::size_t i = 0; i < before.plates.size(); ++i) same = same && before.plates[i].section_yz == after.plates[i].section_yz;
    CHECK(same);
    CHECK(before.truth.area_mm2 == after.truth.area_mm2);
    CHECK(before.truth.depth_mm == after.truth.depth_mm);
    CHECK(before.truth.track_yz == after.truth.track_yz);
    CHECK(before.truth.toe_a_yz == after.truth.toe_a_yz);
    CHECK(before.truth.toe_b_yz == after.truth.toe_b_yz);
  }
}

TEST_CASE("groove offset: a crowned cap on a tilted chord, a bead pushed against a wall", "[sensor][groove]") {
  JointParams p = thick_vgroove();
  p.passes = 3;
  p.crown_mm = 0.8;
  p.bead_offsets_mm = {0.5, 0.5, 0.5};
  REQUIRE(validate(JointType::VGroove, p).empty());
  const JointTruth t = build_workpiece(JointType::VGroove, p).truth;
  // The area left: the polygon B1, B2, B4, B5 less the cap's circular
  // segment over its chord B2-B4 (sagitta 0.8), worked out here.
  const Vec2 top_a(-half_width(38.0), 38.0), top_b(half_width(38.0), 38.0);
  const double half = 0.5 * (t.toe_b_yz - t.toe_a_yz).norm();
  const double rho = (half * half + 0.64) / 1.6, theta = 4.0 * std::atan(0.8 / half);
  const double left = shoelace({top_a, t.toe_a_yz, t.toe_b_yz, top_b}) - 0.5 * rho * rho * (theta - std::sin(theta));
  CHECK(t.area_mm2 == Approx(left).margin(1e-6));
  // The toes on the walls; the tilt towards b; B3 0.8 above the chord's
  // middle (square to a chord tilted by a few degrees: within 0.01 mm).
  CHECK(-t.toe_a_yz.x() == Approx(half_width(t.toe_a_yz.y())).margin(1e-6));
  CHECK(t.toe_b_yz.x() == Approx(half_width(t.toe_b_yz.y())).margin(1e-6));
  CHECK(t.toe_b_yz.y() > t.toe_a_yz.y() + 0.5);
  const Vec2 mid = 0.5 * (t.toe_a_yz + t.toe_b_yz);
  CHECK(t.track_yz.x() == Approx(mid.x()).margin(1e-9));
  CHECK(t.track_yz.y() - mid.y() == Approx(0.8).margin(0.01));

  // A third bead pushed 12 mm towards b: the slope it asks for (12 t delta
  // / w^2) is steeper than a pool holds, so its top tilts by 15 degrees
  // (docs/CELLS.md), toe a stays above the two beads' flat z = 8, and it
  // holds the flat layer's area (the test's own deposit integral, 8..38).
  const double k15 = std::tan(15.0 * std::numbers::pi / 180.0);
  p.bead_offsets_mm = {0.0, 0.0, 12.0};
  p.crown_mm = 0.0;
  REQUIRE(validate(JointType::VGroove, p).empty());
  const JointTruth pushed = build_workpiece(JointType::VGroove, p).truth;
  CHECK(pushed.toe_a_yz.y() > 8.0);
  CHECK(-pushed.toe_a_yz.x() == Approx(half_width(pushed.toe_a_yz.y())).margin(1e-6));
  const double slope = (pushed.toe_b_yz.y() - pushed.toe_a_yz.y()) / (pushed.toe_b_yz.x() - pushed.toe_a_yz.x());
  CHECK(slope == Approx(k15).margin(1e-9));
  CHECK(12.0 * 4.0 * 12.0 / std::pow(2.0 * half_width(12.0), 2) > k15);  // the slope asked for
  CHECK(deposit(pushed.toe_a_yz.y() - slope * pushed.toe_a_yz.x(), slope) ==
        Approx(2.0 * (4.0 + 0.5 * kT30 * (144.0 - 64.0))).margin(1e-3));
  // The root bead pushed 3 mm towards b: tilted by 15 degrees too, both
  // root edges covered (toe a above the root).
  p.passes = 1;
  p.bead_offsets_mm = {3.0};
  REQUIRE(validate(JointType::VGroove, p).empty());
  const JointTruth root = build_workpiece(JointType::VGroove, p).truth;
  CHECK(root.toe_a_yz.y() > 0.0);
  CHECK((root.toe_b_yz.y() - root.toe_a_yz.y()) / (root.toe_b_yz.x() - root.toe_a_yz.x()) ==
        Approx(k15).margin(1e-9));
  CHECK(root.toe_b_yz.y() > 4.0);
  p.passes = 3;
  p.bead_offsets_mm = {0.0, NAN};
  CHECK(validate(JointType::VGroove, p).find("must be a finite number") != std::string::npos);
}
