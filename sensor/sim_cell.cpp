#include "sensor/sim_cell.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

#include "sensor/error_model.h"
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

std::string bad(const char* field, double value, const char* why) {
  std::ostringstream s;
  s << field << " = " << value << ": " << why;
  return s.str();
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

}  // namespace

Vec3 SimSeamTruth::lateral() const {
  Vec3 l = plate_normal.cross(direction()).normalized();
  return l.dot(wall_normal) < 0.0 ? Vec3(-l) : l;
}

std::string validate(const SimCellParams& p) {
  const std::pair<const char*, double> positive[] = {
      {"box_side_mm", p.box_side_mm},         {"box_height_mm", p.box_height_mm},
      {"plate_side_mm", p.plate_side_mm},     {"plate_thickness_mm", p.plate_thickness_mm},
      {"lookahead_mm", p.lookahead_mm},       {"standoff_mm", p.standoff_mm}};
  for (const auto& [f, v] : positive)
    if (!std::isfinite(v) || v <= 0.0) return bad(f, v, "must be a finite number > 0");
  if (!std::isfinite(p.offset_mm) || p.offset_mm < 0.0 || p.offset_mm > 50.0)
    return bad("offset_mm", p.offset_mm, "must be between 0 and 50 mm");
  if (!std::isfinite(p.rotation_deg) || p.rotation_deg < 0.0 || p.rotation_deg > 20.0)
    return bad("rotation_deg", p.rotation_deg, "must be between 0 and 20 degrees");
  if (p.plate_side_mm < p.box_side_mm + 40.0)
    return bad("plate_side_mm", p.plate_side_mm, "must exceed box_side_mm by at least 40 mm");
  if (!std::isfinite(p.seam1_short_mm) || p.seam1_short_mm < 0.0 || p.seam1_short_mm > 0.8 * p.box_side_mm)
    return bad("seam1_short_mm", p.seam1_short_mm, "must be between 0 and 0.8 box_side_mm");
  if (!std::isfinite(p.seam1_gap_rise_mm) || p.seam1_gap_rise_mm < 0.0 || p.seam1_gap_rise_mm > 5.0)
    return bad("seam1_gap_rise_mm", p.seam1_gap_rise_mm, "must be between 0 and 5 mm");
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
  cell.mesh.append(plate_mesh(block(-h, x1, -h, h, 0.0, p.box_height_mm), 10.0, actual * plate_from_box));

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

  cell.tool_from_laser = Pose::Identity();
  cell.tool_from_laser.translation() = Vec3(p.lookahead_mm, 0.0, -p.standoff_mm);
  return cell;
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
  // the offset plus the rotation's sweep at the box corner, plus 5 mm.
  m.search_margin_mm =
      p.offset_mm + std::sqrt(0.5) * p.box_side_mm * std::sin(p.rotation_deg * kDeg) + 5.0;
  return m;
}

PointError seam_error(const SimSeamTruth& seam, const Vec3& tcp) {
  const Vec3 d = seam.direction();
  const double s = std::clamp((tcp - seam.start).dot(d), 0.0, seam.length());
  PointError e;
  e.true_point = seam.start + s * d;
  const Vec3 r = tcp - e.true_point;
  e.lateral_mm = r.dot(seam.lateral());
  e.vertical_mm = r.dot(seam.plate_normal);
  return e;
}

std::vector<SeamMetrics> evaluate(const SimCell& cell, const tracker::MasterResult& result) {
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
    double sl = 0.0, sv = 0.0;
    for (const auto& smp : result.samples) {
      if (smp.seam != static_cast<int>(k) || smp.phase != tracker::Phase::Weld) continue;
      const Vec3 tcp = smp.world_from_tool.translation();
      const PointError e = seam_error(truth, tcp);
      sl += e.lateral_mm * e.lateral_mm;
      sv += e.vertical_mm * e.vertical_mm;
      m.max_error_mm = std::max(m.max_error_mm, std::hypot(e.lateral_mm, e.vertical_mm));
      ++m.samples;
    }
    double sp = 0.0;
    for (const Vec3& p : run.track_points) {
      const PointError e = seam_error(truth, p);
      sp += e.lateral_mm * e.lateral_mm + e.vertical_mm * e.vertical_mm;
    }
    if (!run.track_points.empty()) m.sensor_rms_mm = std::sqrt(sp / run.track_points.size());
    m.welded = run.start_found && m.samples > 0;
    if (m.samples > 0) {
      m.rms_lateral_mm = std::sqrt(sl / m.samples);
      m.rms_vertical_mm = std::sqrt(sv / m.samples);
    }
    m.start_error_mm = m.welded ? (run.weld_start - truth.start).norm() : 0.0;
    m.end_error_mm = m.welded ? (run.weld_end - truth.end).norm() : 0.0;
    m.start_along_mm = m.welded ? (run.weld_start - truth.start).dot(truth.direction()) : 0.0;
    m.end_along_mm = m.welded ? (run.weld_end - truth.end).dot(truth.direction()) : 0.0;
    out.push_back(m);
  }
  return out;
}

}  // namespace vts
