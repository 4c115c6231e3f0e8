#include "sensor/workpiece.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

namespace vts {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

struct JointName {
  JointType type;
  std::string_view name;
};
constexpr JointName kJointNames[] = {{JointType::Fillet, "fillet"}, {JointType::Corner, "corner"},
                                     {JointType::Lap, "lap"},       {JointType::Butt, "butt"},
                                     {JointType::VGroove, "vgroove"}, {JointType::Plate, "plate"}};

std::string bad(std::string_view field, double value, std::string_view why) {
  std::ostringstream s;
  s << field << " = " << value << ": " << why;
  return s.str();
}

double signed_area(const std::vector<Vec2>& poly) {
  double a = 0.0;
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const Vec2& p = poly[i];
    const Vec2& q = poly[(i + 1) % poly.size()];
    a += p.x() * q.y() - q.x() * p.y();
  }
  return 0.5 * a;
}

Plate make_plate(std::vector<Vec2> section, double length_mm) {
  if (signed_area(section) < 0.0) std::reverse(section.begin(), section.end());
  return Plate{std::move(section), 0.0, length_mm};
}

Plate rect(double y0, double y1, double z0, double z1, double length_mm) {
  return make_plate({{y0, z0}, {y1, z0}, {y1, z1}, {y0, z1}}, length_mm);
}

void build_fillet(const JointParams& p, Workpiece& w) {
  const double a = p.angle_deg * kDeg, t = p.thickness_mm, g = p.gap_mm;
  w.plates.push_back(rect(-p.width_mm, p.width_mm, -t, 0.0, p.length_mm));
  // Web: its open-side face lies on the line through the root at angle a from
  // the flange; its bottom is cut parallel to the flange, g above it.
  const Vec2 u(std::cos(a), std::sin(a));
  const Vec2 v(-std::sin(a), std::cos(a));
  const Vec2 toe(g / std::tan(a), g);
  const Vec2 top = toe + p.height_mm / std::sin(a) * u;
  const Vec2 back_top = top + t * v;
  const Vec2 back_toe = toe + t * v - t * std::cos(a) / std::sin(a) * u;
  w.plates.push_back(make_plate({toe, top, back_top, back_toe}, p.length_mm));
  w.truth.gap_mm = g;
  w.truth.angle_deg = p.angle_deg;
  w.truth.features = {{"flange_edge", {p.width_mm, 0.0}}, {"web_toe", toe}, {"web_top", top}};
}

void build_corner(const JointParams& p, Workpiece& w) {
  const double h = 0.5 * p.angle_deg * kDeg, s = std::sin(h), c = std::cos(h);
  const double t = p.thickness_mm, W = p.width_mm, g = p.gap_mm;
  // Two plates whose outer faces fall away from the apex on either side of z;
  // each plate's inner end runs into the other plate.
  const Vec2 o_r(0.5 * g, 0.0), a_r(s, -c), m_r(-c, -s);
  const Vec2 o_l(-0.5 * g, 0.0), a_l(-s, -c), m_l(c, -s);
  w.plates.push_back(make_plate({o_r, o_r + W * a_r, o_r + W * a_r + t * m_r, o_r + t * m_r}, p.length_mm));
  w.plates.push_back(make_plate({o_l, o_l + t * m_l, o_l + W * a_l + t * m_l, o_l + W * a_l}, p.length_mm));
  w.truth.gap_mm = g;
  w.truth.angle_deg = p.angle_deg;
  w.truth.features = {{"left_edge", o_l}, {"right_edge", o_r}};
}

void build_lap(const JointParams& p, Workpiece& w) {
  const double t = p.thickness_mm, W = p.width_mm, g = p.gap_mm;
  w.plates.push_back(rect(-W, W, -t, 0.0, p.length_mm));
  w.plates.push_back(rect(-W, 0.0, g, g + t, p.length_mm));
  w.truth.gap_mm = g;
  w.truth.angle_deg = 90.0;
  w.truth.step_mm = g + t;
  w.truth.features = {{"edge_top", {0.0, g + t}}, {"edge_bottom", {0.0, g}}, {"foot", {0.0, 0.0}}};
}

void build_butt(const JointParams& p, Workpiece& w) {
  const double t = p.thickness_mm, W = p.width_mm, g = p.gap_mm, m = p.mismatch_mm;
  w.plates.push_back(rect(-0.5 * g - W, -0.5 * g, -t, 0.0, p.length_mm));
  w.plates.push_back(rect(0.5 * g, 0.5 * g + W, m - t, m, p.length_mm));
  w.truth.gap_mm = g;
  w.truth.angle_deg = 180.0;
  w.truth.mismatch_mm = m;
  w.truth.features = {{"left_edge", {-0.5 * g, 0.0}}, {"right_edge", {0.5 * g, m}}};
}

void build_vgroove(const JointParams& p, Workpiece& w) {
  const double g = p.gap_mm, W = p.width_mm, m = p.mismatch_mm, rf = p.root_face_mm;
  const double d = p.thickness_mm - rf;  // bevel depth
  const double run = d * std::tan(0.5 * p.angle_deg * kDeg);
  const double yl = -0.5 * g, yr = 0.5 * g;
  w.plates.push_back(make_plate(
      {{yl - W, -rf}, {yl, -rf}, {yl, 0.0}, {yl - run, d}, {yl - W, d}}, p.length_mm));
  w.plates.push_back(make_plate(
      {{yr, m - rf}, {yr + W, m - rf}, {yr + W, m + d}, {yr + run, m + d}, {yr, m}}, p.length_mm));
  const std::vector<Vec2> open = {{yl, 0.0}, {yr, m}, {yr + run, m + d}, {yl - run, d}};
  w.truth.gap_mm = g;
  w.truth.angle_deg = p.angle_deg;
  w.truth.mismatch_mm = m;
  w.truth.depth_mm = d;
  w.truth.area_mm2 = std::abs(signed_area(open));
  w.truth.features = {{"left_root", {yl, 0.0}},  {"right_root", {yr, m}},
                      {"left_top", {yl - run, d}}, {"right_top", {yr + run, m + d}}};
}

void build_plate(const JointParams& p, Workpiece& w) {
  w.plates.push_back(rect(-0.5 * p.width_mm, 0.5 * p.width_mm, -p.thickness_mm, 0.0, p.length_mm));
  w.truth.angle_deg = 180.0;
}

}  // namespace

std::string_view to_string(JointType type) {
  for (const auto& j : kJointNames)
    if (j.type == type) return j.name;
  return "unknown";
}

std::optional<JointType> joint_type_from_string(std::string_view name) {
  for (const auto& j : kJointNames)
    if (j.name == name) return j.type;
  return std::nullopt;
}

JointParams default_params(JointType type) {
  JointParams p;
  switch (type) {
    case JointType::Fillet: break;
    case JointType::Corner: p.width_mm = 60.0; break;
    case JointType::Lap: p.thickness_mm = 4.0; p.width_mm = 60.0; break;
    case JointType::Butt: p.gap_mm = 1.0; break;
    case JointType::VGroove:
      p.thickness_mm = 12.0; p.angle_deg = 60.0; p.gap_mm = 1.0; p.root_face_mm = 1.5;
      break;
    case JointType::Plate: p.width_mm = 200.0; p.angle_deg = 180.0; break;
  }
  return p;
}

std::string validate(JointType type, const JointParams& p) {
  const std::pair<std::string_view, double> all[] = {
      {"length_mm", p.length_mm},       {"width_mm", p.width_mm},   {"thickness_mm", p.thickness_mm},
      {"height_mm", p.height_mm},       {"gap_mm", p.gap_mm},       {"angle_deg", p.angle_deg},
      {"mismatch_mm", p.mismatch_mm},   {"root_face_mm", p.root_face_mm}, {"segment_mm", p.segment_mm}};
  for (const auto& [field, value] : all)
    if (!std::isfinite(value)) return bad(field, value, "must be a finite number");
  for (const auto& [field, value] : {all[0], all[1], all[2], all[3], all[8]})
    if (value <= 0.0) return bad(field, value, "must be > 0");
  if (p.gap_mm < 0.0) return bad("gap_mm", p.gap_mm, "must be >= 0");
  if (p.length_mm / p.segment_mm > 100000.0)
    return bad("segment_mm", p.segment_mm, "too small for length_mm (more than 100000 cuts)");
  switch (type) {
    case JointType::Fillet:
      if (p.angle_deg < 30.0 || p.angle_deg > 150.0)
        return bad("angle_deg", p.angle_deg, "fillet angle must be between 30 and 150 degrees");
      break;
    case JointType::Corner:
      if (p.angle_deg < 90.0 || p.angle_deg >= 180.0)
        return bad("angle_deg", p.angle_deg, "corner angle must be >= 90 and < 180 degrees");
      if (p.gap_mm >= p.thickness_mm)
        return bad("gap_mm", p.gap_mm, "corner gap must be smaller than thickness_mm");
      break;
    case JointType::VGroove: {
      if (p.angle_deg <= 0.0 || p.angle_deg >= 150.0)
        return bad("angle_deg", p.angle_deg, "groove angle must be > 0 and < 150 degrees");
      if (p.root_face_mm < 0.0 || p.root_face_mm >= p.thickness_mm)
        return bad("root_face_mm", p.root_face_mm, "must be >= 0 and smaller than thickness_mm");
      const double run = (p.thickness_mm - p.root_face_mm) * std::tan(0.5 * p.angle_deg * kDeg);
      if (p.width_mm <= run)
        return bad("width_mm", p.width_mm, "must exceed the bevel's width across the seam");
      break;
    }
    default: break;
  }
  return {};
}

Workpiece build_workpiece(JointType type, const JointParams& params, const Pose& world_from_joint) {
  Workpiece w;
  w.type = type;
  w.params = params;
  w.world_from_joint = world_from_joint;
  switch (type) {
    case JointType::Fillet: build_fillet(params, w); break;
    case JointType::Corner: build_corner(params, w); break;
    case JointType::Lap: build_lap(params, w); break;
    case JointType::Butt: build_butt(params, w); break;
    case JointType::VGroove: build_vgroove(params, w); break;
    case JointType::Plate: build_plate(params, w); break;
  }
  return w;
}

Mesh plate_mesh(const Plate& plate, double segment_mm, const Pose& world_from_joint) {
  Mesh m;
  const auto& poly = plate.section_yz;
  const int k = static_cast<int>(poly.size());
  const double len = plate.x1_mm - plate.x0_mm;
  const int cuts = std::max(1, static_cast<int>(std::ceil(len / segment_mm - 1e-9)));
  auto vertex = [&](double x, const Vec2& yz) {
    m.vertices.push_back((world_from_joint * Vec3(x, yz.x(), yz.y())).cast<float>());
    return static_cast<std::uint32_t>(m.vertices.size() - 1);
  };
  // Rings of section vertices at each cut; sides join consecutive rings.
  std::vector<std::uint32_t> prev, cur;
  for (int j = 0; j <= cuts; ++j) {
    const double x = j == cuts ? plate.x1_mm : plate.x0_mm + len * j / cuts;
    cur.clear();
    for (const auto& p : poly) cur.push_back(vertex(x, p));
    if (j > 0) {
      for (int e = 0; e < k; ++e) {
        const int f = (e + 1) % k;
        // a = (x_prev, p_e), b = (x, p_e), c = (x, p_f), d = (x_prev, p_f): outward is (a, c, b), (a, d, c)
        m.triangles.push_back({prev[e], cur[f], cur[e]});
        m.triangles.push_back({prev[e], prev[f], cur[f]});
      }
    } else {
      for (int e = 1; e + 1 < k; ++e) m.triangles.push_back({cur[0], cur[e + 1], cur[e]});
    }
    std::swap(prev, cur);
  }
  for (int e = 1; e + 1 < k; ++e) m.triangles.push_back({prev[0], prev[e], prev[e + 1]});
  return m;
}

Mesh Workpiece::mesh() const {
  Mesh m;
  for (const auto& p : plates) m.append(plate_mesh(p, params.segment_mm, world_from_joint));
  return m;
}

Vec3 Workpiece::seam_origin() const { return world_from_joint * Vec3::Zero(); }
Vec3 Workpiece::seam_direction() const { return world_from_joint.linear() * Vec3::UnitX(); }

std::vector<std::pair<Vec3, double>> Workpiece::face_planes() const {
  std::vector<std::pair<Vec3, double>> planes;
  const Eigen::Matrix3d& r = world_from_joint.linear();
  auto add = [&](const Vec3& n_joint, const Vec3& point_joint) {
    const Vec3 n = (r * n_joint).normalized();
    planes.emplace_back(n, n.dot(world_from_joint * point_joint));
  };
  for (const auto& plate : plates) {
    const auto& poly = plate.section_yz;
    for (std::size_t e = 0; e < poly.size(); ++e) {
      const Vec2 d = poly[(e + 1) % poly.size()] - poly[e];
      add(Vec3(0.0, d.y(), -d.x()), Vec3(plate.x0_mm, poly[e].x(), poly[e].y()));
    }
    add(-Vec3::UnitX(), Vec3(plate.x0_mm, 0.0, 0.0));
    add(Vec3::UnitX(), Vec3(plate.x1_mm, 0.0, 0.0));
  }
  return planes;
}

}  // namespace vts
