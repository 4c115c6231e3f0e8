#include "sensor/sim_cell.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <span>

#include "sensor/error_model.h"
#include "sensor/field_error.h"
#include "sensor/workpiece.h"

namespace vts {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// splitmix64: the same numbers on every platform and standard library.
struct Rng {
  std::uint64_t state;
  std::uint64_t next() {
    std::uint64_t z = (state += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  }
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }  // [0, 1)
  // Uniform in the unit ball (rejection from the cube).
  Vec3 in_ball() {
    while (true) {
      const Vec3 v(2.0 * uniform() - 1.0, 2.0 * uniform() - 1.0, 2.0 * uniform() - 1.0);
      if (v.squaredNorm() <= 1.0) return v;
    }
  }
  Vec3 on_sphere() {
    while (true) {
      const Vec3 v = in_ball();
      if (v.norm() > 1e-3) return v.normalized();
    }
  }
};

// The point of a seam's root at arc length s and its direction there.
std::pair<Vec3, Vec3> seam_point(const SimSeamTruth& t, double s) {
  if (t.path.size() < 2) return {t.start + s * t.direction(), t.direction()};
  for (std::size_t i = 1; i < t.path.size(); ++i) {
    const Vec3 ab = t.path[i] - t.path[i - 1];
    const double l = ab.norm();
    if (s <= l || i + 1 == t.path.size()) return {t.path[i - 1] + std::min(s, l) / l * ab, ab / l};
    s -= l;
  }
  return {t.end, t.direction()};
}

Plate block(double x0, double x1, double y0, double y1, double z0, double z1) {
  return Plate{{{y0, z0}, {y1, z0}, {y1, z1}, {y0, z1}}, x0, x1};
}

// The seam where the face (unit normal n, through p) meets the plate top
// z = 0, between the projections of two corners (workpiece frame).
std::pair<Vec3, Vec3> root_line(const Vec3& n, const Vec3& p, const Vec3& c0, const Vec3& c1) {
  const Vec3 u = n.cross(Vec3::UnitZ()).normalized();
  const Vec3 v = u.cross(n);  // in the face, across the seam
  const Vec3 p0 = p - (p.z() / v.z()) * v;
  return {p0 + (c0 - p0).dot(u) * u, p0 + (c1 - p0).dot(u) * u};
}

// The saddle frame in the workpiece frame: lowered by the main pipe's radius.
Pose workpiece_from_saddle(const SaddleParams& s) {
  Pose m = Pose::Identity();
  m.translation() = Vec3(0.0, 0.0, -s.main_radius_mm);
  return m;
}

// The pipe saddle: the mesh where it actually lies; the two halves of the
// curve C(t) as the plan, each led in by the curve before it, and as the
// truth with the frames along it. As pipe joints are welded, both halves
// start at the same crown (t = 0) and end at the other (t = +-pi): seam 1
// for t from 0 up to pi, seam 2 from 0 down to -pi, the torch winding one
// way and then back. The main pipe is the plate, the branch the wall.
void build_saddle(SimCell& cell) {
  const SimCellParams& p = cell.params;
  const SaddleParams& sp = p.saddle;
  const Pose ws = workpiece_from_saddle(sp);
  cell.mesh = saddle_mesh(sp, cell.actual_world_from_workpiece * ws);
  const double r = sp.branch_radius_mm;
  // Points about 1 mm apart (|dC/dt| >= r); the lead-in lets the sensor
  // measure the seam from lookahead + 15 mm before the weld's start, so
  // that the local fit has points either side of it.
  const double dt = 1.0 / r;
  const double lead_in = p.lookahead_mm + 15.0;
  const int n_half = static_cast<int>(std::ceil(std::numbers::pi / dt));
  const int n_lead = static_cast<int>(std::ceil(lead_in / r / dt));
  for (int k = 0; k < 2; ++k) {
    const double sense = k == 0 ? 1.0 : -1.0;
    tracker::SeamPlan plan;
    SimSeamTruth truth;
    double arc = 0.0;
    Vec3 last;
    for (int i = -n_lead; i <= n_half; ++i) {
      const double t = sense * std::numbers::pi * i / n_half;
      const SaddlePoint q = saddle_point(sp, t);
      tracker::PathPoint pp;
      pp.point = ws * q.root;
      pp.plate_normal = ws.linear() * q.main_normal;
      pp.wall_normal = ws.linear() * q.branch_normal;
      if (i > -n_lead) arc += (pp.point - last).norm();
      last = pp.point;
      if (i == 0) plan.weld_from_mm = arc;
      plan.path.push_back(pp);
      if (i < 0) continue;
      const SaddlePoint a = transformed(q, cell.actual_world_from_workpiece * ws);
      truth.path.push_back(a.root);
      truth.path_plate_normal.push_back(a.main_normal);
      truth.path_lateral.push_back(a.main_side);
    }
    plan.start_mm = plan.path[static_cast<std::size_t>(n_lead)].point;
    plan.end_mm = plan.path.back().point;
    plan.plate_normal = plan.path[static_cast<std::size_t>(n_lead)].plate_normal;
    plan.wall_normal = plan.path[static_cast<std::size_t>(n_lead)].wall_normal;
    truth.start = truth.path.front();
    truth.end = truth.path.back();
    truth.plate_normal = truth.path_plate_normal.front();
    const SaddlePoint a = transformed(saddle_point(sp, 0.0), cell.actual_world_from_workpiece * ws);
    truth.wall_normal = a.branch_normal;
    cell.plan.push_back(plan);
    cell.truth.push_back(truth);
  }
}

}  // namespace

double SimSeamTruth::length() const {
  if (path.size() < 2) return (end - start).norm();
  double l = 0.0;
  for (std::size_t i = 1; i < path.size(); ++i) l += (path[i] - path[i - 1]).norm();
  return l;
}

Vec3 SimSeamTruth::lateral() const {
  Vec3 l = plate_normal.cross(direction()).normalized();
  return l.dot(wall_normal) < 0.0 ? Vec3(-l) : l;
}

namespace {

// The disturbances that change the box's own shape or its welds (the lift
// is modelled on the plain box; the saddle has none of them).
std::array<std::pair<const char*, double>, 5> box_shape_keys(const SimCellParams& p) {
  return {{{"seam1_short_mm", p.seam1_short_mm},
           {"seam1_gap_rise_mm", p.seam1_gap_rise_mm},
           {"seam1_bow_mm", p.seam1_bow_mm},
           {"seam1_wave_mm", p.seam1_wave_mm},
           {"tack_spacing_mm", p.tack_spacing_mm}}};
}

}  // namespace

std::string validate(const SimCellParams& p) {
  const std::pair<const char*, double> positive[] = {
      {"box_side_mm", p.box_side_mm},         {"box_height_mm", p.box_height_mm},
      {"plate_side_mm", p.plate_side_mm},     {"plate_thickness_mm", p.plate_thickness_mm},
      {"lookahead_mm", p.lookahead_mm},       {"standoff_mm", p.standoff_mm}};
  for (const auto& [f, v] : positive)
    if (!std::isfinite(v) || v <= 0.0) return field_error(f, v, "must be a finite number > 0");
  if (!std::isfinite(p.offset_mm) || p.offset_mm < 0.0 || p.offset_mm > 50.0)
    return field_error("offset_mm", p.offset_mm, "must be between 0 and 50 mm");
  if (!std::isfinite(p.rotation_deg) || p.rotation_deg < 0.0 || p.rotation_deg > 20.0)
    return field_error("rotation_deg", p.rotation_deg, "must be between 0 and 20 degrees");
  if (p.plate_side_mm < p.box_side_mm + 40.0)
    return field_error("plate_side_mm", p.plate_side_mm, "must exceed box_side_mm by at least 40 mm");
  if (!std::isfinite(p.seam1_short_mm) || p.seam1_short_mm < 0.0 || p.seam1_short_mm > 0.8 * p.box_side_mm)
    return field_error("seam1_short_mm", p.seam1_short_mm, "must be between 0 and 0.8 box_side_mm");
  if (!std::isfinite(p.seam1_gap_rise_mm) || p.seam1_gap_rise_mm < 0.0 || p.seam1_gap_rise_mm > 5.0)
    return field_error("seam1_gap_rise_mm", p.seam1_gap_rise_mm, "must be between 0 and 5 mm");
  if (!std::isfinite(p.seam1_bow_mm) || p.seam1_bow_mm < 0.0 || p.seam1_bow_mm > 0.2 * p.box_side_mm)
    return field_error("seam1_bow_mm", p.seam1_bow_mm, "must be between 0 and 0.2 box_side_mm");
  if (p.seam1_bow_mm > 0.0 && 0.5 * p.plate_side_mm - 0.5 * p.box_side_mm < p.seam1_bow_mm + 20.0)
    return field_error("seam1_bow_mm", p.seam1_bow_mm, "must leave 20 mm of plate outside the box");
  if (!std::isfinite(p.seam1_wave_mm) || std::abs(p.seam1_wave_mm) > 10.0)
    return field_error("seam1_wave_mm", p.seam1_wave_mm, "must be between -10 and 10 mm");
  if (!std::isfinite(p.seam1_wavelength_mm) || p.seam1_wavelength_mm < 30.0)
    return field_error("seam1_wavelength_mm", p.seam1_wavelength_mm, "must be at least 30 mm");
  if (p.seam1_wave_mm != 0.0 && 0.5 * p.plate_side_mm - 0.5 * p.box_side_mm < std::abs(p.seam1_wave_mm) + p.seam1_bow_mm + 20.0)
    return field_error("seam1_wave_mm", p.seam1_wave_mm, "must leave 20 mm of plate outside the box");
  if (!std::isfinite(p.tack_spacing_mm) || (p.tack_spacing_mm != 0.0 && p.tack_spacing_mm < 10.0))
    return field_error("tack_spacing_mm", p.tack_spacing_mm, "must be 0 (no tacks) or at least 10 mm");
  if (!std::isfinite(p.distortion_deg_per_100mm) || std::abs(p.distortion_deg_per_100mm) > 5.0)
    return field_error("distortion_deg_per_100mm", p.distortion_deg_per_100mm, "must be between -5 and 5 degrees");
  if (!std::isfinite(p.distortion_lift_deg_per_100mm) || p.distortion_lift_deg_per_100mm < 0.0 ||
      p.distortion_lift_deg_per_100mm > 5.0)
    return field_error("distortion_lift_deg_per_100mm", p.distortion_lift_deg_per_100mm,
                       "must be between 0 and 5 degrees");
  if (p.distortion_lift_deg_per_100mm != 0.0)
    for (const auto& [f, v] : box_shape_keys(p))
      if (v != 0.0)
        return field_error(f, v, "must be 0 with distortion_lift_deg_per_100mm (the lift is modelled on the plain box)");
  if (!std::isfinite(p.tack_first_mm) || p.tack_first_mm < 0.0)
    return field_error("tack_first_mm", p.tack_first_mm, "must be a finite number >= 0");
  if (!std::isfinite(p.tack_length_mm) || p.tack_length_mm <= 0.0 || p.tack_length_mm > 50.0)
    return field_error("tack_length_mm", p.tack_length_mm, "must be between 0 (exclusive) and 50 mm");
  if (!std::isfinite(p.tack_leg_mm) || p.tack_leg_mm <= 0.0 || p.tack_leg_mm > 15.0)
    return field_error("tack_leg_mm", p.tack_leg_mm, "must be between 0 (exclusive) and 15 mm");
  if (p.workpiece == SimWorkpiece::Saddle) {
    if (const std::string why = validate(p.saddle); !why.empty()) return why;
    const std::pair<const char*, double> distortions[] = {
        {"distortion_deg_per_100mm", p.distortion_deg_per_100mm},
        {"distortion_lift_deg_per_100mm", p.distortion_lift_deg_per_100mm}};
    const auto shape = box_shape_keys(p);
    for (const auto& keys : {std::span<const std::pair<const char*, double>>(shape),
                             std::span<const std::pair<const char*, double>>(distortions)})
      for (const auto& [f, v] : keys)
        if (v != 0.0) return field_error(f, v, "is a disturbance of the box: must be 0 on the saddle");
    // The laser plane, lookahead_mm ahead along the tangent, must still cut
    // the branch near the seam: it cuts it asin(lookahead / r) further round.
    if (p.lookahead_mm > 0.5 * p.saddle.branch_radius_mm)
      return field_error("lookahead_mm", p.lookahead_mm,
                         "must be at most half the saddle's branch radius (" +
                             message_number(p.saddle.branch_radius_mm) + " mm): ahead along the tangent, the laser "
                             "plane must still cross the curving seam");
  }
  return {};
}

SimCell build_sim_cell(const SimCellParams& p) {
  SimCell cell;
  cell.params = p;
  cell.nominal_world_from_workpiece = p.nominal_world_from_workpiece;

  Rng rng{p.seed};
  const Vec3 axis = rng.on_sphere();
  const double angle = p.rotation_deg * kDeg * rng.uniform();
  const Vec3 shift = p.offset_mm * rng.in_ball();
  Pose delta = Pose::Identity();
  delta.linear() = Eigen::AngleAxisd(angle, axis).toRotationMatrix();
  cell.actual_world_from_workpiece = p.nominal_world_from_workpiece * delta;
  cell.actual_world_from_workpiece.pretranslate(shift);
  const Pose& actual = cell.actual_world_from_workpiece;
  cell.tool_from_laser = Pose::Identity();
  cell.tool_from_laser.translation() = Vec3(p.lookahead_mm, 0.0, -p.standoff_mm);
  if (p.workpiece == SimWorkpiece::Saddle) {
    build_saddle(cell);
    return cell;
  }

  const double h = 0.5 * p.box_side_mm;
  // The master's model.
  tracker::SeamPlan s1, s2;
  s1.start_mm = Vec3(-h, -h, 0.0);
  s1.end_mm = Vec3(h, -h, 0.0);
  s1.wall_normal = -Vec3::UnitY();
  s2.start_mm = Vec3(h, -h, 0.0);
  s2.end_mm = Vec3(h, h, 0.0);
  s2.wall_normal = Vec3::UnitX();
  cell.plan = {s1, s2};

  // The actual part: the box possibly shorter and tilted about its bottom
  // edge at x = -h (plate_from_box).
  const double x1 = h - p.seam1_short_mm;
  const double tilt = std::atan2(p.seam1_gap_rise_mm, x1 + h);
  Pose plate_from_box = Pose::Identity();
  plate_from_box.translate(Vec3(-h, 0.0, 0.0));
  plate_from_box.rotate(Eigen::AngleAxisd(-tilt, Vec3::UnitY()));  // lifts the +x end
  plate_from_box.translate(Vec3(h, 0.0, 0.0));

  const double ph = 0.5 * p.plate_side_mm;
  cell.mesh = plate_mesh(block(-ph, ph, -ph, ph, -p.plate_thickness_mm, 0.0), 10.0, actual);
  // A curved seam-1 wall's footprint (box frame, z = 0), points 2 mm apart
  // or closer from (-h, -h) to (x1, -h): moved to -y by the bow's circular
  // arc and the waves. The wall is flat between them (a chord of a 150 mm
  // radius sags 3 um over 2 mm) and the truth is the same polyline.
  std::vector<Vec2> bowed;
  if (p.seam1_bow_mm > 0.0 || p.seam1_wave_mm != 0.0) {
    const double b = p.seam1_bow_mm, c = 0.5 * (x1 + h), xm = 0.5 * (x1 - h);
    const double r = b > 0.0 ? (c * c + b * b) / (2.0 * b) : 0.0;
    const double yc = -h - b + r;
    const int n = 2 * std::max(1, static_cast<int>(std::ceil(c / 2.0)));  // even: a point mid-seam
    for (int i = 0; i <= n; ++i) {
      const double x = -h + 2.0 * c * i / n;
      double y = -h;
      if (b > 0.0 && i > 0 && i < n) y = yc - std::sqrt(r * r - (x - xm) * (x - xm));
      y -= p.seam1_wave_mm * std::sin(2.0 * std::numbers::pi * (x + h) / p.seam1_wavelength_mm);
      bowed.emplace_back(x, y);
    }
  }
  if (bowed.empty()) {
    const Mesh box = plate_mesh(block(-h, x1, -h, h, 0.0, p.box_height_mm), 10.0, actual * plate_from_box);
    if (p.distortion_lift_deg_per_100mm != 0.0) {
      // Kept apart so that it can lift off the plate (validate: the plain box).
      cell.fixed_part = cell.mesh;
      cell.moving_part = box;
    }
    cell.mesh.append(box);
  } else {
    // The box behind the wall (from 5 mm inside the wall's innermost point
    // to the far side), and strips from the wall to it, each a convex
    // footprint (a trapezoid from two wall points) extruded up: a section
    // in (x, y) of the box frame, counter-clockwise seen from above; its x
    // is the box's z. The strips' shared faces lie inside the box. Short
    // strips keep every triangle small (long thin ones slow the ray casts).
    double inner = -h;
    for (const Vec2& q : bowed) inner = std::max(inner, q.y());
    inner += 5.0;
    cell.mesh.append(plate_mesh(block(-h, x1, inner, h, 0.0, p.box_height_mm), 10.0, actual * plate_from_box));
    Pose box_from_section = Pose::Identity();
    box_from_section.linear().col(0) = Vec3::UnitZ();
    box_from_section.linear().col(1) = Vec3::UnitX();
    box_from_section.linear().col(2) = Vec3::UnitY();
    for (std::size_t i = 1; i < bowed.size(); ++i) {
      Plate strip;
      strip.section_yz = {bowed[i - 1], bowed[i], Vec2(bowed[i].x(), inner), Vec2(bowed[i - 1].x(), inner)};
      strip.x0_mm = 0.0;
      strip.x1_mm = p.box_height_mm;
      cell.mesh.append(plate_mesh(strip, 10.0, actual * plate_from_box * box_from_section));
    }
  }

  const Eigen::Matrix3d rb = plate_from_box.linear();
  auto truth = [&](const Vec3& face_n, const Vec3& c0, const Vec3& c1) {
    const Vec3 n = rb * face_n;
    const Vec3 a = plate_from_box * c0, b = plate_from_box * c1;
    const auto [start, end] = root_line(n, a, a, b);
    SimSeamTruth t;
    t.start = actual * start;
    t.end = actual * end;
    t.plate_normal = actual.linear() * Vec3::UnitZ();
    t.wall_normal = actual.linear() * n;
    return t;
  };
  cell.truth = {truth(-Vec3::UnitY(), Vec3(-h, -h, 0.0), Vec3(x1, -h, 0.0)),
                truth(Vec3::UnitX(), Vec3(x1, -h, 0.0), Vec3(x1, h, 0.0))};
  if (!bowed.empty()) {
    // Each footprint point's wall line (vertical in the box) meets the
    // plate top at the root.
    SimSeamTruth& t = cell.truth[0];
    const Vec3 up = rb * Vec3::UnitZ();
    for (const Vec2& f : bowed) {
      const Vec3 a = plate_from_box * Vec3(f.x(), f.y(), 0.0);
      t.path.push_back(actual * Vec3(a - (a.z() / up.z()) * up));
    }
    t.start = t.path.front();
    t.end = t.path.back();
  }
  if (p.tack_spacing_mm > 0.0) {
    // A tack's section in the seam's frame: u across (towards the open
    // side), v up the plate normal; legs on the plate and up the wall, the
    // face bulging out.
    const double leg = p.tack_leg_mm;
    std::vector<Vec2> uv{{0.0, 0.0}, {leg, 0.0}};
    for (int i = 1; i < 8; ++i) {
      const double f = i / 8.0;
      const double bulge = 0.3 * leg * 4.0 * f * (1.0 - f);
      // Along the chord from (leg, 0) to (0, leg), out along (1, 1)/sqrt 2.
      uv.emplace_back(leg * (1.0 - f) + bulge * std::sqrt(0.5), leg * f + bulge * std::sqrt(0.5));
    }
    uv.emplace_back(0.0, leg);
    for (int k = 0; k < static_cast<int>(cell.truth.size()); ++k) {
      const SimSeamTruth& t = cell.truth[static_cast<std::size_t>(k)];
      const double len = t.length();
      for (double s0 = p.tack_first_mm; s0 + p.tack_length_mm <= len - p.tack_first_mm + 1e-9;
           s0 += p.tack_spacing_mm) {
        const double sm = s0 + 0.5 * p.tack_length_mm;
        const auto [root, dir] = seam_point(t, sm);
        Vec3 lat = t.plate_normal.cross(dir).normalized();
        if (lat.dot(t.lateral()) < 0.0) lat = -lat;
        // Frame: x along the seam, y = lat, z = x cross y (+- the plate normal).
        const double sgn = dir.cross(lat).dot(t.plate_normal) < 0.0 ? -1.0 : 1.0;
        Plate tack;
        for (const Vec2& q : uv) tack.section_yz.emplace_back(q.x(), sgn * q.y());
        if (sgn < 0.0) std::reverse(tack.section_yz.begin(), tack.section_yz.end());
        tack.x0_mm = -0.5 * p.tack_length_mm;
        tack.x1_mm = 0.5 * p.tack_length_mm;
        Pose world_from_tack = Pose::Identity();
        world_from_tack.linear().col(0) = dir;
        world_from_tack.linear().col(1) = lat;
        world_from_tack.linear().col(2) = dir.cross(lat);
        // A little into the plate and the wall, so the bead joins both.
        world_from_tack.translation() = root - 0.05 * lat - 0.05 * t.plate_normal;
        cell.mesh.append(plate_mesh(tack, 10.0, world_from_tack));
        cell.tacks.push_back({k, s0, s0 + p.tack_length_mm});
      }
    }
  }

  if (p.distorted()) {
    // Seam 2 as the part lies once seam 1 is welded to its end. The lift
    // turns its wall about its own foot (the axis through seam 1's end):
    // only the wall's normal changes.
    SeamDistortion d(cell);
    d.update(cell.truth[0].end + 1.0 * cell.truth[0].direction());
    const Pose m = d.part_motion();
    SimSeamTruth& t = cell.truth[1];
    t.start = m * t.start;
    t.end = m * t.end;
    for (Vec3& q : t.path) q = m * q;
    t.plate_normal = m.linear() * t.plate_normal;
    t.wall_normal = m.linear() * d.wall_motion().linear() * t.wall_normal;
  }
  return cell;
}

SeamDistortion::SeamDistortion(const SimCell& cell)
    : cell_(&cell),
      rate_deg_per_mm_(cell.params.distortion_deg_per_100mm / 100.0),
      lift_deg_per_mm_(cell.params.distortion_lift_deg_per_100mm / 100.0) {}

void SeamDistortion::update(const Vec3& tcp) {
  const SimSeamTruth& t = cell_->truth[0];
  const double u = std::clamp((tcp - t.start).dot(t.direction()), 0.0, (t.end - t.start).norm());
  s_ = std::max(s_, u);
}

double SeamDistortion::angle_deg() const { return rate_deg_per_mm_ * s_; }
double SeamDistortion::lift_deg() const { return lift_deg_per_mm_ * s_; }

Pose SeamDistortion::wall_motion() const {
  Pose m = Pose::Identity();
  if (lift_deg_per_mm_ == 0.0 || s_ <= 0.0) return m;
  const SimSeamTruth& t = cell_->truth[0];
  const Vec3 a = t.wall_normal, d = t.direction();
  // Positive about the wall's normal: the seam ahead turns out of the plate.
  const double sign = a.cross(d).dot(t.plate_normal) >= 0.0 ? 1.0 : -1.0;
  const Vec3 pivot = t.start + s_ * d;
  m.linear() = Eigen::AngleAxisd(sign * lift_deg() * kDeg, a).toRotationMatrix();
  m.translation() = pivot - m.linear() * pivot;
  return m;
}

Pose SeamDistortion::part_motion() const {
  Pose m = Pose::Identity();
  if (rate_deg_per_mm_ == 0.0 || s_ <= 0.0) return m;
  const SimSeamTruth& t = cell_->truth[0];
  const Vec3 n = t.plate_normal, d = t.direction();
  // Positive: the seam ahead turns towards the open side.
  const double sign = n.cross(d).dot(t.lateral()) >= 0.0 ? 1.0 : -1.0;
  const Vec3 pivot = t.start + s_ * d;
  m.linear() = Eigen::AngleAxisd(sign * angle_deg() * kDeg, n).toRotationMatrix();
  m.translation() = pivot - m.linear() * pivot;
  return m;
}

double sim_standoff_mm(const ScannerDesc& scanner) {
  const double lo = scanner.min_range_mm, hi = std::min(scanner.max_range_mm, scanner.max_hit_mm);
  if (lo + 20.0 <= 100.0 && 100.0 <= hi - 100.0) return 100.0;
  return 0.5 * (lo + hi);
}

tracker::TrackerParams sim_tracker_params(const ScannerDesc& scanner, double standoff_mm) {
  tracker::TrackerParams t;
  t.joint = tracker::JointType::Fillet;
  if (!scanner.ideal) t.surface_tol_mm = std::max(t.surface_tol_mm, 3.0 * depth_noise_mm(scanner, standoff_mm));
  t.segmentation.roi_first = scanner.roi_first_column;
  t.segmentation.roi_last = std::min(scanner.roi_last_column, scanner.points - 1);
  return t;
}

tracker::MasterParams sim_master_params(const SimCell& cell, double speed_mm_s, double rate_hz) {
  const SimCellParams& p = cell.params;
  tracker::MasterParams m;
  m.speed_mm_s = speed_mm_s;
  m.control_rate_hz = rate_hz;
  m.lookahead_mm = p.lookahead_mm;
  // The first search must cover the largest displacement of a seam start:
  // the offset plus the rotation's sweep at the box corner (the saddle's
  // seam: its farthest point from the workpiece origin), plus 5 mm.
  const double reach = p.workpiece == SimWorkpiece::Saddle
                           ? std::hypot(p.saddle.branch_radius_mm,
                                        p.saddle.main_radius_mm -
                                            std::sqrt(p.saddle.main_radius_mm * p.saddle.main_radius_mm -
                                                      p.saddle.branch_radius_mm * p.saddle.branch_radius_mm))
                           : std::sqrt(0.5) * p.box_side_mm;
  m.search_margin_mm = p.offset_mm + reach * std::sin(p.rotation_deg * kDeg) + 5.0;
  return m;
}

PointError seam_error(const SimSeamTruth& seam, const Vec3& tcp) {
  if (seam.path.size() >= 2) {
    // The nearest point of the polyline. With frames along the path (the
    // saddle), the errors in the frame there (interpolated between the
    // points'); else lateral across the segment in the plate.
    const bool frames = seam.path_lateral.size() == seam.path.size() &&
                        seam.path_plate_normal.size() == seam.path.size();
    double best = std::numeric_limits<double>::infinity();
    PointError e;
    for (std::size_t i = 1; i < seam.path.size(); ++i) {
      const Vec3 a = seam.path[i - 1], ab = seam.path[i] - a;
      const double f = std::clamp((tcp - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
      const Vec3 q = a + f * ab;
      const double dist = (tcp - q).squaredNorm();
      if (dist >= best) continue;
      best = dist;
      Vec3 n = seam.plate_normal, lat;
      if (frames) {
        const Vec3 d = ab.normalized();
        n = (1.0 - f) * seam.path_plate_normal[i - 1] + f * seam.path_plate_normal[i];
        n = (n - n.dot(d) * d).normalized();
        lat = (1.0 - f) * seam.path_lateral[i - 1] + f * seam.path_lateral[i];
        lat = (lat - lat.dot(d) * d - lat.dot(n) * n).normalized();
      } else {
        lat = seam.plate_normal.cross(ab).normalized();
        if (lat.dot(seam.lateral()) < 0.0) lat = -lat;
      }
      e.true_point = q;
      e.lateral_mm = (tcp - q).dot(lat);
      e.vertical_mm = (tcp - q).dot(n);
    }
    return e;
  }
  const Vec3 d = seam.direction();
  const double s = std::clamp((tcp - seam.start).dot(d), 0.0, seam.length());
  PointError e;
  e.true_point = seam.start + s * d;
  const Vec3 r = tcp - e.true_point;
  e.lateral_mm = r.dot(seam.lateral());
  e.vertical_mm = r.dot(seam.plate_normal);
  return e;
}

Pose sample_tcp(const tracker::MasterResult& result, const std::vector<Pose>* actual, std::size_t i) {
  return actual && i < actual->size() ? (*actual)[i] : result.samples[i].world_from_tool;
}

Vec3 weld_centre(const tracker::MasterResult& result, const std::vector<Pose>* actual, std::size_t i) {
  return sample_tcp(result, actual, i).translation() - result.samples[i].weave_mm;
}

std::vector<SeamMetrics> evaluate(const SimCell& cell, const tracker::MasterResult& result,
                                  const std::vector<Pose>* actual) {
  const auto& samples = result.samples;
  auto centre = [&](std::size_t i) { return weld_centre(result, actual, i); };
  std::vector<SeamMetrics> out;
  for (std::size_t k = 0; k < result.seams.size() && k < cell.truth.size(); ++k) {
    const tracker::SeamRun& run = result.seams[k];
    const SimSeamTruth& truth = cell.truth[k];
    SeamMetrics m;
    m.start_found = run.start_found;
    m.end_found = run.end_found;
    m.lost = run.lost;
    m.failure = run.failure;
    m.search_mm = run.search_mm;
    m.welded_mm = run.welded_mm;
    m.points = run.points;
    m.rejected_points = run.rejected_points;
    m.refits = run.refits;
    m.sensor_max_gap_mm = run.max_gap_mm;
    double sl = 0.0, sv = 0.0;
    std::size_t first_weld = samples.size(), last_weld = samples.size();
    for (std::size_t i = 0; i < samples.size(); ++i) {
      const auto& smp = samples[i];
      if (smp.seam != static_cast<int>(k) || smp.phase != tracker::Phase::Weld) continue;
      if (first_weld == samples.size()) first_weld = i;
      last_weld = i;
      const Vec3 tcp = centre(i);
      const PointError e = seam_error(truth, tcp);
      sl += e.lateral_mm * e.lateral_mm;
      sv += e.vertical_mm * e.vertical_mm;
      m.max_error_mm = std::max(m.max_error_mm, std::hypot(e.lateral_mm, e.vertical_mm));
      ++m.samples;
    }
    double sp = 0.0;
    int counted = 0;
    for (const Vec3& p : run.track_points) {
      // On a curved seam, the points measured on the lead-in before its
      // start or past its end are not on it.
      const std::size_t np = truth.path.size();
      if (np >= 2 && ((p - truth.path[0]).dot(truth.path[1] - truth.path[0]) < 0.0 ||
                      (p - truth.path[np - 1]).dot(truth.path[np - 1] - truth.path[np - 2]) > 0.0))
        continue;
      const PointError e = seam_error(truth, p);
      sp += e.lateral_mm * e.lateral_mm + e.vertical_mm * e.vertical_mm;
      ++counted;
    }
    if (counted > 0) m.sensor_rms_mm = std::sqrt(sp / counted);
    m.welded = run.start_found && m.samples > 0;
    if (m.samples > 0) {
      m.rms_lateral_mm = std::sqrt(sl / m.samples);
      m.rms_vertical_mm = std::sqrt(sv / m.samples);
    }
    // Where welding began (the cycle before the first weld sample) and ended.
    Vec3 weld_start = run.weld_start, weld_end = run.weld_end;
    if (actual && m.welded && first_weld > 0) {
      weld_start = centre(first_weld - 1);
      weld_end = centre(last_weld);
    }
    const Vec3 d0 = truth.path.size() >= 2 ? Vec3((truth.path[1] - truth.path[0]).normalized()) : truth.direction();
    const std::size_t np = truth.path.size();
    const Vec3 d1 = np >= 2 ? Vec3((truth.path[np - 1] - truth.path[np - 2]).normalized()) : truth.direction();
    m.start_error_mm = m.welded ? (weld_start - truth.start).norm() : 0.0;
    m.end_error_mm = m.welded ? (weld_end - truth.end).norm() : 0.0;
    m.start_along_mm = m.welded ? (weld_start - truth.start).dot(d0) : 0.0;
    m.end_along_mm = m.welded ? (weld_end - truth.end).dot(d1) : 0.0;
    out.push_back(m);
  }
  return out;
}

}  // namespace vts
