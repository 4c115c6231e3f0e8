#include "pipeline/profile_truth.h"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace vts {
namespace {

namespace tk = vts::tracker;

double cross(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

// Column rays run from negative to positive y / z (sensor/rays.h).
bool before(const Vec2& a, const Vec2& b) { return a.x() / a.y() < b.x() / b.y(); }

}  // namespace

ProfileTruth profile_truth(const Workpiece& w, const ScannerDesc& scanner, const Pose& pose) {
  const auto joint = tracker_joint(w.type);
  if (w.is_mesh() || !joint)
    throw std::invalid_argument("profile_truth: the workpiece has no joint (" + std::string(to_string(w.type)) + ")");
  const JointTruth& t = w.truth;
  auto s = [&](const Vec2& yz) { return w.in_sensor_frame(pose, yz); };
  ProfileTruth out;
  out.joint = *joint;
  const bool groove = is_groove(w.type);
  out.track_point = s(groove ? t.track_yz : t.root_yz);
  for (const auto& [name, yz] : t.features) out.features.emplace_back(name, s(yz));
  auto feature = [&](std::string_view name) {
    for (const auto& [n, yz] : t.features)
      if (n == name) return s(yz);
    throw std::logic_error("profile_truth: no feature " + std::string(name));
  };
  out.gap_mm = t.gap_mm;
  out.angle_deg = t.angle_deg;
  auto& bp = out.break_points;
  const Vec2 root = s(t.root_yz);
  switch (w.type) {
    case JointType::Fillet: {
      bp[1] = bp[2] = bp[3] = root;
      if (t.gap_mm > 0.0) {
        // The ray past the web edge meets the flange's line (joint y axis).
        const Vec2 toe = feature("web_toe");
        const Vec2 flange = s(Vec2(1.0, 0.0)) - root;
        bp[3] = toe;
        bp[2] = cross(root, flange) / cross(toe, flange) * toe;
      }
      break;
    }
    case JointType::Corner: {
      Vec2 a = feature("left_edge"), b = feature("right_edge");
      if (!before(a, b)) std::swap(a, b);
      const double half = 0.5 * w.params.angle_deg * std::numbers::pi / 180.0;
      bp[1] = a, bp[3] = b;
      bp[2] = s(Vec2(0.0, 0.5 * t.gap_mm / std::tan(half)));
      break;
    }
    case JointType::Lap:
      bp[1] = feature("foot"), bp[2] = feature("edge_bottom"), bp[3] = feature("edge_top");
      out.step_mm = t.step_mm;
      break;
    case JointType::Butt: {
      Vec2 a = feature("left_edge"), b = feature("right_edge");
      if (!before(a, b)) std::swap(a, b);
      bp[1] = a, bp[2] = root, bp[3] = b;
      out.mismatch_mm = t.mismatch_mm;
      break;
    }
    case JointType::VGroove:
    case JointType::Bevel:
    case JointType::UGroove:
    case JointType::JGroove: {
      Vec2 top1 = s(t.top_a_yz), top2 = s(t.top_b_yz), toe1 = s(t.toe_a_yz), toe2 = s(t.toe_b_yz);
      double wall1 = t.wall_angle_a_deg, wall2 = t.wall_angle_b_deg;
      if (!before(top1, top2)) std::swap(top1, top2), std::swap(toe1, toe2), std::swap(wall1, wall2);
      bp[1] = top1, bp[2] = toe1, bp[3] = out.track_point, bp[4] = toe2, bp[5] = top2;
      out.wall_angle_a_deg = wall1, out.wall_angle_b_deg = wall2;
      out.mismatch_mm = t.mismatch_mm;
      out.depth_mm = t.depth_mm;
      out.area_mm2 = t.area_mm2;
      out.top_width_mm = t.top_width_mm;
      out.fill_lowest = s(t.fill_lowest_yz);
      break;
    }
    case JointType::Plate: break;  // refused above
  }
  const Vec2& tp = out.track_point;
  const double half_fan = std::tan(0.5 * scanner.fan_deg * std::numbers::pi / 180.0);
  out.in_window = tp.y() >= scanner.min_range_mm && tp.y() <= scanner.max_range_mm &&
                  std::abs(tp.x()) <= half_fan * tp.y();
  return out;
}

trackio::Json profile_truth_json(const ProfileTruth& t) {
  using trackio::Json;
  const auto point = [](const Vec2& p) { return Json{{"y", p.x()}, {"z", p.y()}}; };
  Json j;
  j["in_window"] = t.in_window;
  j["track_point"] = point(t.track_point);
  Json bps = Json::array();
  for (int b = 0; b < tk::kMaxBreakPoints; ++b) {
    if (!t.break_points[b]) continue;
    const char name[3] = {'B', static_cast<char>('0' + b), '\0'};
    Json bp{{"name", name}, {"meaning", std::string(tk::break_point_name(t.joint, b))}};
    bp.update(point(*t.break_points[b]));
    bps.push_back(std::move(bp));
  }
  j["break_points"] = std::move(bps);
  // NaN (does not apply) is written as null.
  j["gap_mm"] = t.gap_mm;
  j["angle_deg"] = t.angle_deg;
  j["mismatch_mm"] = t.mismatch_mm;
  j["step_mm"] = t.step_mm;
  j["depth_mm"] = t.depth_mm;
  j["area_mm2"] = t.area_mm2;
  j["top_width_mm"] = t.top_width_mm;
  j["wall_angle_a_deg"] = t.wall_angle_a_deg;
  j["wall_angle_b_deg"] = t.wall_angle_b_deg;
  j["fill_lowest"] = t.fill_lowest ? point(*t.fill_lowest) : Json();
  Json features = Json::object();
  for (const auto& [name, yz] : t.features) features[name] = point(yz);
  j["features"] = std::move(features);
  return j;
}

}  // namespace vts
