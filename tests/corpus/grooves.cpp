// The groove joints of docs/design/grooves.md (issue 18): single bevel, U, J
// and a V in thick plate, with beads laid in them. Geometry and truth written
// from the design document alone (nothing from sensor/, render/ or tracker/):
// straight walls and circular arcs, the truth from the exact lines and arcs.
#include "internal.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace vts_corpus::detail {

namespace {

enum class WallKind { Square, Bevel, Curved };

// One wall in the joint frame, from its root edge (the top of its land) up to
// its plate's top edge.
struct Wall {
  double side = -1;  // -1: side a (y < 0), +1: side b
  Vec2 root{0, 0};
  WallKind kind = WallKind::Square;
  double beta = 0;  // the straight part's angle from vertical (rad)
  double R = 0;     // Curved: the arc's radius (centre straight above the root edge)
  double D = 0;     // the top edge's height above the root edge

  // The arc runs from phi = 0 (the root edge, horizontal tangent) to phi_t,
  // where its tangent is the straight part's direction.
  double phi_t() const { return kPi / 2 - beta; }
  double tangent_h() const { return kind == WallKind::Curved ? R * (1 - dm::sin(beta)) : 0.0; }
  Vec2 centre() const { return root + Vec2(0, R); }
  Vec2 arc(double phi) const { return root + Vec2(side * R * dm::sin(phi), R - R * dm::cos(phi)); }
  // The wall's point at height h above the root edge.
  Vec2 at(double h) const {
    double out;
    if (kind == WallKind::Curved && h < tangent_h())
      out = std::sqrt(std::max(0.0, R * R - (R - h) * (R - h)));
    else if (kind == WallKind::Curved)
      out = R * dm::cos(beta) + (h - tangent_h()) * dm::tan(beta);
    else
      out = h * dm::tan(beta);
    return root + Vec2(side * out, h);
  }
  Vec2 tangent() const { return at(tangent_h()); }
  Vec2 top() const { return at(D); }
  // The wall's vertices from the root edge up to (not including) the top edge,
  // with the toe (height toe_h; NaN: none) as a vertex of its own: arc samples
  // every phi_t / n (at most 2 degrees), the same for the plate and the fill.
  // Each with the face of the edge leaving it upwards.
  std::vector<std::pair<Vec2, int>> up_to_top(double toe_h, int arc_face, int straight_face) const {
    std::vector<std::pair<Vec2, int>> v;
    const bool toe = !std::isnan(toe_h);
    auto h = [&](const Vec2& p) { return p.y() - root.y(); };
    if (kind == WallKind::Curved) {
      const int n = std::max(1, static_cast<int>(std::ceil(phi_t() / rad(2.0))));
      for (int k = 0; k < n; ++k) {
        const Vec2 p = arc(phi_t() * k / n);
        if (toe && !v.empty() && h(p) > toe_h && h(v.back().first) < toe_h) v.push_back({at(toe_h), arc_face});
        v.push_back({p, arc_face});
      }
      if (toe && toe_h > h(v.back().first) && toe_h < tangent_h()) v.push_back({at(toe_h), arc_face});
      v.push_back({tangent(), straight_face});
      if (toe && toe_h > tangent_h()) v.push_back({at(toe_h), straight_face});
    } else {
      v.push_back({root, straight_face});
      if (toe && toe_h > 0) v.push_back({at(toe_h), straight_face});
    }
    return v;
  }
};

// A piece of the bottom surface or of the groove's outline: a segment p -> q,
// or an arc about c of radius r from angle t0 sweeping dt (signed), p -> q.
struct Piece {
  bool arc = false;
  Vec2 p, q, c{0, 0};
  double r = 0, t0 = 0, dt = 0;
};

Piece segment(const Vec2& p, const Vec2& q) { return Piece{false, p, q}; }
Piece arc_piece(const Vec2& c, double r, const Vec2& p, const Vec2& q) {
  // Every arc here is less than a half circle and does not cross angle +-pi.
  const double t0 = dm::atan2(p.y() - c.y(), p.x() - c.x()), t1 = dm::atan2(q.y() - c.y(), q.x() - c.x());
  return Piece{true, p, q, c, r, t0, t1 - t0};
}

// Whether angle t lies on the arc's sweep.
bool on_sweep(const Piece& a, double t, double tol = 1e-12) {
  double d = t - a.t0;
  if (a.dt >= 0) {
    while (d < -tol) d += 2 * kPi;
    while (d > 2 * kPi - tol) d -= 2 * kPi;
    return d >= -tol && d <= a.dt + tol;
  }
  while (d > tol) d -= 2 * kPi;
  while (d < -2 * kPi + tol) d += 2 * kPi;
  return d <= tol && d >= a.dt - tol;
}

// The groove of a spec, with its bottom surface.
struct Groove {
  Wall a, b;
  double rf = 0, g = 0, m = 0, D = 0;
  int passes = 0;
  double level = 0, crown = 0;  // the last pass's level h_N (z) and the cap's sagitta
  Vec2 toe_a, toe_b;            // B2, B4 in the joint frame
  bool cap_flat = true;
  Vec2 cap_c{0, 0};
  double cap_r = 0;
  double toe_h_a() const { return passes > 0 ? level : a.tangent_h(); }
  double toe_h_b() const { return passes > 0 ? level - m : b.tangent_h(); }
};

Groove groove_of(const JointSpec& s) {
  Groove G;
  G.rf = s.root_face_mm;
  G.g = s.gap_mm;
  G.m = s.mismatch_mm;
  G.D = s.depth_mm;
  G.a.side = -1;
  G.b.side = 1;
  G.a.root = Vec2(-G.g / 2, 0);
  G.b.root = Vec2(G.g / 2, G.m);
  G.a.D = G.b.D = G.D;
  G.a.R = G.b.R = s.radius_mm;
  const double included = rad(s.angle_deg);
  switch (s.joint) {
    case Joint::Bevel:  // side a square, side b bevelled at the included angle
      G.a.kind = WallKind::Square;
      G.b.kind = WallKind::Bevel;
      G.b.beta = included;
      break;
    case Joint::UGroove:
      G.a.kind = G.b.kind = WallKind::Curved;
      G.a.beta = G.b.beta = included / 2;
      break;
    case Joint::JGroove:
      G.a.kind = WallKind::Square;
      G.b.kind = WallKind::Curved;
      G.b.beta = included;
      break;
    default:  // VGrooveThick
      G.a.kind = G.b.kind = WallKind::Bevel;
      G.a.beta = G.b.beta = included / 2;
      break;
  }
  G.passes = s.passes;
  G.level = s.passes * s.layer_mm;
  G.crown = s.passes > 0 ? s.crown_mm : 0.0;
  G.toe_a = G.passes > 0 ? G.a.at(G.level) : G.a.tangent();
  G.toe_b = G.passes > 0 ? G.b.at(G.level - G.m) : G.b.tangent();
  if (G.passes > 0 && G.crown != 0) {
    const double c = G.toe_b.x() - G.toe_a.x(), sag = G.crown;
    G.cap_flat = false;
    G.cap_r = (c * c / 4 + sag * sag) / (2 * std::abs(sag));
    G.cap_c = Vec2(0.5 * (G.toe_a.x() + G.toe_b.x()), G.level + sag - (sag > 0 ? G.cap_r : -G.cap_r));
  }
  return G;
}

// The bottom surface from toe a to toe b: the cap, or the root and the arcs.
std::vector<Piece> bottom(const Groove& G) {
  std::vector<Piece> out;
  if (G.passes > 0) {
    out.push_back(G.cap_flat ? segment(G.toe_a, G.toe_b) : arc_piece(G.cap_c, G.cap_r, G.toe_a, G.toe_b));
    return out;
  }
  if (G.a.kind == WallKind::Curved) out.push_back(arc_piece(G.a.centre(), G.a.R, G.toe_a, G.a.root));
  // (A V or bevel closed at the root: the bottom is the one root point.)
  if ((G.b.root - G.a.root).norm() > 0 || out.empty()) out.push_back(segment(G.a.root, G.b.root));
  if (G.b.kind == WallKind::Curved) out.push_back(arc_piece(G.b.centre(), G.b.R, G.b.root, G.toe_b));
  return out;
}

// The closed outline B1 -> wall a -> B2 -> bottom -> B4 -> wall b -> B5 -> B1.
std::vector<Piece> outline(const Groove& G) {
  std::vector<Piece> out;
  const Vec2 B1 = G.a.top(), B5 = G.b.top();
  if (G.a.kind == WallKind::Curved && G.toe_h_a() < G.a.tangent_h()) {
    out.push_back(segment(B1, G.a.tangent()));
    out.push_back(arc_piece(G.a.centre(), G.a.R, G.a.tangent(), G.toe_a));
  } else {
    out.push_back(segment(B1, G.toe_a));
  }
  for (const Piece& p : bottom(G)) out.push_back(p);
  if (G.b.kind == WallKind::Curved && G.toe_h_b() < G.b.tangent_h()) {
    out.push_back(arc_piece(G.b.centre(), G.b.R, G.toe_b, G.b.tangent()));
    out.push_back(segment(G.b.tangent(), B5));
  } else {
    out.push_back(segment(G.toe_b, B5));
  }
  out.push_back(segment(B5, B1));
  return out;
}

// Area enclosed by a closed outline (Green's theorem; exact for the arcs).
double enclosed_area(const std::vector<Piece>& pieces) {
  double twice = 0;
  for (const Piece& p : pieces) {
    if (!p.arc) {
      twice += cross(p.p, p.q);
    } else {  // integral of (x dy - y dx) over c + r u(t): r c x (u1 - u0) + r^2 dt
      const Vec2 u0 = (p.p - p.c) / p.r, u1 = (p.q - p.c) / p.r;
      twice += p.r * cross(p.c, u1 - u0) + p.r * p.r * p.dt;
    }
  }
  return 0.5 * std::abs(twice);
}

// Where the line o + l d meets the pieces (the one nearest o); nullopt: nowhere.
std::optional<Vec2> meet(const std::vector<Piece>& pieces, const Vec2& o, const Vec2& d) {
  std::optional<Vec2> best;
  double best_l = 1e300;
  auto take = [&](double l) {
    if (std::abs(l) < std::abs(best_l)) {
      best_l = l;
      best = o + l * d;
    }
  };
  for (const Piece& p : pieces) {
    if (!p.arc) {
      const Vec2 e = p.q - p.p;
      if (e.squaredNorm() == 0) {  // a point
        const double l = (p.p - o).dot(d) / d.squaredNorm();
        if ((o + l * d - p.p).norm() < 1e-9) take(l);
        continue;
      }
      const double den = cross(d, e);
      if (std::abs(den) < 1e-12 * d.norm() * e.norm()) {  // parallel: on the line, its middle (a closed root's step)
        if (std::abs(cross(d.normalized(), p.p - o)) < 1e-9) take((0.5 * (p.p + p.q) - o).dot(d) / d.squaredNorm());
        continue;
      }
      const double l = cross(p.p - o, e) / den, mu = cross(p.p - o, d) / den;
      if (mu >= -1e-12 && mu <= 1 + 1e-12) take(l);
    } else {
      const Vec2 w = o - p.c;
      const double A = d.squaredNorm(), B = w.dot(d), C = w.squaredNorm() - p.r * p.r;
      const double disc = B * B - A * C;
      if (disc < 0) continue;
      for (const double l : {(-B - std::sqrt(disc)) / A, (-B + std::sqrt(disc)) / A}) {
        const Vec2 q = o + l * d - p.c;
        if (on_sweep(p, dm::atan2(q.y(), q.x()), 1e-9)) take(l);
      }
    }
  }
  return best;
}

// The bottom surface's point midway between the toes along the plates, the
// perpendicular taken in the frame the map leads to (the sensor frame; the
// identity: the joint frame). Joint frame.
Vec2 track_point(const Groove& G, const Affine& map) {
  const Vec2 ms = 0.5 * (map(G.toe_a) + map(G.toe_b));
  const Vec2 plate = map.dir(Vec2(1, 0));
  const Mat2 inv = inverse(map.A);
  const Vec2 o = mul(inv, Vec2(ms - map.t)), d = mul(inv, Vec2(-plate.y(), plate.x()));
  const auto hit = meet(bottom(G), o, d);
  if (!hit)
    throw std::logic_error("corpus: the groove's track line misses its bottom (" + std::to_string(o.x()) + ", " +
                           std::to_string(o.y()) + ") dir (" + std::to_string(d.x()) + ", " + std::to_string(d.y()) +
                           "), passes " + std::to_string(G.passes) + " crown " + std::to_string(G.crown));
  return *hit;
}

// The lowest point of the bottom surface: farthest from the line B1-B5 (an
// affine map keeps the ratios of distances from a line: the same point in any
// frame). Ties go to the side scanned first.
Vec2 fill_lowest(const Groove& G, bool a_first) {
  const Vec2 B1 = G.a.top(), B5 = G.b.top();
  const Vec2 e = (B5 - B1).normalized(), down(e.y(), -e.x());
  std::vector<Vec2> cand;
  for (const Piece& p : bottom(G)) {
    cand.push_back(p.p);
    if (p.arc && on_sweep(p, dm::atan2(down.y(), down.x()))) cand.push_back(p.c + p.r * down);
    cand.push_back(p.q);
  }
  if (!a_first) std::reverse(cand.begin(), cand.end());
  Vec2 best = cand.front();
  double best_d = cross(best - B1, e);
  for (const Vec2& q : cand) {
    const double d = cross(q - B1, e);
    if (d > best_d + 1e-9) best = q, best_d = d;
  }
  return best;
}

Corner C(const Vec2& p, int face, CornerKind kind = CornerKind::Sharp, double size = 0) {
  return Corner{p, face, kind, size};
}

}  // namespace

JointSpec draw_groove(Joint joint, Rng& rng, const SensorDraw& sd, const Probabilities& p) {
  JointSpec s;
  s.joint = joint;
  auto param = [&](const char* name, double v) { s.params.emplace_back(name, v); };
  auto tag = [&](const char* name) { s.tags.push_back(name); };
  // Every value and coin is drawn whatever the probabilities, so changing one
  // leaves the draws that follow as they were.
  const double t_thin = rng.uniform(8, 15), t_thick = rng.uniform(20, 80);
  double angle = 0;
  switch (joint) {
    case Joint::Bevel: angle = rng.uniform(30, 50); break;
    case Joint::UGroove: angle = rng.uniform(8, 20); break;
    case Joint::JGroove: angle = rng.uniform(10, 25); break;
    default: angle = rng.uniform(40, 70); break;
  }
  auto optional = [&](const char* name, double lo, double hi) {
    const bool coin = rng.chance(p(name));
    const double v = rng.uniform(lo, hi);
    if (coin) tag(name);
    return coin ? v : 0.0;
  };
  s.root_face_mm = optional("root_face", 0.2, 3.0);
  s.gap_mm = optional("gap", 0.1, 3.0);
  const double mismatch_sign = rng.sign();
  s.mismatch_mm = mismatch_sign * optional("mismatch", 0.1, 2.0);
  const double radius = rng.uniform(3, 8);
  const bool passes_coin = rng.chance(p("passes"));
  s.layer_mm = rng.uniform(2, 5);
  s.crown_mm = rng.uniform(-0.5, 1.5);
  const double passes_fraction = rng.uniform();
  const bool ripples_coin = rng.chance(p("bead_ripples"));
  const double ripple = rng.uniform(0.05, 0.2), ripple_wl = rng.uniform(2, 6), ripple_phase = rng.uniform(0, 2 * kPi);
  s.backing = rng.chance(p("backing_bar"));
  s.backing_width_mm = rng.uniform(20, 40);
  s.backing_thickness_mm = rng.uniform(3, 8);
  s.backing_offset_mm = rng.uniform(-3, 3);
  const bool rounded = rng.chance(p("rounded_edges"));
  const double edge_size = rng.uniform(0.5, 2.0);

  const double thickness = sd.thick ? t_thick : t_thin;
  if (sd.thick) tag("thick");
  s.angle_deg = angle;
  s.depth_mm = thickness - s.root_face_mm;
  const double D = s.depth_mm;
  // U and J: the arc ends at least 1 mm below the top.
  if (joint == Joint::UGroove || joint == Joint::JGroove) {
    const double beta = rad(joint == Joint::UGroove ? angle / 2 : angle);
    const double r_max = (D - 1.0) / (1.0 - dm::sin(beta));
    s.radius_mm = std::min(radius, r_max);
    if (radius > r_max) tag("radius_limited");
  }
  // Beads: the fill stays at least 2 mm below the lower top, the last pass at
  // least on the higher root edge.
  const double room = D + std::min(0.0, s.mismatch_mm) - 2.0 - std::max(0.0, s.crown_mm);
  const int n_max = static_cast<int>(std::floor(room / s.layer_mm));
  s.passes = passes_coin && n_max >= 1 ? 1 + std::min(n_max - 1, static_cast<int>(passes_fraction * n_max)) : 0;
  if (s.passes > 0) {
    tag("passes");
    // The cap's sagitta at most a quarter of its chord (a bead wets the walls,
    // it does not overhang them).
    Groove flat = groove_of(s);
    const double chord = flat.toe_b.x() - flat.toe_a.x(), limit = 0.25 * chord;
    if (std::abs(s.crown_mm) > limit) {
      s.crown_mm = std::clamp(s.crown_mm, -limit, limit);
      tag("crown_limited");
    }
    if (ripples_coin) {
      s.ripple_mm = ripple;
      s.ripple_wavelength_mm = ripple_wl;
      s.ripple_phase = ripple_phase;
      tag("bead_ripples");
    }
  }
  if (rounded) {
    s.edge = {CornerKind::Round, std::min(edge_size, 0.4 * D)};
    tag("rounded_edges");
  }
  if (s.backing) tag("backing_bar");
  param("thickness_mm", thickness);
  param("included_angle_deg", angle);
  param("root_face_mm", s.root_face_mm);
  param("depth_joint_mm", D);
  param("radius_mm", s.radius_mm);
  param("passes", s.passes);
  param("layer_mm", s.passes > 0 ? s.layer_mm : 0.0);
  param("crown_mm", s.passes > 0 ? s.crown_mm : 0.0);
  param("fill_level_mm", s.passes * s.layer_mm);
  param("ripple_mm", s.ripple_mm);
  param("edge_size_mm", s.edge.kind == CornerKind::Sharp ? 0.0 : s.edge.size_mm);
  param("gap_joint_mm", s.gap_mm);
  param("mismatch_joint_mm", s.mismatch_mm);
  return s;
}

void fit_groove_sensor(SensorDraw& sd, JointSpec& s, const Options& o) {
  const Groove G = groove_of(s);
  const Vec2 track = track_point(G, Affine{});
  const Vec2 B1 = G.a.top(), B5 = G.b.top();
  // What must be seen: the groove and 10 mm of each top, rolled up to 15
  // degrees (a top 15 degrees up comes nearer by sin 15 of its distance).
  const double w = std::max(track.x() - B1.x(), B5.x() - track.x()) + 10.0;
  const double h = std::max(B1.y(), B5.y()) - track.y() + 0.27 * w + 1.0;
  const double f = sd.nominal_standoff_mm / sd.standoff_mm;
  const double s_drawn = sd.standoff_mm, fan_drawn = sd.sensor.fan_deg;
  double standoff = sd.standoff_mm;
  if (o.standoff_mm <= 0) {
    // The measuring range (0.6-1.4 x nominal) must reach the tops: raise the standoff.
    standoff = std::max(standoff, h / (1.0 - 0.62 * f));
    // Then the field at the tops (with the placement's margins): raise it up to
    // the top of its range (400 mm thick, 250 mm thin)...
    const double hi = sd.thick ? 400.0 : 250.0;
    const double need = h + 1.2 * w / dm::tan(rad(sd.sensor.fan_deg / 2));
    if (need > standoff) standoff = std::max(standoff, std::min(need, hi));
  }
  // ... and widen the fan for the rest (at most 80 degrees).
  const double tan_need = 1.2 * w / std::max(standoff - h, 1.0);
  if (tan_need > dm::tan(rad(sd.sensor.fan_deg / 2)))
    sd.sensor.fan_deg = std::min(80.0, 2.0 * deg(dm::atan2(tan_need, 1.0)) + 1.0);
  if (standoff != s_drawn) {
    s.tags.push_back("standoff_raised");
    sd.standoff_mm = standoff;
    sd.nominal_standoff_mm = standoff * f;
    sd.sensor.z_near_mm = 0.6 * sd.nominal_standoff_mm;
    sd.sensor.z_far_mm = 1.4 * sd.nominal_standoff_mm;
    sd.baseline_mm = sd.nominal_standoff_mm * dm::tan(rad(sd.triangulation_deg));
  }
  if (sd.sensor.fan_deg != fan_drawn) s.tags.push_back("fan_widened");
  s.params.emplace_back("standoff_drawn_mm", s_drawn);
  s.params.emplace_back("fan_drawn_deg", fan_drawn);
  s.plate_half_length_mm = 4.0 * sd.standoff_mm + 100.0;
}

Section build_groove_section(const JointSpec& s, const DecoySpec& decoy) {
  const Groove G = groove_of(s);
  const double L = s.plate_half_length_mm, rf = G.rf, m = G.m, D = G.D;
  const double toe_a = G.passes > 0 ? G.toe_h_a() : kNaN, toe_b = G.passes > 0 ? G.toe_h_b() : kNaN;
  const auto wa = G.a.up_to_top(toe_a, kFaceArc1, kFaceBevel1);
  const auto wb = G.b.up_to_top(toe_b, kFaceArc2, kFaceBevel2);
  Section sec;
  // Plate a: bottom, land (root face), wall up, top edge, top.
  std::vector<Corner> pa = {C(Vec2(-L, -rf), kFaceOther), C(Vec2(-G.g / 2, -rf), kFaceRoot1)};
  for (const auto& [q, face] : wa) pa.push_back(C(q, face));
  pa.push_back(C(G.a.top(), kFaceTop1, s.edge.kind, s.edge.size_mm));
  if (decoy.on) add_notch_decoy(pa, G.a.top().x(), D, decoy, sec);
  pa.push_back(C(Vec2(-L, D), kFaceOther));
  sec.solids.push_back(make_polygon(pa));
  // Plate b (raised by the mismatch): bottom, far end, top, top edge, wall down, land.
  std::vector<Corner> pb = {C(Vec2(G.g / 2, m - rf), kFaceOther), C(Vec2(L, m - rf), kFaceOther),
                            C(Vec2(L, m + D), kFaceTop2), C(G.b.top(), kFaceBevel2, s.edge.kind, s.edge.size_mm)};
  for (std::size_t i = wb.size(); i-- > 0;) {
    // The edge leaving a vertex downwards has the face of the edge below it.
    const int face = i > 0 ? wb[i - 1].second : kFaceRoot2;
    pb.push_back(C(wb[i].first, face));
  }
  sec.solids.push_back(make_polygon(pb));
  if (s.backing) {
    const double top_z = std::min(-rf, m - rf);
    const double y0 = s.backing_offset_mm - s.backing_width_mm / 2, y1 = y0 + s.backing_width_mm;
    sec.solids.push_back(make_polygon({C(Vec2(y0, top_z - s.backing_thickness_mm), kFaceOther),
                                       C(Vec2(y1, top_z - s.backing_thickness_mm), kFaceOther),
                                       C(Vec2(y1, top_z), kFaceBacking), C(Vec2(y0, top_z), kFaceOther)}));
  }
  if (G.passes > 0) {
    // The weld metal: down wall a from its toe, the gap between the lands, up
    // wall b to its toe, and the cap back (its vertices every 0.2 mm or 1
    // degree, moved by the bead ripples, which fade out within 1 mm of the toes).
    std::vector<Corner> fill;
    fill.push_back(C(G.toe_a, kFaceOther));
    for (std::size_t i = wa.size(); i-- > 0;)
      if (wa[i].first.y() - G.a.root.y() < toe_a - 1e-12) fill.push_back(C(wa[i].first, kFaceOther));
    if (G.g > 0) {
      fill.push_back(C(Vec2(-G.g / 2, -rf), kFaceOther));
      fill.push_back(C(Vec2(G.g / 2, m - rf), kFaceOther));
    }
    for (const auto& [q, face] : wb)
      if (q.y() - G.b.root.y() < toe_b - 1e-12) fill.push_back(C(q, kFaceOther));
    fill.push_back(C(G.toe_b, kFaceCap));
    const Piece cap = bottom(G).front();
    const double length = cap.arc ? cap.r * std::abs(cap.dt) : (cap.q - cap.p).norm();
    const int n = std::max(2, static_cast<int>(std::ceil(std::max(length / 0.2, cap.arc ? deg(std::abs(cap.dt)) : 0.0))));
    for (int k = n - 1; k >= 1; --k) {  // from b back to a
      const double f = static_cast<double>(k) / n;
      Vec2 q, normal(0, 1);
      if (cap.arc) {
        const double t = cap.t0 + f * cap.dt;
        const Vec2 u(dm::cos(t), dm::sin(t));
        q = cap.c + cap.r * u;
        normal = G.crown > 0 ? u : Vec2(-u);
      } else {
        q = cap.p + f * (cap.q - cap.p);
      }
      if (s.ripple_mm > 0) {
        const double arc_s = f * length, x = std::clamp(std::min(arc_s, length - arc_s), 0.0, 1.0);
        const double taper = x * x * (3 - 2 * x);
        q += taper * s.ripple_mm * dm::sin(2 * kPi * arc_s / s.ripple_wavelength_mm + s.ripple_phase) * normal;
      }
      fill.push_back(C(q, kFaceCap));
    }
    sec.solids.push_back(make_polygon(fill, 2.0));
  }
  sec.view_dir = Vec2(0, -1);
  sec.track = track_point(G, Affine{});
  sec.halfwidth_mm = std::max(sec.track.x() - G.a.top().x(), G.b.top().x() - sec.track.x()) + 10.0;
  sec.top_height_mm = std::max(G.a.top().y(), G.b.top().y()) - sec.track.y();
  sec.pts["top_a"] = G.a.top();
  sec.pts["top_b"] = G.b.top();
  sec.pts["toe_a"] = G.toe_a;
  sec.pts["toe_b"] = G.toe_b;
  sec.pts["root_a"] = G.a.root;
  sec.pts["root_b"] = G.b.root;
  sec.defining = {"toe_a", "toe_b"};
  return sec;
}

void compute_groove_truth(const JointSpec& s, const Section&, const Affine& map, Truth& t) {
  const Groove G = groove_of(s);
  auto scan_u = [](const Vec2& p) { return p.x() / p.y(); };
  // Side a of the truth: the plate scanned first (the tracker's a).
  const bool a_first = scan_u(map(G.a.top() - Vec2(5, 0))) < scan_u(map(G.b.top() + Vec2(5, 0)));
  const Wall& wa = a_first ? G.a : G.b;
  const Wall& wb = a_first ? G.b : G.a;
  const Vec2 toe_a = map(a_first ? G.toe_a : G.toe_b), toe_b = map(a_first ? G.toe_b : G.toe_a);
  const Vec2 top_a = map(wa.top()), top_b = map(wb.top());
  const Vec2 track = map(track_point(G, map)), lowest = map(fill_lowest(G, a_first));
  auto wall_angle = [&](const Wall& w) {  // the straight part (down from the top edge) against the top line over the groove
    const Vec2 lower = w.kind == WallKind::Curved ? w.tangent() : w.root;
    const Vec2 down = map.dir(lower - w.top()), over = map.dir(Vec2(-w.side, 0));
    return deg(dm::acos(std::clamp(down.dot(over), -1.0, 1.0)));
  };
  const Vec2 plate = map.dir(Vec2(1, 0));
  Vec2 up(-plate.y(), plate.x());  // the plates' normal towards the sensor
  if (up.y() > 0) up = -up;
  t.track_y_mm = track.x();
  t.track_z_mm = track.y();
  t.wall_angle_a_deg = wall_angle(wa);
  t.wall_angle_b_deg = wall_angle(wb);
  t.angle_deg = 180.0 - t.wall_angle_a_deg - t.wall_angle_b_deg;
  t.top_width_mm = (top_b - top_a).norm();
  t.fill_lowest_y_mm = lowest.x();
  t.fill_lowest_z_mm = lowest.y();
  t.depth_mm = std::abs(cross((top_b - top_a).normalized(), lowest - top_a));
  t.area_mm2 = enclosed_area(outline(G)) * std::abs(map.A(0, 0) * map.A(1, 1) - map.A(0, 1) * map.A(1, 0));
  t.gap_mm = G.g == 0 ? 0.0 : std::abs((map(wb.root) - map(wa.root)).dot(plate));
  t.mismatch_mm = G.m == 0 ? 0.0 : up.dot(top_b - top_a);
  t.passes = G.passes;
  t.params.emplace_back("a_is_joint_side_a", a_first ? 1 : 0);
  auto bp = [&](const char* name, const Vec2& p) { t.break_points.push_back({name, {p.x(), p.y()}}); };
  bp("B1", top_a);
  bp("B2", toe_a);
  bp("B3", track);
  bp("B4", toe_b);
  bp("B5", top_b);
}

}  // namespace vts_corpus::detail
