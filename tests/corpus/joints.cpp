// The five joints: drawing their parameters, building their cross-sections in
// the joint frame (y across the seam, z up, root at the origin), and their
// truth in the sensor frame (docs/JOINTS.md, docs/CELLS.md).
#include "internal.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace vts_corpus::detail {

namespace {

using CK = CornerKind;

void param(JointSpec& s, const char* name, double value) { s.params.emplace_back(name, value); }

// Rounded (any joint) or chamfered (where allowed) plate edges, sized 0.5-2 mm.
EdgeStyle draw_edge(Rng& rng, const Probabilities& p, bool allow_chamfer, double max_size_mm, JointSpec& s) {
  const double e = rng.uniform();
  const double size = std::min(rng.uniform(0.5, 2.0), max_size_mm);
  EdgeStyle style;
  if (e < p("rounded_edges")) {
    style = {CK::Round, size};
    s.tags.push_back("rounded_edges");
  } else if (allow_chamfer && e >= 1.0 - p("chamfered_edges")) {
    style = {CK::Chamfer, size};
    s.tags.push_back("chamfered_edges");
  }
  param(s, "edge_size_mm", style.kind == CK::Sharp ? 0.0 : style.size_mm);
  return style;
}

// Draws a value and a coin every time, so that changing one probability never
// shifts the draws that follow.
double optional_value(Rng& rng, double probability, double lo, double hi, bool* on = nullptr) {
  const bool coin = rng.chance(probability);
  const double v = rng.uniform(lo, hi);
  if (on) *on = coin;
  return coin ? v : 0.0;
}

Corner C(const Vec2& p, int face, EdgeStyle style = {}) { return Corner{p, face, style.kind, style.size_mm}; }
Corner C(double y, double z, int face, EdgeStyle style = {}) { return C(Vec2(y, z), face, style); }

Vec2 rot(const Vec2& v, double angle_rad) {
  const double c = dm::cos(angle_rad), s = dm::sin(angle_rad);
  return {c * v.x() - s * v.y(), s * v.x() + c * v.y()};
}

// Intersection of the lines p1 + s d1 and p2 + s d2.
Vec2 intersect(const Vec2& p1, const Vec2& d1, const Vec2& p2, const Vec2& d2) {
  const double den = cross(d1, d2);
  const double s = cross(p2 - p1, d2) / den;
  return p1 + s * d1;
}

double dist_to_line(const Vec2& q, const Vec2& p, const Vec2& d) {
  return std::abs(cross(d.normalized(), q - p));
}

double angle_between_deg(const Vec2& a, const Vec2& b) {
  return deg(dm::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0)));
}

// A backing bar: its top against the plates' bottoms, centred under the gap.
Polygon backing_bar(const JointSpec& s, double top_z) {
  const double y0 = s.backing_offset_mm - s.backing_width_mm / 2, y1 = y0 + s.backing_width_mm;
  return make_polygon({C(y0, top_z - s.backing_thickness_mm, kFaceOther), C(y1, top_z - s.backing_thickness_mm, kFaceOther),
                       C(y1, top_z, kFaceBacking), C(y0, top_z, kFaceOther)});
}

// A circle that contains both points with a 0.2 mm margin (a tack weld must
// cover the root it sits in).
double covering_radius(const Vec2& centre, double r, const Vec2& a, const Vec2& b) {
  const double need = std::max((a - centre).norm(), (b - centre).norm()) + 0.2;
  return std::max(r, need);
}

int circle_segments(double r_mm) { return std::clamp(static_cast<int>(std::ceil(2 * kPi * r_mm / 0.25)), 36, 256); }

}  // namespace

void add_notch_decoy(std::vector<Corner>& p1, double edge_y, double top_z, const DecoySpec& decoy, Section& sec) {
  const double dn = 1.0 + decoy.a_mm, wn = dn * dm::tan(rad(30 + 15 * decoy.b_mm));
  const double d = std::max(decoy.distance_mm, -edge_y + wn + 3.0);
  p1.push_back(C(-d + wn, top_z, kFaceDecoy));
  p1.push_back(C(-d, top_z - dn, kFaceDecoy));
  p1.push_back(C(-d - wn, top_z, kFaceTop1));
  sec.has_decoy = true;
  sec.decoy_point = Vec2(-d, top_z - dn);
}

JointSpec draw_joint(Joint joint, Rng& rng, const SensorDraw& sd, const Probabilities& p) {
  if (is_groove(joint)) return draw_groove(joint, rng, sd, p);
  JointSpec s;
  s.joint = joint;
  const double D = sd.standoff_mm;
  // Long enough to leave the field of view and the measuring range on every pose.
  s.plate_half_length_mm = 4.0 * D + 100.0;
  bool on = false;
  switch (joint) {
    case Joint::Fillet: {
      s.angle_deg = rng.uniform(60, 120);
      s.gap_mm = optional_value(rng, p("gap"), 0.2, 2.0, &on);
      if (on) s.tags.push_back("gap");
      s.t1_mm = rng.uniform(5, 20);  // flange
      s.t2_mm = rng.uniform(3, 20);  // web
      s.web_height_mm = rng.uniform(0.6, 1.1) * D * dm::sin(rad(s.angle_deg / 2));
      s.edge = draw_edge(rng, p, true, 0.4 * s.t2_mm, s);
      s.tack = rng.chance(p("tack_weld"));
      s.tack_a_mm = rng.uniform(1.5, 3.5);  // radius
      s.tack_c = rng.uniform(-0.3, 0.3);    // centre along the bisector, in radii
      param(s, "open_angle_deg", s.angle_deg);
      param(s, "flange_thickness_mm", s.t1_mm);
      param(s, "web_thickness_mm", s.t2_mm);
      param(s, "web_height_mm", s.web_height_mm);
      break;
    }
    case Joint::Corner: {
      s.angle_deg = rng.uniform(70, 165);
      s.gap_mm = optional_value(rng, p("gap"), 0.2, 2.0, &on);
      if (on) s.tags.push_back("gap");
      s.t1_mm = rng.uniform(3, 15);
      s.t2_mm = rng.chance(0.5) ? s.t1_mm : rng.uniform(3, 15);
      s.edge = draw_edge(rng, p, true, 0.4 * std::min(s.t1_mm, s.t2_mm), s);
      param(s, "inside_angle_deg", s.angle_deg);
      param(s, "thickness1_mm", s.t1_mm);
      param(s, "thickness2_mm", s.t2_mm);
      break;
    }
    case Joint::Lap: {
      s.t1_mm = rng.uniform(3, 15);  // lower
      s.t2_mm = rng.uniform(1, 10);  // upper
      s.gap_mm = optional_value(rng, p("gap"), 0.1, 1.5, &on);
      if (on) s.tags.push_back("gap");
      s.tilt_deg = optional_value(rng, p("tilt"), 0.5, 3.0, &on);
      if (on) s.tags.push_back("tilt");
      s.edge = draw_edge(rng, p, true, 0.4 * s.t2_mm, s);
      param(s, "lower_thickness_mm", s.t1_mm);
      param(s, "upper_thickness_mm", s.t2_mm);
      param(s, "tilt_deg", s.tilt_deg);
      break;
    }
    case Joint::Butt: {
      s.gap_mm = optional_value(rng, p("gap"), 0.1, 3.0, &on);
      if (on) s.tags.push_back("gap");
      const double mismatch_sign = rng.sign();
      s.mismatch_mm = mismatch_sign * optional_value(rng, p("mismatch"), 0.1, 2.0, &on);
      if (on) s.tags.push_back("mismatch");
      s.t1_mm = rng.uniform(3, 20);
      const double t2 = rng.uniform(3, 20);
      if (rng.chance(p("unequal_thickness"))) {
        s.t2_mm = t2;
        s.tags.push_back("unequal_thickness");
      } else {
        s.t2_mm = s.t1_mm;
      }
      s.backing = rng.chance(p("backing_bar"));
      s.backing_width_mm = rng.uniform(20, 40);
      s.backing_thickness_mm = rng.uniform(3, 8);
      s.backing_offset_mm = rng.uniform(-3, 3);
      s.edge = draw_edge(rng, p, true, 0.4 * std::min(s.t1_mm, s.t2_mm), s);
      s.tack = rng.chance(p("tack_weld"));
      s.tack_a_mm = rng.uniform(0, 1);      // cap width, as a fraction of its range
      s.tack_b_mm = rng.uniform(0.5, 1.5);  // cap height
      // Coplanar, closed and sharp shows nothing: open the gap.
      const double forced_gap = rng.uniform(0.3, 3.0);
      if (s.gap_mm == 0 && s.mismatch_mm == 0 && s.edge.kind == CK::Sharp) {
        s.gap_mm = forced_gap;
        s.tags.push_back("gap");
      }
      param(s, "thickness1_mm", s.t1_mm);
      param(s, "thickness2_mm", s.t2_mm);
      break;
    }
    case Joint::VGroove: {
      s.angle_deg = rng.uniform(40, 90);
      s.root_face_mm = optional_value(rng, p("root_face"), 0.2, 2.0, &on);
      if (on) s.tags.push_back("root_face");
      s.gap_mm = optional_value(rng, p("gap"), 0.1, 2.0, &on);
      if (on) s.tags.push_back("gap");
      const double mismatch_sign = rng.sign();
      s.mismatch_mm = mismatch_sign * optional_value(rng, p("mismatch"), 0.1, 1.5, &on);
      if (on) s.tags.push_back("mismatch");
      const double thickness = rng.uniform(6, 25);
      // A groove much wider than the field of view, or a plate top outside the
      // measuring range, is no profile of a v-groove: limit the depth.
      const double tf = dm::tan(rad(sd.sensor.fan_deg / 2)), th = dm::tan(rad(s.angle_deg / 2));
      const double limit = std::min(0.3 * D, (1.2 * D * tf - s.gap_mm) / (2 * th + 1.2 * tf));
      s.depth_mm = std::max(std::min(thickness - s.root_face_mm, limit), 3.0);
      if (s.depth_mm < thickness - s.root_face_mm) s.tags.push_back("thickness_limited");
      s.backing = rng.chance(p("backing_bar"));
      s.backing_width_mm = rng.uniform(20, 40);
      s.backing_thickness_mm = rng.uniform(3, 8);
      s.backing_offset_mm = rng.uniform(-3, 3);
      s.edge = draw_edge(rng, p, false, 0.4 * s.depth_mm, s);
      s.tack = rng.chance(p("tack_weld"));
      s.tack_a_mm = rng.uniform(1.5, 3.0);  // radius
      s.tack_c = rng.uniform(0.3, 1.5);     // bump top above the root, mm
      param(s, "included_angle_deg", s.angle_deg);
      param(s, "root_face_mm", s.root_face_mm);
      param(s, "thickness_mm", s.depth_mm + s.root_face_mm);
      break;
    }
    case Joint::Bevel:
    case Joint::UGroove:
    case Joint::JGroove:
    case Joint::VGrooveThick: break;  // draw_groove
  }
  if (s.backing) s.tags.push_back("backing_bar");
  if (s.tack) s.tags.push_back("tack_weld");
  param(s, "gap_joint_mm", s.gap_mm);
  param(s, "mismatch_joint_mm", s.mismatch_mm);
  return s;
}

DecoySpec draw_decoy(Joint, Rng& rng, const SensorDraw&) {
  DecoySpec d;
  d.distance_mm = rng.uniform(20, 40);
  d.a_mm = rng.uniform(0, 1);
  d.b_mm = rng.uniform(0, 1);
  d.c = rng.uniform(0, 1);
  d.kind = rng.uniform_int(0, 1);
  return d;
}

Section build_section(const JointSpec& s, const DecoySpec& decoy) {
  if (is_groove(s.joint)) return build_groove_section(s, decoy);
  Section sec;
  const double L = s.plate_half_length_mm;
  const double g = s.gap_mm;
  switch (s.joint) {
    case Joint::Fillet: {
      // Open side towards +y: the flange's top (z = 0) and the web's open face
      // through the root at angle a; the web lifted by the gap, its bottom cut
      // parallel to the flange.
      const double a = rad(s.angle_deg);
      const Vec2 e_w(dm::cos(a), dm::sin(a)), n_open(dm::sin(a), -dm::cos(a));
      const Vec2 A(g * dm::cos(a) / dm::sin(a), g);
      const Vec2 B = A - s.t2_mm * n_open - (s.t2_mm * dm::cos(a) / dm::sin(a)) * e_w;
      const Vec2 up = (s.web_height_mm / dm::sin(a)) * e_w;
      sec.solids.push_back(make_polygon({C(-L, -s.t1_mm, kFaceOther), C(L, -s.t1_mm, kFaceOther),
                                         C(L, 0, kFaceFlangeTop), C(-L, 0, kFaceOther)}));
      sec.solids.push_back(make_polygon({C(B, kFaceWebBottom, s.edge), C(A, kFaceWebOpen, s.edge),
                                         C(A + up, kFaceOther), C(B + up, kFaceOther)}));
      const Vec2 bisector(dm::cos(a / 2), dm::sin(a / 2));
      if (s.tack) {
        const Vec2 c = s.tack_c * s.tack_a_mm * bisector;
        sec.solids.push_back(make_circle(c, s.tack_a_mm, kFaceTack, circle_segments(s.tack_a_mm)));
      }
      if (decoy.on) {  // a rib on the flange: a second inside corner
        const double d = decoy.distance_mm, w = 2 + 3 * decoy.a_mm, h = 3 + 5 * decoy.b_mm;
        sec.solids.push_back(make_polygon({C(d, -0.5, kFaceOther), C(d + w, -0.5, kFaceDecoy),
                                           C(d + w, h, kFaceDecoy), C(d, h, kFaceDecoy)}));
        sec.has_decoy = true;
        sec.decoy_point = Vec2(d, 0);
      }
      sec.view_dir = -bisector;
      // A 60-degree fillet rolled 15 degrees shows one plate at 15 degrees to the
      // optical axis: nearly along the rays, out of range or shadowed entirely.
      sec.max_roll_deg = std::clamp(s.angle_deg / 2 - 20, 0.0, 15.0);
      sec.open_angle_deg = s.angle_deg;
      sec.track = Vec2(0, 0);
      sec.halfwidth_mm = 5;
      sec.pts["root"] = Vec2(0, 0);
      sec.pts["web_edge"] = A;
      sec.dirs["flange"] = Vec2(1, 0);
      sec.dirs["web"] = e_w;
      sec.defining = {"root"};
      break;
    }
    case Joint::Corner: {
      // Outer faces fall away from the edges at +-h from -z; mitred ends on
      // y = -+g/2 (a notch between the edges when g > 0).
      const double h = rad(s.angle_deg / 2);
      const Vec2 d1(-dm::sin(h), -dm::cos(h)), d2(dm::sin(h), -dm::cos(h));
      const Vec2 n1(dm::cos(h), -dm::sin(h)), n2(-dm::cos(h), -dm::sin(h));  // into the material
      const Vec2 E1(-g / 2, 0), E2(g / 2, 0);
      const Vec2 I1 = E1 + s.t1_mm * n1 + (s.t1_mm * dm::cos(h) / dm::sin(h)) * d1;
      const Vec2 I2 = E2 + s.t2_mm * n2 + (s.t2_mm * dm::cos(h) / dm::sin(h)) * d2;
      if (decoy.on) {  // a chamfered step down on plate 1's outer face: a second outside edge
        const double d = decoy.distance_mm, hs = std::min(1.0 + 2.0 * decoy.a_mm, 0.5 * s.t1_mm);
        const double chamfer = 0.5 + decoy.b_mm;
        const Vec2 P1 = E1 + d * d1, P2 = P1 + hs * n1;
        sec.solids.push_back(make_polygon({C(E1, kFaceOuter1, s.edge), C(P1, kFaceDecoy, {CK::Chamfer, chamfer}),
                                           C(P2, kFaceDecoy), C(E1 + L * d1 + hs * n1, kFaceOther),
                                           C(E1 + L * d1 + s.t1_mm * n1, kFaceOther), C(I1, kFaceEnd1)}));
        sec.has_decoy = true;
        sec.decoy_point = P1;
      } else {
        sec.solids.push_back(make_polygon({C(E1, kFaceOuter1, s.edge), C(E1 + L * d1, kFaceOther),
                                           C(E1 + L * d1 + s.t1_mm * n1, kFaceOther), C(I1, kFaceEnd1)}));
      }
      sec.solids.push_back(make_polygon({C(E2, kFaceEnd2, s.edge), C(I2, kFaceOther),
                                         C(E2 + L * d2 + s.t2_mm * n2, kFaceOther), C(E2 + L * d2, kFaceOuter2)}));
      sec.view_dir = Vec2(0, -1);
      sec.track = Vec2(0, 0);
      sec.halfwidth_mm = g / 2 + 5;
      sec.pts["edge1"] = E1;
      sec.pts["edge2"] = E2;
      sec.pts["apex"] = intersect(E1, d1, E2, d2);
      sec.pts["ref1"] = E1 + 5 * d1;
      sec.pts["ref2"] = E2 + 5 * d2;
      sec.dirs["face1"] = d1;
      sec.dirs["face2"] = d2;
      sec.defining = {"edge1", "edge2"};
      break;
    }
    case Joint::Lap: {
      // Upper plate on the -y side, its edge at y = 0 facing +y, lifted by the
      // gap and tilted about its bottom edge (its far end rising).
      const double tu = s.t2_mm;
      const Vec2 Eb(0, g);
      const double tilt = -rad(s.tilt_deg);
      auto up = [&](double y, double z) -> Vec2 { return Eb + rot(Vec2(y, z) - Eb, tilt); };
      sec.solids.push_back(make_polygon({C(-L, -s.t1_mm, kFaceOther), C(L, -s.t1_mm, kFaceOther),
                                         C(L, 0, kFaceLowerTop), C(-L, 0, kFaceOther)}));
      sec.solids.push_back(make_polygon({C(up(0, g), kFaceUpperEdge), C(up(0, g + tu), kFaceUpperTop, s.edge),
                                         C(up(-L, g + tu), kFaceOther), C(up(-L, g), kFaceUpperBottom)}));
      if (decoy.on) {
        const double d = decoy.distance_mm, ts = 0.5 + 2.5 * decoy.a_mm;
        if (decoy.kind == 0) {  // a shim on the upper plate: its edge a second step
          sec.solids.push_back(make_polygon({C(up(-d, g + tu - 0.2), kFaceDecoy), C(up(-d, g + tu + ts), kFaceDecoy),
                                             C(up(-L, g + tu + ts), kFaceOther), C(up(-L, g + tu - 0.2), kFaceOther)}));
          sec.decoy_point = up(-d, g + tu);
        } else {  // a strip on the lower plate, its far edge a step the same way
          const double w = std::min(10 + 10 * decoy.b_mm, d - 8);  // clear of the joint
          sec.solids.push_back(make_polygon({C(d - w, -0.2, kFaceOther), C(d, -0.2, kFaceDecoy),
                                             C(d, ts, kFaceDecoy), C(d - w, ts, kFaceDecoy)}));
          sec.decoy_point = Vec2(d, 0);
        }
        sec.has_decoy = true;
      }
      const Vec2 Eb_t = up(0, g), Et_t = up(0, g + tu), face = rot(Vec2(0, 1), tilt);
      const Vec2 foot = Eb_t - (Eb_t.y() / face.y()) * face;
      sec.view_dir = Vec2(0, -1);
      sec.track = foot;
      sec.halfwidth_mm = 6;
      sec.pts["foot"] = foot;
      sec.pts["bottom_edge"] = Eb_t;
      sec.pts["top_edge"] = Et_t;
      sec.dirs["lower"] = Vec2(1, 0);  // from the foot away from the upper plate
      sec.dirs["face"] = face;
      sec.dirs["upper"] = rot(Vec2(-1, 0), tilt);
      sec.defining = {"top_edge"};
      break;
    }
    case Joint::Butt: {
      const double m = s.mismatch_mm;
      const Vec2 E1(-g / 2, 0), E2(g / 2, m);
      if (decoy.on) {  // a kerf in plate 1: through the plate or part way
        const double d = decoy.distance_mm, w = 1 + decoy.a_mm;
        const bool through = decoy.kind == 0;
        const double depth = through ? s.t1_mm : 1.0 + (0.6 * s.t1_mm - 1.0) * decoy.b_mm;
        if (through) {
          sec.solids.push_back(make_polygon({C(-d + w / 2, -s.t1_mm, kFaceOther), C(-g / 2, -s.t1_mm, kFaceEdge1),
                                             C(E1, kFaceTop1, s.edge), C(-d + w / 2, 0, kFaceDecoy)}));
          sec.solids.push_back(make_polygon({C(-L, -s.t1_mm, kFaceOther), C(-d - w / 2, -s.t1_mm, kFaceDecoy),
                                             C(-d - w / 2, 0, kFaceTop1), C(-L, 0, kFaceOther)}));
        } else {
          sec.solids.push_back(make_polygon({C(-L, -s.t1_mm, kFaceOther), C(-g / 2, -s.t1_mm, kFaceEdge1),
                                             C(E1, kFaceTop1, s.edge), C(-d + w / 2, 0, kFaceDecoy),
                                             C(-d + w / 2, -depth, kFaceDecoy), C(-d - w / 2, -depth, kFaceDecoy),
                                             C(-d - w / 2, 0, kFaceTop1), C(-L, 0, kFaceOther)}));
        }
        sec.has_decoy = true;
        sec.decoy_point = Vec2(-d, 0);
      } else {
        sec.solids.push_back(make_polygon({C(-L, -s.t1_mm, kFaceOther), C(-g / 2, -s.t1_mm, kFaceEdge1),
                                           C(E1, kFaceTop1, s.edge), C(-L, 0, kFaceOther)}));
      }
      sec.solids.push_back(make_polygon({C(g / 2, m - s.t2_mm, kFaceOther), C(L, m - s.t2_mm, kFaceOther),
                                         C(L, m, kFaceTop2), C(E2, kFaceEdge2, s.edge)}));
      if (s.backing) sec.solids.push_back(backing_bar(s, std::min(-s.t1_mm, m - s.t2_mm)));
      if (s.tack) {  // a cap over the gap: a circular segment s.tack_b_mm high
        const double width = std::max(3.0, g + 2.0) + (8.0 - std::max(3.0, g + 2.0)) * s.tack_a_mm;
        const double hc = s.tack_b_mm, r = (width * width / 4 + hc * hc) / (2 * hc);
        const Vec2 c(0, std::max(0.0, m) + hc - r);
        const double r2 = covering_radius(c, r, E1, E2);  // a cap over a step grows to cover the lower edge
        sec.solids.push_back(make_circle(c, r2, kFaceTack, circle_segments(r2)));
      }
      const bool lower1 = m >= 0;  // plate 1 is the lower one (farther from the sensor)
      sec.view_dir = Vec2(0, -1);
      sec.track = Vec2(0, lower1 ? 0.0 : m);
      sec.halfwidth_mm = g / 2 + 5;
      sec.pts["edge1"] = E1;
      sec.pts["edge2"] = E2;
      sec.pts["ref1"] = Vec2(-g / 2 - 5, 0);
      sec.pts["ref2"] = Vec2(g / 2 + 5, m);
      sec.pts["lower_edge"] = lower1 ? E1 : E2;
      sec.pts["higher_edge"] = lower1 ? E2 : E1;
      sec.dirs["plate"] = Vec2(1, 0);
      sec.defining = {"edge1", "edge2"};
      break;
    }
    case Joint::VGroove: {
      const double m = s.mismatch_mm, rf = s.root_face_mm, D = s.depth_mm;
      const double th = dm::tan(rad(s.angle_deg / 2));
      const Vec2 R1(-g / 2, 0), R2(g / 2, m);
      const Vec2 T1(-g / 2 - D * th, D), T2(g / 2 + D * th, m + D);
      std::vector<Corner> p1 = {C(-L, -rf, kFaceOther), C(-g / 2, -rf, kFaceRoot1), C(R1, kFaceBevel1),
                                C(T1, kFaceTop1, s.edge)};
      if (decoy.on) add_notch_decoy(p1, T1.x(), D, decoy, sec);
      p1.push_back(C(-L, D, kFaceOther));
      sec.solids.push_back(make_polygon(p1));
      sec.solids.push_back(make_polygon({C(T2, kFaceBevel2, s.edge), C(R2, kFaceRoot2), C(g / 2, m - rf, kFaceOther),
                                         C(L, m - rf, kFaceOther), C(L, m + D, kFaceTop2)}));
      if (s.backing) sec.solids.push_back(backing_bar(s, std::min(-rf, m - rf)));
      if (s.tack) {  // a bump filling the root, its top s.tack_c above the lower root edge
        const double r = s.tack_a_mm;
        const Vec2 c(0, std::min(0.0, m) + s.tack_c - r);
        const double r2 = covering_radius(c, r, R1, R2);
        sec.solids.push_back(make_circle(c, r2, kFaceTack, circle_segments(r2)));
      }
      const bool lower1 = m >= 0;
      sec.view_dir = Vec2(0, -1);
      sec.track = Vec2(0, lower1 ? 0.0 : m);
      sec.halfwidth_mm = g / 2 + D * th + 5;
      sec.pts["root1"] = R1;
      sec.pts["root2"] = R2;
      sec.pts["top1"] = T1;
      sec.pts["top2"] = T2;
      sec.pts["ref1"] = T1 + Vec2(-5, 0);
      sec.pts["ref2"] = T2 + Vec2(5, 0);
      sec.pts["lower_root"] = lower1 ? R1 : R2;
      sec.dirs["plate"] = Vec2(1, 0);
      sec.dirs["bevel1"] = T1 - R1;
      sec.dirs["bevel2"] = T2 - R2;
      sec.defining = {"root1", "root2"};
      break;
    }
    case Joint::Bevel:
    case Joint::UGroove:
    case Joint::JGroove:
    case Joint::VGrooveThick: break;  // build_groove_section
  }
  return sec;
}

void compute_truth(const JointSpec& s, const Section& sec, const Affine& map, Truth& t) {
  if (is_groove(s.joint)) return compute_groove_truth(s, sec, map, t);
  auto P = [&](const char* name) { return map(sec.pts.at(name)); };
  auto Dir = [&](const char* name) { return map.dir(sec.dirs.at(name)); };
  auto bp = [&](const char* name, const Vec2& p) { t.break_points.push_back({name, {p.x(), p.y()}}); };
  // Scan order: columns run with increasing y/z.
  auto scan_u = [](const Vec2& p) { return p.x() / p.y(); };
  const Vec2 track = map(sec.track);
  t.track_y_mm = track.x();
  t.track_z_mm = track.y();
  switch (s.joint) {
    case Joint::Fillet: {
      const Vec2 root = P("root"), web_edge = P("web_edge"), flange = Dir("flange"), web = Dir("web");
      t.angle_deg = angle_between_deg(flange, web);
      t.gap_mm = dist_to_line(web_edge, root, flange);
      bp("B1", root);
      bp("B3", web_edge);
      break;
    }
    case Joint::Corner: {
      Vec2 e1 = P("edge1"), e2 = P("edge2");
      if (scan_u(P("ref1")) > scan_u(P("ref2"))) std::swap(e1, e2);
      t.gap_mm = (e2 - e1).norm();
      t.angle_deg = angle_between_deg(Dir("face1"), Dir("face2"));
      bp("B1", e1);
      bp("B2", P("apex"));
      bp("B3", e2);
      break;
    }
    case Joint::Lap: {
      const Vec2 foot = P("foot"), lower = Dir("lower");
      t.step_mm = dist_to_line(P("top_edge"), foot, lower);
      t.gap_mm = dist_to_line(P("bottom_edge"), foot, lower);
      t.angle_deg = angle_between_deg(lower, Dir("face"));
      bp("B1", foot);
      bp("B2", P("bottom_edge"));
      bp("B3", P("top_edge"));
      break;
    }
    case Joint::Butt: {
      const Vec2 plate = Dir("plate"), lower = P("lower_edge"), higher = P("higher_edge");
      Vec2 e1 = P("edge1"), e2 = P("edge2");
      if (scan_u(P("ref1")) > scan_u(P("ref2"))) std::swap(e1, e2);
      // The gap centre on the lower plate's line, projected in the sensor frame
      // (the affine map does not keep right angles).
      const Vec2 centre = lower + (0.5 * (e1 + e2) - lower).dot(plate) * plate;
      t.track_y_mm = centre.x();
      t.track_z_mm = centre.y();
      t.gap_mm = std::abs((e2 - e1).dot(plate));
      t.mismatch_mm = s.mismatch_mm == 0 ? 0.0 : dist_to_line(higher, lower, plate);
      // The perpendicular distance between the edge faces: differs from the gap
      // along the plate by mismatch x the skew of the oblique cut.
      t.params.emplace_back("gap_faces_mm", dist_to_line(e2, e1, mul(map.A, Vec2(0, 1))));
      t.angle_deg = 180.0;  // the plates are parallel
      bp("B1", e1);
      bp("B2", centre);
      bp("B3", e2);
      break;
    }
    case Joint::VGroove: {
      const Vec2 plate = Dir("plate");
      Vec2 r1 = P("root1"), r2 = P("root2"), t1 = P("top1"), t2 = P("top2");
      if (scan_u(P("ref1")) > scan_u(P("ref2"))) {
        std::swap(r1, r2);
        std::swap(t1, t2);
      }
      // Midpoint of the root edges moved along the plates' normal onto the
      // level of the lower root edge (in the sensor frame).
      const Vec2 lower = P("lower_root");
      const Vec2 centre = lower + (0.5 * (r1 + r2) - lower).dot(plate) * plate;
      t.track_y_mm = centre.x();
      t.track_z_mm = centre.y();
      t.gap_mm = s.gap_mm == 0 ? 0.0 : std::abs((r2 - r1).dot(plate));
      t.params.emplace_back("gap_faces_mm", dist_to_line(r2, r1, mul(map.A, Vec2(0, 1))));
      t.mismatch_mm = s.mismatch_mm == 0 ? 0.0 : std::abs(cross(plate, r2 - r1));
      t.angle_deg = angle_between_deg(t1 - r1, t2 - r2);
      t.depth_mm = 0.5 * (dist_to_line(r1, t1, plate) + dist_to_line(r2, t2, plate));
      // Shoelace over B1-B2-B4-B5.
      const Vec2 q[4] = {t1, r1, r2, t2};
      double area2 = 0;
      for (int i = 0; i < 4; ++i) area2 += cross(q[i], q[(i + 1) % 4]);
      t.area_mm2 = 0.5 * std::abs(area2);
      bp("B1", t1);
      bp("B2", r1);
      bp("B3", centre);
      bp("B4", r2);
      bp("B5", t2);
      break;
    }
    case Joint::Bevel:
    case Joint::UGroove:
    case Joint::JGroove:
    case Joint::VGrooveThick: break;  // compute_groove_truth
  }
}

}  // namespace vts_corpus::detail
