#include "sensor/groove.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "sensor/field_error.h"

namespace vts::groove {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;

double cross(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

// Twice the signed area (counter-clockwise positive).
double shoelace2(const std::vector<Vec2>& poly) {
  double a = 0.0;
  for (std::size_t i = 0; i < poly.size(); ++i) a += cross(poly[i], poly[(i + 1) % poly.size()]);
  return a;
}

// Chords of an arc of radius r spanning `span` radians, each within
// kArcChordErrorMm of the arc: r (1 - cos(step / 2)) <= error.
int arc_segments(double r, double span) {
  if (span <= 0.0) return 0;
  const double step = 2.0 * std::acos(std::max(-1.0, 1.0 - kArcChordErrorMm / r));
  return std::max(1, static_cast<int>(std::ceil(span / step - 1e-9)));
}

// Area between an arc of radius r and its chord, central angle theta.
double segment_area(double r, double theta) { return 0.5 * r * r * (theta - std::sin(theta)); }

// One wall in its side's own frame: u across, away from the gap's centre,
// from the root edge; v up from the root edge. A square wall has beta 0 and no
// arc; a bevelled one beta > 0; a curved one an arc of `radius` from the root
// edge (horizontal tangent there, centre (0, radius)) up to the tangent point
// with the straight part.
struct Wall {
  double beta = 0.0;    // the straight part from vertical, rad
  double radius = 0.0;  // 0: no arc
  double depth = 0.0;   // root edge to plate top (D)

  bool curved() const { return radius > 0.0; }
  // The arc's angle at the tangent point, from its bottom (the root edge).
  double arc_span() const { return curved() ? 0.5 * kPi - beta : 0.0; }
  Vec2 arc_point(double phi) const { return {radius * std::sin(phi), radius * (1.0 - std::cos(phi))}; }
  Vec2 tangent() const {
    return curved() ? Vec2(radius * std::cos(beta), radius * (1.0 - std::sin(beta))) : Vec2(0.0, 0.0);
  }
  Vec2 top() const {
    const Vec2 t = tangent();
    return {t.x() + (depth - t.y()) * std::tan(beta), depth};
  }
  // The true wall at height v (0 <= v <= depth).
  double u_at(double v) const {
    const Vec2 t = tangent();
    if (curved() && v <= t.y()) {
      const double c = radius - v;
      return std::sqrt(std::max(0.0, radius * radius - c * c));
    }
    return t.x() + (v - t.y()) * std::tan(beta);
  }
  double phi_at(double v) const { return std::acos(std::clamp((radius - v) / radius, -1.0, 1.0)); }
  // Root edge, the arc's chords, the tangent point, the top: the mesh's wall.
  std::vector<Vec2> polyline() const {
    std::vector<Vec2> pts{Vec2(0.0, 0.0)};
    if (curved()) {
      const int n = arc_segments(radius, arc_span());
      for (int i = 1; i < n; ++i) pts.push_back(arc_point(arc_span() * i / n));
      pts.push_back(tangent());
    }
    pts.push_back(top());
    return pts;
  }
};

// Linear interpolation along a polyline whose coordinate `key` (0: y or u,
// 1: z or v) rises from point to point: the other coordinate where `key`
// has `value` (clamped to the ends; a step where `key` does not rise is
// skipped).
double polyline_at(const std::vector<Vec2>& pts, int key, double value) {
  const int other = 1 - key;
  for (std::size_t i = 0; i + 1 < pts.size(); ++i) {
    const Vec2 &p = pts[i], &q = pts[i + 1];
    if (value <= q[key] && q[key] > p[key]) {
      const double s = std::clamp((value - p[key]) / (q[key] - p[key]), 0.0, 1.0);
      return p[other] + s * (q[other] - p[other]);
    }
  }
  return pts.back()[other];
}
// u of a wall's polyline at height v; z of a polyline (by rising y) at y.
double polyline_u(const std::vector<Vec2>& pts, double v) { return polyline_at(pts, 1, v); }
double polyline_z(const std::vector<Vec2>& pts, double y) { return polyline_at(pts, 0, y); }

struct Shape {
  double g = 0.0, m = 0.0, rf = 0.0, D = 0.0, W = 0.0;
  int passes = 0;
  double level = 0.0;  // h_N = passes * layer_mm
  double crown = 0.0;
  Wall a, b;
  // Beads laid off-centre (JointParams::bead_offsets_mm not all 0): the
  // fill's chord is the line z = fill_c + fill_slope y (joint frame) instead
  // of z = level.
  bool tilted = false;
  double fill_c = 0.0, fill_slope = 0.0;

  Vec2 on_a(const Vec2& uv) const { return {-0.5 * g - uv.x(), uv.y()}; }
  Vec2 on_b(const Vec2& uv) const { return {0.5 * g + uv.x(), m + uv.y()}; }
};

// Where the line z = c + k y meets a wall (side a or b): bisection on the
// height v above its root edge, u(v) the wall's (true or polyline) offset.
template <class U, class Map>
Vec2 wall_meets_line(double c, double k, double v_max, U u_of, Map on_side) {
  auto below = [&](double v) {
    const Vec2 q = on_side(Vec2(u_of(v), v));
    return q.y() < c + k * q.x();
  };
  double lo = 0.0, hi = v_max;
  if (!below(lo)) return on_side(Vec2(u_of(lo), lo));
  if (below(hi)) return on_side(Vec2(u_of(hi), hi));
  for (int i = 0; i < 100 && hi - lo > 1e-12; ++i) {
    const double mid = 0.5 * (lo + hi);
    (below(mid) ? lo : hi) = mid;
  }
  const double v = 0.5 * (lo + hi);
  return on_side(Vec2(u_of(v), v));
}

// The groove's open section from the root edges up to the plate tops
// (walls by their polylines), counter-clockwise: top a, wall a down, root
// a, root b, wall b up, top b.
std::vector<Vec2> open_section(const Shape& s) {
  std::vector<Vec2> poly;
  const std::vector<Vec2> wa = s.a.polyline(), wb = s.b.polyline();
  for (auto it = wa.rbegin(); it != wa.rend(); ++it) poly.push_back(s.on_a(*it));
  for (const Vec2& q : wb) poly.push_back(s.on_b(q));
  return poly;
}

// The area of `poly` below the line z = c + k y (Sutherland-Hodgman against
// the half-plane, then the shoelace).
double area_below(const std::vector<Vec2>& poly, double c, double k) {
  auto f = [&](const Vec2& q) { return c + k * q.x() - q.y(); };  // >= 0: kept
  std::vector<Vec2> out;
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const Vec2 &p = poly[i], &q = poly[(i + 1) % poly.size()];
    const double fp = f(p), fq = f(q);
    if (fp >= 0.0) out.push_back(p);
    if ((fp >= 0.0) != (fq >= 0.0)) out.push_back(p + (q - p) * (fp / (fp - fq)));
  }
  return out.size() < 3 ? 0.0 : 0.5 * std::abs(shoelace2(out));
}

bool any_offset(const JointParams& p) {
  const std::size_t n = std::min<std::size_t>(p.bead_offsets_mm.size(), std::max(p.passes, 0));
  for (std::size_t i = 0; i < n; ++i)
    if (p.bead_offsets_mm[i] != 0.0) return true;
  return false;
}

// Beads laid off-centre (docs/CELLS.md "Beads laid off-centre"): bead k
// deposits the area its flat layer would, between z = (k-1) t and k t
// (t = layer_mm), under a straight chord z = c + s y. Laid delta_k across
// from the middle between the toes of the fill under it, the chord's slope
// is 12 t delta_k / w^2 (w the flat layer's top width: a w x t rectangle
// whose top slopes by s has its centroid s w^2 / (12 t) off its middle), and
// c the level at which the area under the chord inside the walls has grown
// by the deposit. A bead cannot push its top under the fill it lies on: where
// that slope would take the chord below the old one at a wall, the slope is
// brought back towards the old one until the chord just touches it there
// (the layer thins to nothing at that wall).
constexpr double kMaxBeadTiltDeg = 15.0;

void lay_beads(Shape& s, const JointParams& p) {
  const std::vector<Vec2> open = open_section(s);
  double c = 0.0, k = 0.0, area = area_below(open, 0.0, 0.0);
  auto ua = [&](double v) { return s.a.u_at(v); };
  auto ub = [&](double v) { return s.b.u_at(v); };
  auto on_a = [&](const Vec2& uv) { return s.on_a(uv); };
  auto on_b = [&](const Vec2& uv) { return s.on_b(uv); };
  for (int i = 0; i < s.passes; ++i) {
    const double h1 = (i + 1) * p.layer_mm;
    const double delta = i < static_cast<int>(p.bead_offsets_mm.size()) ? p.bead_offsets_mm[i] : 0.0;
    const double w = (s.on_b({s.b.u_at(h1 - s.m), h1 - s.m}) - s.on_a({s.a.u_at(h1), h1})).x();
    const double target = area + area_below(open, h1, 0.0) - area_below(open, h1 - p.layer_mm, 0.0);
    // The old chord's toes: the new one must not pass under either.
    const Vec2 old_a = wall_meets_line(c, k, s.D, ua, on_a), old_b = wall_meets_line(c, k, s.D, ub, on_b);
    auto level_for = [&](double kk) {
      double lo = -s.D - std::abs(kk) * s.W - std::abs(s.m) - s.g, hi = s.D + std::abs(kk) * s.W + std::abs(s.m) + s.g;
      for (int it = 0; it < 200 && hi - lo > 1e-13; ++it) {
        const double mid = 0.5 * (lo + hi);
        (area_below(open, mid, kk) < target ? lo : hi) = mid;
      }
      return 0.5 * (lo + hi);
    };
    auto fits = [&](double kk, double cc) {
      return cc + kk * old_a.x() >= old_a.y() - 1e-9 && cc + kk * old_b.x() >= old_b.y() - 1e-9;
    };
    // A pool in the flat position holds no steeper top than kMaxBeadTiltDeg:
    // a narrow layer (the root's) wets both walls and levels, its deposit's
    // centroid moving less than the torch.
    const double k_max = std::tan(kMaxBeadTiltDeg * std::numbers::pi / 180.0);
    const double k_want =
        std::isfinite(delta) ? std::clamp(12.0 * p.layer_mm * delta / (w * w), -k_max, k_max) : 0.0;
    double k_new = k_want, c_new = level_for(k_want);
    if (!fits(k_new, c_new)) {
      double lo = 0.0, hi = 1.0;  // of the way from the old slope to the one wanted
      for (int it = 0; it < 60; ++it) {
        const double mid = 0.5 * (lo + hi), kk = k + mid * (k_want - k);
        (fits(kk, level_for(kk)) ? lo : hi) = mid;
      }
      k_new = k + lo * (k_want - k);
      c_new = level_for(k_new);
    }
    c = c_new, k = k_new;
    area = area_below(open, c, k);
  }
  s.tilted = true;
  s.fill_c = c;
  s.fill_slope = k;
}

// The toes of the fill: flat, where z = level meets the walls (u by the
// walls' polylines when `polyline`, the mesh's, else the true walls);
// tilted, where the fill's chord does.
std::pair<Vec2, Vec2> fill_toes(const Shape& s, bool polyline) {
  const std::vector<Vec2> wa = s.a.polyline(), wb = s.b.polyline();
  if (!s.tilted) {
    if (polyline)
      return {s.on_a({polyline_u(wa, s.level), s.level}), s.on_b({polyline_u(wb, s.level - s.m), s.level - s.m})};
    return {s.on_a({s.a.u_at(s.level), s.level}), s.on_b({s.b.u_at(s.level - s.m), s.level - s.m})};
  }
  auto ua = [&](double v) { return polyline ? polyline_u(wa, v) : s.a.u_at(v); };
  auto ub = [&](double v) { return polyline ? polyline_u(wb, v) : s.b.u_at(v); };
  return {wall_meets_line(s.fill_c, s.fill_slope, s.D, ua, [&](const Vec2& uv) { return s.on_a(uv); }),
          wall_meets_line(s.fill_c, s.fill_slope, s.D, ub, [&](const Vec2& uv) { return s.on_b(uv); })};
}

Shape shape_of(JointType type, const JointParams& p) {
  Shape s;
  s.g = p.gap_mm;
  s.m = p.mismatch_mm;
  s.rf = p.root_face_mm;
  s.D = p.thickness_mm - p.root_face_mm;
  s.W = p.width_mm;
  s.passes = p.passes;
  s.level = p.passes * p.layer_mm;
  s.crown = p.crown_mm;
  const double half = 0.5 * p.angle_deg * kDeg, full = p.angle_deg * kDeg, r = p.radius_mm;
  switch (type) {
    case JointType::Bevel: s.a = {0.0, 0.0, s.D}; s.b = {full, 0.0, s.D}; break;
    case JointType::UGroove: s.a = {half, r, s.D}; s.b = {half, r, s.D}; break;
    case JointType::JGroove: s.a = {0.0, 0.0, s.D}; s.b = {full, r, s.D}; break;
    default: s.a = {half, 0.0, s.D}; s.b = {half, 0.0, s.D}; break;  // v-groove
  }
  if (any_offset(p)) lay_beads(s, p);
  return s;
}

// The last pass's cap: a circular arc from toe a to toe b (same height) with
// sagitta `crown` at the middle; flat when crown is 0.
struct Cap {
  Vec2 a, b;
  double crown = 0.0;
  double half = 0.0;             // half the chord
  Vec2 centre = Vec2::Zero();    // of the circle (crown != 0)
  double rho = 0.0;              // its radius
  double theta = 0.0;            // central angle

  // `tilted`: the toes need not be level (beads laid off-centre); the
  // sagitta is then square to the chord.
  Cap(const Vec2& toe_a, const Vec2& toe_b, double c, bool tilted) : a(toe_a), b(toe_b), crown(c) {
    if (tilted) {
      const Vec2 d = b - a;
      half = 0.5 * d.norm();
      if (crown == 0.0) return;
      const Vec2 n = Vec2(-d.y(), d.x()) / d.norm();  // up, for a chord from a to b
      rho = (half * half + crown * crown) / (2.0 * std::abs(crown));
      centre = 0.5 * (a + b) + (crown - std::copysign(rho, crown)) * n;
      theta = 4.0 * std::atan(std::abs(crown) / half);
      return;
    }
    half = 0.5 * (b.x() - a.x());
    if (crown == 0.0) return;
    rho = (half * half + crown * crown) / (2.0 * std::abs(crown));
    centre = Vec2(0.5 * (a.x() + b.x()), a.y() + crown - std::copysign(rho, crown));
    theta = 4.0 * std::atan(std::abs(crown) / half);  // tan(theta / 4) = sagitta / half chord
  }
  bool flat() const { return crown == 0.0; }
  Vec2 middle() const { return {0.5 * (a.x() + b.x()), a.y() + crown}; }
  // The cap at y (between the toes): on the chord when flat, else on the
  // circle (its upper half for a convex cap, the lower for a concave one).
  Vec2 at(double y) const {
    if (flat()) return {y, a.y() + (b.y() - a.y()) * (y - a.x()) / (b.x() - a.x())};
    const double dy = y - centre.x();
    return {y, centre.y() + std::copysign(std::sqrt(std::max(0.0, rho * rho - dy * dy)), crown)};
  }
  // The cap's points, toe a to toe b, chords within kArcChordErrorMm.
  std::vector<Vec2> polyline() const {
    if (flat()) return {a, b};
    const double t0 = std::atan2(a.y() - centre.y(), a.x() - centre.x());
    const double t1 = std::atan2(b.y() - centre.y(), b.x() - centre.x());
    const int n = arc_segments(rho, theta);
    std::vector<Vec2> pts{a};
    for (int i = 1; i < n; ++i) {
      const double t = t0 + (t1 - t0) * i / n;
      pts.push_back(centre + rho * Vec2(std::cos(t), std::sin(t)));
    }
    pts.push_back(b);
    return pts;
  }
};

// Removes repeated points (and a last point equal to the first).
std::vector<Vec2> dedupe(const std::vector<Vec2>& in) {
  std::vector<Vec2> out;
  for (const Vec2& p : in)
    if (out.empty() || (p - out.back()).norm() > 1e-9) out.push_back(p);
  while (out.size() > 1 && (out.front() - out.back()).norm() <= 1e-9) out.pop_back();
  return out;
}

void add_plate(std::vector<Vec2> section, double length_mm, Workpiece& w) {
  section = dedupe(section);
  const double a2 = section.size() >= 3 ? shoelace2(section) : 0.0;
  if (std::abs(a2) <= 1e-12) return;
  if (a2 < 0.0) std::reverse(section.begin(), section.end());
  w.plates.push_back(Plate{std::move(section), 0.0, length_mm});
}

// One side's plate, as convex pieces: under each chord of the arc a strip
// with vertical sides, under the straight part a trapezoid (or, for a wall
// without an arc, the whole plate as one polygon), then the rest of the
// plate out to W as a rectangle.
template <class Map>
void add_side(const Shape& s, const Wall& wall, Map to_joint, double length_mm, Workpiece& w) {
  const std::vector<Vec2> pts = wall.polyline();
  const double W = s.W, rf = s.rf, D = s.D;
  auto add = [&](std::initializer_list<Vec2> local) {
    std::vector<Vec2> section;
    for (const Vec2& p : local) section.push_back(to_joint(p));
    add_plate(std::move(section), length_mm, w);
  };
  if (!wall.curved()) {
    if (wall.beta == 0.0) add({{0.0, -rf}, {W, -rf}, {W, D}, {0.0, D}});
    else add({{W, -rf}, {0.0, -rf}, {0.0, 0.0}, pts.back(), {W, D}});
    return;
  }
  for (std::size_t i = 0; i + 1 < pts.size(); ++i)
    add({{pts[i].x(), -rf}, {pts[i + 1].x(), -rf}, pts[i + 1], pts[i]});
  add({{pts.back().x(), -rf}, {W, -rf}, {W, D}, {pts.back().x(), D}});
}

// The beads: the groove's open section from z = -rf (between the lands) or
// the walls up to the cap, cut into strips with vertical sides at every
// corner of the walls, the root edges and the cap's polyline, each strip a
// convex quadrilateral (a triangle at a toe).
void add_fill(const Shape& s, double length_mm, Workpiece& w) {
  const std::vector<Vec2> wa = s.a.polyline(), wb = s.b.polyline();
  const std::pair<Vec2, Vec2> toes = fill_toes(s, true);
  const Vec2 toe_a = toes.first, toe_b = toes.second;  // (no structured binding: clang 14 cannot capture one)
  const std::vector<Vec2> cap = Cap(toe_a, toe_b, s.crown, s.tilted).polyline();
  // The walls in the joint frame by rising y.
  std::vector<Vec2> floor_a, floor_b;
  for (auto it = wa.rbegin(); it != wa.rend(); ++it) floor_a.push_back(s.on_a(*it));
  for (const Vec2& p : wb) floor_b.push_back(s.on_b(p));

  std::vector<double> ys{toe_a.x(), toe_b.x()};
  const auto inside = [&](double y) { return y > toe_a.x() && y < toe_b.x(); };
  for (const double y : {-0.5 * s.g, 0.5 * s.g})
    if (inside(y)) ys.push_back(y);
  for (const std::vector<Vec2>* pts : std::initializer_list<const std::vector<Vec2>*>{&floor_a, &floor_b, &cap})
    for (const Vec2& p : *pts)
      if (inside(p.x())) ys.push_back(p.x());
  std::sort(ys.begin(), ys.end());
  ys.erase(std::unique(ys.begin(), ys.end(), [](double u, double v) { return v - u <= 1e-9; }), ys.end());

  const double lo = -0.5 * s.g, hi = 0.5 * s.g;
  for (std::size_t i = 0; i + 1 < ys.size(); ++i) {
    const double y0 = ys[i], y1 = ys[i + 1], mid = 0.5 * (y0 + y1);
    // On a wall the toe's own height (a wall may be vertical there); between
    // the lands the bottom of the root faces.
    auto floor_z = [&](double y) {
      if (mid < lo) return y == toe_a.x() ? toe_a.y() : polyline_z(floor_a, y);
      if (mid > hi) return y == toe_b.x() ? toe_b.y() : polyline_z(floor_b, y);
      return -s.rf;
    };
    add_plate({{y0, floor_z(y0)}, {y1, floor_z(y1)}, {y1, polyline_z(cap, y1)}, {y0, polyline_z(cap, y0)}},
              length_mm, w);
  }
}

// A piece of the bottom surface, for its point farthest from the top line:
// a segment (radius 0), or an arc of the circle (centre, radius) from p to q
// whose points lie at angles [t0, t1] about the centre (no wrap at +-pi).
struct Piece {
  Vec2 p, q;
  Vec2 centre = Vec2::Zero();
  double radius = 0.0;
  double t0 = 0.0, t1 = 0.0;
};

}  // namespace

std::string validate(JointType type, const JointParams& p) {
  const double D = p.thickness_mm - p.root_face_mm;
  switch (type) {
    case JointType::Bevel:
      if (p.angle_deg <= 0.0 || p.angle_deg >= 90.0)
        return field_error("angle_deg", p.angle_deg,
                           "bevel angle (side b's wall from vertical) must be > 0 and < 90 degrees");
      break;
    case JointType::UGroove:
      if (p.angle_deg < 0.0 || p.angle_deg >= 150.0)
        return field_error("angle_deg", p.angle_deg, "U-groove included angle must be >= 0 and < 150 degrees");
      break;
    case JointType::JGroove:
      if (p.angle_deg < 0.0 || p.angle_deg >= 90.0)
        return field_error("angle_deg", p.angle_deg,
                           "J-groove wall angle (from vertical) must be >= 0 and < 90 degrees");
      break;
    default: break;
  }
  if (type != JointType::VGroove) {  // the v-groove checks these itself, as before
    if (p.root_face_mm < 0.0 || p.root_face_mm >= p.thickness_mm)
      return field_error("root_face_mm", p.root_face_mm, "must be >= 0 and smaller than thickness_mm");
  }
  const Shape s = shape_of(type, p);
  for (const Wall* wall : {&s.a, &s.b}) {
    if (wall->curved() && wall->tangent().y() >= D)
      return field_error(
          "radius_mm", p.radius_mm,
          "the bottom arc does not fit: it meets the straight wall " + message_number(wall->tangent().y()) +
              " mm above the root, not below the plate top (thickness_mm - root_face_mm = " + message_number(D) +
              " mm)");
    if (type != JointType::VGroove && p.width_mm <= wall->top().x())
      return field_error(
          "width_mm", p.width_mm,
          "must exceed the groove wall's width across the seam (" + message_number(wall->top().x()) + " mm)");
  }
  if (p.passes == 0) return {};
  for (std::size_t i = 0; i < p.bead_offsets_mm.size(); ++i)
    if (!std::isfinite(p.bead_offsets_mm[i]))
      return field_error("bead_offsets_mm[" + std::to_string(i) + "]", p.bead_offsets_mm[i], "must be a finite number");
  if (s.tilted) {
    const auto [ta, tb] = fill_toes(s, false);
    if (ta.y() + std::max(s.crown, 0.0) >= D || tb.y() + std::max(s.crown, 0.0) >= D + s.m)
      return field_error("passes", p.passes,
                         "the fill, tilted by beads laid off-centre, reaches a plate top (its toes at z = " +
                             message_number(ta.y()) + " and " + message_number(tb.y()) + " mm)");
    // (A bead pushed against one wall may leave the other toe exactly on a
    // root edge, its layer thinned to nothing there: that edge is covered.)
    if (ta.y() < -1e-6 || tb.y() < s.m - 1e-6)
      return field_error("passes", p.passes,
                         "the fill, tilted by beads laid off-centre, leaves a root edge bare (its toes at z = " +
                             message_number(ta.y()) + " and " + message_number(tb.y()) + " mm)");
  }
  const double top = std::min(D, D + s.m);
  if (s.level + std::max(s.crown, 0.0) >= top)
    return field_error("passes", p.passes,
                       "the fill (passes x layer_mm = " + message_number(s.level) + " mm, crown_mm " +
                           message_number(s.crown) + ") must stay below the plate tops (" + message_number(top) +
                           " mm above the root)");
  if (s.level <= std::max(s.m, 0.0))
    return field_error("passes", p.passes,
                       "the fill level (passes x layer_mm = " + message_number(s.level) +
                           " mm) must be above side b's root edge (mismatch_mm = " + message_number(s.m) + ")");
  const auto [toe_a, toe_b] = fill_toes(s, false);
  const double half = s.tilted ? 0.5 * (toe_b - toe_a).norm() : 0.5 * (toe_b.x() - toe_a.x());
  if (std::abs(s.crown) >= half)
    return field_error("crown_mm", s.crown,
                       "must be smaller in size than half the cap's width (" + message_number(half) + " mm)");
  if (s.crown < 0.0) {
    // A concave cap must not dip below the groove's surface anywhere.
    const Cap cap(toe_a, toe_b, s.crown, s.tilted);
    const std::vector<Vec2> wa = s.a.polyline(), wb = s.b.polyline();
    std::vector<Vec2> floor_a, floor_b;
    for (auto it = wa.rbegin(); it != wa.rend(); ++it) floor_a.push_back(s.on_a(*it));
    for (const Vec2& q : wb) floor_b.push_back(s.on_b(q));
    constexpr int kSamples = 400;
    for (int i = 1; i < kSamples; ++i) {
      const double y = toe_a.x() + (toe_b.x() - toe_a.x()) * i / kSamples;
      const double dy = y - cap.centre.x();
      const double z = cap.centre.y() - std::sqrt(std::max(0.0, cap.rho * cap.rho - dy * dy));
      double fz = -s.rf;
      if (y < -0.5 * s.g) fz = polyline_z(floor_a, y);
      else if (y > 0.5 * s.g) fz = polyline_z(floor_b, y);
      if (z < fz) return field_error("crown_mm", s.crown, "the concave cap dips below the groove's wall");
    }
  }
  return {};
}

void add_plates(JointType type, const JointParams& p, Workpiece& w, bool sides) {
  const Shape s = shape_of(type, p);
  if (sides) {
    add_side(s, s.a, [&](const Vec2& uv) { return s.on_a(uv); }, p.length_mm, w);
    add_side(s, s.b, [&](const Vec2& uv) { return s.on_b(uv); }, p.length_mm, w);
  }
  if (s.passes > 0) add_fill(s, p.length_mm, w);
}

void set_truth(JointType type, const JointParams& p, Workpiece& w, bool keep_depth_area) {
  const Shape s = shape_of(type, p);
  JointTruth& t = w.truth;
  t.gap_mm = s.g;
  t.mismatch_mm = s.m;
  t.angle_deg = p.angle_deg;
  t.wall_angle_a_deg = 90.0 - s.a.beta / kDeg;
  t.wall_angle_b_deg = 90.0 - s.b.beta / kDeg;
  const Vec2 root_a = s.on_a({0.0, 0.0}), root_b = s.on_b({0.0, 0.0});
  const Vec2 top_a = s.on_a(s.a.top()), top_b = s.on_b(s.b.top());
  const Vec2 tan_a = s.on_a(s.a.tangent()), tan_b = s.on_b(s.b.tangent());
  const Vec2 centre_a = s.on_a({0.0, s.a.radius}), centre_b = s.on_b({0.0, s.b.radius});
  t.top_a_yz = top_a;
  t.top_b_yz = top_b;
  t.top_width_mm = (top_b - top_a).norm();

  // The region left open, B1 -> wall a -> B2 -> bottom -> B4 -> wall b -> B5,
  // as a polygon (arcs by their chords) plus the circular segments between
  // each arc and its chord: a wall's arc bulges out of the polygon (the
  // groove is inside its circle), a convex cap into it.
  std::vector<Vec2> outline{top_a};
  double segments = 0.0;
  std::vector<Piece> bottom;  // side a to side b
  if (s.passes == 0) {
    t.toe_a_yz = tan_a;
    t.toe_b_yz = tan_b;
    if (s.a.curved()) {
      outline.push_back(tan_a);
      segments += segment_area(s.a.radius, s.a.arc_span());
      bottom.push_back({tan_a, root_a, centre_a, s.a.radius, -0.5 * kPi - s.a.arc_span(), -0.5 * kPi});
    }
    outline.push_back(root_a);
    outline.push_back(root_b);
    bottom.push_back({root_a, root_b});
    if (s.b.curved()) {
      outline.push_back(tan_b);
      segments += segment_area(s.b.radius, s.b.arc_span());
      bottom.push_back({root_b, tan_b, centre_b, s.b.radius, -0.5 * kPi, -0.5 * kPi + s.b.arc_span()});
    }
    // B3: midway between the toes in y, on the bottom surface: the root
    // (closed at the root edges' level, z = 0) or an arc.
    const double y = 0.5 * (t.toe_a_yz.x() + t.toe_b_yz.x());
    double z = 0.0;
    if (y < root_a.x()) {
      const double u = root_a.x() - y;
      z = s.a.radius - std::sqrt(s.a.radius * s.a.radius - u * u);
    } else if (y > root_b.x()) {
      const double u = y - root_b.x();
      z = s.m + s.b.radius - std::sqrt(s.b.radius * s.b.radius - u * u);
    }
    t.track_yz = Vec2(y, z);
  } else {
    std::tie(t.toe_a_yz, t.toe_b_yz) = fill_toes(s, false);
    const double va = s.tilted ? t.toe_a_yz.y() : s.level, vb = s.tilted ? t.toe_b_yz.y() - s.m : s.level - s.m;
    const Cap cap(t.toe_a_yz, t.toe_b_yz, s.crown, s.tilted);
    if (s.a.curved() && va < s.a.tangent().y()) {
      outline.push_back(tan_a);
      segments += segment_area(s.a.radius, s.a.arc_span() - s.a.phi_at(va));
    }
    outline.push_back(t.toe_a_yz);
    outline.push_back(t.toe_b_yz);
    if (s.b.curved() && vb < s.b.tangent().y()) {
      outline.push_back(tan_b);
      segments += segment_area(s.b.radius, s.b.arc_span() - s.b.phi_at(vb));
    }
    if (!cap.flat()) segments -= std::copysign(segment_area(cap.rho, cap.theta), cap.crown);
    if (cap.flat()) {
      bottom.push_back({cap.a, cap.b});
    } else {
      const auto angle = [&](const Vec2& q) { return std::atan2(q.y() - cap.centre.y(), q.x() - cap.centre.x()); };
      const double ta = angle(cap.a), tb = angle(cap.b);
      bottom.push_back({cap.a, cap.b, cap.centre, cap.rho, std::min(ta, tb), std::max(ta, tb)});
    }
    t.track_yz = s.tilted ? cap.at(0.5 * (cap.a.x() + cap.b.x())) : cap.middle();
  }
  outline.push_back(top_b);

  // fill_lowest: the bottom surface's point farthest from the line B1-B5
  // (towards the root); ties to side a (the first in order).
  const Vec2 along = (top_b - top_a).normalized();
  const Vec2 down(along.y(), -along.x());
  const auto dist = [&](const Vec2& q) { return (q - top_a).dot(down); };
  Vec2 lowest = bottom.front().p;
  auto consider = [&](const Vec2& q) {
    if (dist(q) > dist(lowest) + 1e-9) lowest = q;
  };
  for (const Piece& piece : bottom) {
    consider(piece.p);
    if (piece.radius > 0.0) {
      // The circle's farthest point, if it lies on the arc.
      const double td = std::atan2(down.y(), down.x());
      if (td > piece.t0 && td < piece.t1) consider(piece.centre + piece.radius * down);
    }
    consider(piece.q);
  }
  t.fill_lowest_yz = lowest;
  if (!keep_depth_area) {
    t.depth_mm = dist(lowest);
    t.area_mm2 = 0.5 * std::abs(shoelace2(outline)) + segments;
  }

  t.features = {{"left_root", root_a},        {"right_root", root_b},          {"left_top", top_a},
                {"right_top", top_b},         {"left_toe", t.toe_a_yz},        {"right_toe", t.toe_b_yz},
                {"track", t.track_yz},        {"fill_lowest", t.fill_lowest_yz}};
  if (s.a.curved()) t.features.emplace_back("left_tangent", tan_a);
  if (s.b.curved()) t.features.emplace_back("right_tangent", tan_b);
}

}  // namespace vts::groove
