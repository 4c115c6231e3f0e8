#include "sensor/workpiece.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "sensor/field_error.h"
#include "sensor/groove.h"
#include "sensor/saddle.h"

namespace vts {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

constexpr std::string_view kPlateName = "plate";
constexpr int kMaxPasses = 1000;

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

// The subdivision of a plate for cell_mm > 0 (see plate_mesh): cuts along
// x, columns across each section edge, and the outline (ring) those give.
struct DenseGrid {
  double nx = 1.0;               // cuts along x
  std::vector<double> across;    // columns across each section edge
  double ring = 0.0;             // points on the subdivided outline: sum of across
};

DenseGrid dense_grid(const Plate& plate, double segment_mm, double cell_mm) {
  const auto& poly = plate.section_yz;
  const auto cuts = [](double n) { return std::max(1.0, std::ceil(n - 1e-9)); };
  DenseGrid g;
  const double len = plate.x1_mm - plate.x0_mm;
  g.nx = std::max(cuts(len / segment_mm), cuts(len / cell_mm));
  for (std::size_t e = 0; e < poly.size(); ++e)
    g.across.push_back(cuts((poly[(e + 1) % poly.size()] - poly[e]).norm() / cell_mm));
  if (poly.size() == 4) {  // a bilinear cap needs equal counts on opposite sides
    g.across[0] = g.across[2] = std::max(g.across[0], g.across[2]);
    g.across[1] = g.across[3] = std::max(g.across[1], g.across[3]);
  }
  for (const double n : g.across) g.ring += n;
  return g;
}

Mesh dense_plate_mesh(const Plate& plate, double segment_mm, const Pose& world_from_joint, double cell_mm) {
  const auto& poly = plate.section_yz;
  const int k = static_cast<int>(poly.size());
  const DenseGrid g = dense_grid(plate, segment_mm, cell_mm);
  const int nx = static_cast<int>(g.nx);
  const int ring_size = static_cast<int>(g.ring);
  const double len = plate.x1_mm - plate.x0_mm;

  // The outline, each edge cut into its columns (edge e's first point is its corner).
  std::vector<Vec2> ring;
  ring.reserve(ring_size);
  for (int e = 0; e < k; ++e) {
    const Vec2& a = poly[e];
    const Vec2& b = poly[(e + 1) % k];
    const int n = static_cast<int>(g.across[e]);
    for (int j = 0; j < n; ++j) ring.push_back(a + (b - a) * (static_cast<double>(j) / n));
  }

  Mesh m;
  const bool bilinear = k == 4;
  const int a = bilinear ? static_cast<int>(g.across[0]) : 0;
  const int b = bilinear ? static_cast<int>(g.across[1]) : 0;
  const std::size_t cap_vertices = bilinear ? static_cast<std::size_t>(a - 1) * (b - 1) : 1;
  m.vertices.reserve(static_cast<std::size_t>(nx + 1) * ring_size + 2 * cap_vertices);
  m.triangles.reserve(static_cast<std::size_t>(plate_triangle_count(plate, segment_mm, cell_mm)));
  auto vertex = [&](double x, const Vec2& yz) {
    m.vertices.push_back((world_from_joint * Vec3(x, yz.x(), yz.y())).cast<float>());
    return static_cast<std::uint32_t>(m.vertices.size() - 1);
  };
  auto slice_x = [&](int s) { return s == nx ? plate.x1_mm : plate.x0_mm + len * s / nx; };

  // Side faces: the outline at every cut; quads between neighbouring cuts.
  for (int s = 0; s <= nx; ++s) {
    const double x = slice_x(s);
    for (const Vec2& p : ring) vertex(x, p);
  }
  const auto at = [&](int s, int r) { return static_cast<std::uint32_t>(s * ring_size + r % ring_size); };
  for (int s = 0; s < nx; ++s)
    for (int r = 0; r < ring_size; ++r) {
      // a = (s, r), b = (s + 1, r), c = (s + 1, r + 1), d = (s, r + 1): outward (a, c, b), (a, d, c)
      m.triangles.push_back({at(s, r), at(s + 1, r + 1), at(s + 1, r)});
      m.triangles.push_back({at(s, r), at(s, r + 1), at(s + 1, r + 1)});
    }

  // End caps; counter-clockwise in y-z faces +x (the cap at x1), reversed at x0.
  for (const int s : {0, nx}) {
    const bool flip = s == 0;
    auto tri = [&](std::uint32_t p, std::uint32_t q, std::uint32_t r) {
      if (flip) m.triangles.push_back({p, r, q});
      else m.triangles.push_back({p, q, r});
    };
    const double x = slice_x(s);
    if (!bilinear) {
      Vec2 centre = Vec2::Zero();
      for (const Vec2& p : poly) centre += p / k;
      const std::uint32_t c = vertex(x, centre);
      for (int r = 0; r < ring_size; ++r) tri(c, at(s, r), at(s, r + 1));
      continue;
    }
    // Bilinear grid (i along edge 0, j along edge 1); its border is the ring.
    const Vec2 &p0 = poly[0], &p1 = poly[1], &p2 = poly[2], &p3 = poly[3];
    std::vector<std::uint32_t> grid(static_cast<std::size_t>(a + 1) * (b + 1));
    const auto id = [&](int i, int j) -> std::uint32_t& { return grid[static_cast<std::size_t>(j) * (a + 1) + i]; };
    for (int j = 0; j <= b; ++j)
      for (int i = 0; i <= a; ++i) {
        if (j == 0) id(i, j) = at(s, i);
        else if (i == a) id(i, j) = at(s, a + j);
        else if (j == b) id(i, j) = at(s, a + b + (a - i));
        else if (i == 0) id(i, j) = at(s, 2 * a + b + (b - j));
        else {
          const double u = static_cast<double>(i) / a, v = static_cast<double>(j) / b;
          id(i, j) = vertex(x, (1 - u) * (1 - v) * p0 + u * (1 - v) * p1 + u * v * p2 + (1 - u) * v * p3);
        }
      }
    for (int j = 0; j < b; ++j)
      for (int i = 0; i < a; ++i) {
        tri(id(i, j), id(i + 1, j), id(i + 1, j + 1));
        tri(id(i, j), id(i + 1, j + 1), id(i, j + 1));
      }
  }
  return m;
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
  // The beads, and the groove truth (docs/design/grooves.md); empty, the
  // depth and area above stay (with mismatch the depth is thickness - root
  // face, not measured from the tilted line B1-B5).
  groove::add_plates(JointType::VGroove, p, w, false);
  groove::set_truth(JointType::VGroove, p, w, p.passes == 0);
}

// Single bevel, U and J grooves: plates, beads and truth (sensor/groove.h).
void build_groove(JointType type, const JointParams& p, Workpiece& w) {
  groove::add_plates(type, p, w, true);
  groove::set_truth(type, p, w, false);
}

void build_plate(const JointParams& p, Workpiece& w) {
  w.plates.push_back(rect(-0.5 * p.width_mm, 0.5 * p.width_mm, -p.thickness_mm, 0.0, p.length_mm));
  w.truth.angle_deg = 180.0;
}

}  // namespace

std::optional<tracker::JointType> tracker_joint(JointType type) {
  switch (type) {
    case JointType::Fillet: return tracker::JointType::Fillet;
    case JointType::Corner: return tracker::JointType::Corner;
    case JointType::Lap: return tracker::JointType::Lap;
    case JointType::Butt: return tracker::JointType::Butt;
    case JointType::VGroove: return tracker::JointType::VGroove;
    case JointType::Bevel: return tracker::JointType::Bevel;
    case JointType::UGroove: return tracker::JointType::UGroove;
    case JointType::JGroove: return tracker::JointType::JGroove;
    case JointType::Plate: break;
  }
  return std::nullopt;
}

bool is_groove(JointType type) {
  return type == JointType::VGroove || type == JointType::Bevel || type == JointType::UGroove ||
         type == JointType::JGroove;
}

// The joints are named as the tracker names its templates; the plate is ours.
std::string_view to_string(JointType type) {
  if (type == JointType::Plate) return kPlateName;
  if (const auto t = tracker_joint(type)) return tracker::to_string(*t);
  return "unknown";
}

std::optional<JointType> joint_type_from_string(std::string_view name) {
  if (name == kPlateName) return JointType::Plate;
  const auto t = tracker::joint_type_from_string(name);
  if (!t) return std::nullopt;
  for (const JointType type : {JointType::Fillet, JointType::Corner, JointType::Lap, JointType::Butt, JointType::VGroove,
                               JointType::Bevel, JointType::UGroove, JointType::JGroove})
    if (tracker_joint(type) == t) return type;
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
    case JointType::Bevel:
      p.thickness_mm = 12.0; p.angle_deg = 45.0; p.gap_mm = 1.0; p.root_face_mm = 1.5;
      break;
    case JointType::UGroove:
      p.thickness_mm = 25.0; p.angle_deg = 16.0; p.gap_mm = 1.0; p.root_face_mm = 2.0; p.radius_mm = 5.0;
      break;
    case JointType::JGroove:
      p.thickness_mm = 20.0; p.angle_deg = 20.0; p.gap_mm = 1.0; p.root_face_mm = 2.0; p.radius_mm = 5.0;
      break;
  }
  return p;
}

std::string validate(JointType type, const JointParams& p) {
  const std::pair<std::string_view, double> all[] = {
      {"length_mm", p.length_mm},       {"width_mm", p.width_mm},   {"thickness_mm", p.thickness_mm},
      {"height_mm", p.height_mm},       {"gap_mm", p.gap_mm},       {"angle_deg", p.angle_deg},
      {"mismatch_mm", p.mismatch_mm},   {"root_face_mm", p.root_face_mm}, {"segment_mm", p.segment_mm},
      {"cell_mm", p.cell_mm},           {"layer_mm", p.layer_mm},   {"crown_mm", p.crown_mm},
      {"radius_mm", p.radius_mm}};
  for (const auto& [field, value] : all)
    if (!std::isfinite(value)) return field_error(field, value, "must be a finite number");
  for (const auto& [field, value] : {all[0], all[1], all[2], all[3], all[8], all[10], all[12]})
    if (value <= 0.0) return field_error(field, value, "must be > 0");
  if (p.passes < 0) return field_error("passes", p.passes, "must be >= 0 (0: an empty groove)");
  if (p.passes > kMaxPasses) return field_error("passes", p.passes, "must be at most " + std::to_string(kMaxPasses));
  if (p.gap_mm < 0.0) return field_error("gap_mm", p.gap_mm, "must be >= 0");
  if (p.cell_mm < 0.0) return field_error("cell_mm", p.cell_mm, "must be >= 0 (0: no grid)");
  if (p.length_mm / p.segment_mm > 100000.0)
    return field_error("segment_mm", p.segment_mm, "too small for length_mm (more than 100000 cuts)");
  switch (type) {
    case JointType::Fillet:
      if (p.angle_deg < 30.0 || p.angle_deg > 150.0)
        return field_error("angle_deg", p.angle_deg, "fillet angle must be between 30 and 150 degrees");
      break;
    case JointType::Corner:
      if (p.angle_deg < 90.0 || p.angle_deg >= 180.0)
        return field_error("angle_deg", p.angle_deg, "corner angle must be >= 90 and < 180 degrees");
      if (p.gap_mm >= p.thickness_mm)
        return field_error("gap_mm", p.gap_mm, "corner gap must be smaller than thickness_mm");
      break;
    case JointType::VGroove: {
      if (p.angle_deg <= 0.0 || p.angle_deg >= 150.0)
        return field_error("angle_deg", p.angle_deg, "groove angle must be > 0 and < 150 degrees");
      if (p.root_face_mm < 0.0 || p.root_face_mm >= p.thickness_mm)
        return field_error("root_face_mm", p.root_face_mm, "must be >= 0 and smaller than thickness_mm");
      const double run = (p.thickness_mm - p.root_face_mm) * std::tan(0.5 * p.angle_deg * kDeg);
      if (p.width_mm <= run)
        return field_error("width_mm", p.width_mm, "must exceed the bevel's width across the seam");
      break;
    }
    default: break;
  }
  if (is_groove(type))
    if (std::string err = groove::validate(type, p); !err.empty()) return err;
  if (p.cell_mm > 0.0) {
    std::int64_t triangles = 0;
    for (const Plate& plate : build_workpiece(type, p).plates)
      triangles = std::min(kMaxWorkpieceTriangles + 1,
                           triangles + plate_triangle_count(plate, p.segment_mm, p.cell_mm));
    if (triangles > kMaxWorkpieceTriangles)
      return field_error(
          "cell_mm", p.cell_mm,
          "too small: the mesh would have more than " + std::to_string(kMaxWorkpieceTriangles) + " triangles");
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
    case JointType::Bevel:
    case JointType::UGroove:
    case JointType::JGroove: build_groove(type, params, w); break;
  }
  return w;
}

Workpiece mesh_workpiece(std::shared_ptr<const Mesh> mesh, const Pose& world_from_joint,
                         std::optional<JointType> joint, const MeshLoadStats* stats) {
  Workpiece w;
  w.type = joint.value_or(JointType::Fillet);
  w.params = default_params(w.type);
  w.world_from_joint = world_from_joint;
  w.file_mesh = mesh ? std::move(mesh) : std::make_shared<const Mesh>();
  w.mesh_joint = joint.has_value();
  w.mesh_stats = stats ? *stats : mesh_edge_stats(*w.file_mesh);
  return w;
}

Workpiece saddle_workpiece(const SaddleParams& params, const Pose& world_from_saddle) {
  Workpiece w;
  w.type = JointType::Fillet;
  w.params = default_params(w.type);
  w.world_from_joint = world_from_saddle;
  w.mesh_joint = true;
  w.saddle = std::make_shared<const SaddleParams>(params);
  return w;
}

std::int64_t plate_triangle_count(const Plate& plate, double segment_mm, double cell_mm) {
  const auto& poly = plate.section_yz;
  const double k = static_cast<double>(poly.size());
  const double len = plate.x1_mm - plate.x0_mm;
  const auto cuts = [](double n) { return std::max(1.0, std::ceil(n - 1e-9)); };
  double count = 0.0;
  if (cell_mm <= 0.0) {
    count = 2.0 * cuts(len / segment_mm) * k + 2.0 * (k - 2.0);
  } else {
    const DenseGrid g = dense_grid(plate, segment_mm, cell_mm);
    count = 2.0 * g.nx * g.ring;
    count += poly.size() == 4 ? 2.0 * 2.0 * g.across[0] * g.across[1] : 2.0 * g.ring;
  }
  return static_cast<std::int64_t>(std::min(count, 9e18));
}

Mesh plate_mesh(const Plate& plate, double segment_mm, const Pose& world_from_joint, double cell_mm) {
  if (cell_mm > 0.0) return dense_plate_mesh(plate, segment_mm, world_from_joint, cell_mm);
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
  if (file_mesh) {
    m.triangles = file_mesh->triangles;
    m.vertices.reserve(file_mesh->vertices.size());
    for (const auto& v : file_mesh->vertices)
      m.vertices.push_back((world_from_joint * v.cast<double>()).cast<float>());
  }
  if (saddle) {
    Mesh s = saddle_mesh(*saddle, world_from_joint);
    if (m.triangles.empty()) m = std::move(s);
    else m.append(s);
  }
  for (const auto& p : plates) m.append(plate_mesh(p, params.segment_mm, world_from_joint, params.cell_mm));
  return m;
}

Vec3 Workpiece::seam_origin() const { return world_from_joint * Vec3::Zero(); }
Vec3 Workpiece::seam_direction() const { return world_from_joint.linear() * Vec3::UnitX(); }

Vec2 Workpiece::in_sensor_frame(const Pose& world_from_sensor, const Vec2& joint_yz) const {
  const Pose sensor_from_joint = world_from_sensor.inverse() * world_from_joint;
  // The line through the point along the seam, (x, y, z) for every x, meets
  // the laser plane (sensor x = 0) where r(0,0) x + r(0,1) y + r(0,2) z +
  // t.x = 0: at the sensor's own x when the plane is square to the seam, off
  // it when the sensor leans along the seam or turns about its axis.
  const Eigen::Matrix3d& r = sensor_from_joint.linear();
  const double y = joint_yz.x(), z = joint_yz.y();
  const double x = std::abs(r(0, 0)) > 1e-9
                       ? -(r(0, 1) * y + r(0, 2) * z + sensor_from_joint.translation().x()) / r(0, 0)
                       : (world_from_joint.inverse() * world_from_sensor).translation().x();  // plane along the seam
  const Vec3 s = sensor_from_joint * Vec3(x, y, z);
  return Vec2(s.y(), s.z());
}

Vec2 Workpiece::in_joint_frame(const Pose& world_from_sensor, const Vec2& sensor_yz) const {
  const Vec3 q = world_from_joint.inverse() * world_from_sensor * Vec3(0.0, sensor_yz.x(), sensor_yz.y());
  return Vec2(q.y(), q.z());
}

JointParams with_bead_laid(JointParams p, double offset_mm) {
  p.bead_offsets_mm.resize(static_cast<std::size_t>(std::max(p.passes, 0)), 0.0);
  p.bead_offsets_mm.push_back(offset_mm);
  ++p.passes;
  return p;
}

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
