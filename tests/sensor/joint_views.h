#pragma once
// What the tracker accuracy tests (tracker_accuracy_test.cpp, ideal profiles;
// tracker_noisy_test.cpp, measured ones) share: their tolerances, the sensor
// looking at a built-in joint's root from a tilted view, the joint's
// cross-section in the sensor frame, and the ray spacing along a surface
// (and at each joint's edges) worked out from the column geometry (sensor/rays.h's definition), never
// from the tracker's own output.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <sstream>
#include <string>

#include "sensor/cell.h"
#include "sensor/profile.h"
#include "sensor/workpiece.h"
#include "tracker/tracker.h"

namespace vts::test {

namespace tk = vts::tracker;

inline constexpr double kDeg = std::numbers::pi / 180.0;
// The tolerances on ideal profiles.
inline constexpr double kTrackTolMm = 0.05;
inline constexpr double kGapTolMm = 0.1;
inline constexpr double kAngleTolDeg = 0.5;
inline constexpr double kSeamX = 100.0;  // the laser plane cuts the seam here

// The joint's template; a lap template knows the nominal upper plate thickness.
inline tk::TrackerParams params_for(const Workpiece& w) {
  tk::TrackerParams tp;
  const auto joint = tracker_joint(w.type);
  REQUIRE(joint);
  tp.joint = *joint;
  if (w.type == JointType::Lap) tp.lap.upper_thickness_mm = w.params.thickness_mm;
  return tp;
}

// The sensor at `pose` looking at workpiece `w`, with its scanner.
struct JointView {
  Pose pose = Pose::Identity();
  const Workpiece* w = nullptr;
  ScannerDesc desc;

  // Joint-frame cross-section point -> sensor frame (y, z).
  Vec2 to_sensor(const Vec2& yz) const {
    const Vec3 s = pose.inverse() * (w->world_from_joint * Vec3(kSeamX, yz.x(), yz.y()));
    return Vec2(s.y(), s.z());
  }
  Vec2 dir_to_sensor(const Vec2& u) const {
    const Vec3 d = pose.linear().transpose() * (w->world_from_joint.linear() * Vec3(0.0, u.x(), u.y()));
    return Vec2(d.y(), d.z()).normalized();
  }
  // Distance between neighbouring columns' hits along the surface through
  // joint point e with joint direction u: the angular step of the columns at
  // that ray (tangents are evenly spaced, sensor/rays.h) times the range,
  // divided by the sine of the angle between the ray and the surface.
  double spacing_along(const Vec2& e, const Vec2& u) const {
    const Vec2 es = to_sensor(e), us = dir_to_sensor(u);
    const double dt = 2.0 * std::tan(0.5 * desc.fan_deg * kDeg) / desc.points;
    const double t = es.x() / es.y();
    const double r = es.norm();
    const Vec2 rho = es / r;
    const double sine = std::abs(rho.x() * us.y() - rho.y() * us.x());
    return 1.05 * r * dt / (1.0 + t * t) / std::max(sine, 1e-3);
  }
};

// The laser looking at the root of `w` (shifted by shift_mm across the view)
// from the joint's natural direction turned by tilt_deg about the seam, at
// standoff_mm, travelling along the seam.
inline Pose root_view(const Workpiece& w, double standoff_mm, double tilt_deg, double shift_mm = 0.0) {
  const Vec3 view_joint = Eigen::AngleAxisd(tilt_deg * kDeg, Vec3::UnitX()) * default_view_direction(w);
  const Vec3 across = view_joint.cross(Vec3::UnitX()).normalized();
  const Vec3 target =
      w.world_from_joint * (Vec3(kSeamX, w.truth.root_yz.x(), w.truth.root_yz.y()) + shift_mm * across);
  return sensor_pose_looking_at(target, w.world_from_joint.linear() * view_joint, standoff_mm, w.seam_direction());
}

inline const Vec2& feature(const Workpiece& w, const std::string& name) {
  for (const auto& [n, p] : w.truth.features)
    if (n == name) return p;
  FAIL("no feature " << name);
  static Vec2 none;
  return none;
}

// The ray spacing along the surface (JointView::spacing_along) at the two
// edges that bound each joint: fillet, the web's toe along the web (second
// 0); corner, each plate's inner edge along its outer face; lap, the upper
// plate's top edge along its top and its bottom edge up the edge face; butt,
// each plate's edge across the seam; v-groove, each root up its bevel.
struct EdgeSpacings {
  double first = 0.0, second = 0.0;
};

inline EdgeSpacings edge_spacings(const JointView& s) {
  const Workpiece& w = *s.w;
  switch (w.type) {
    case JointType::Fillet: {
      const double a = w.params.angle_deg * kDeg;
      return {s.spacing_along(feature(w, "web_toe"), Vec2(std::cos(a), std::sin(a))), 0.0};
    }
    case JointType::Corner: {
      const double h = 0.5 * w.params.angle_deg * kDeg;
      return {s.spacing_along(feature(w, "left_edge"), Vec2(-std::sin(h), -std::cos(h))),
              s.spacing_along(feature(w, "right_edge"), Vec2(std::sin(h), -std::cos(h)))};
    }
    case JointType::Lap:
      return {s.spacing_along(feature(w, "edge_top"), Vec2(1.0, 0.0)),
              s.spacing_along(feature(w, "edge_bottom"), Vec2(0.0, 1.0))};
    case JointType::Butt:
      return {s.spacing_along(feature(w, "left_edge"), Vec2(1.0, 0.0)),
              s.spacing_along(feature(w, "right_edge"), Vec2(1.0, 0.0))};
    case JointType::VGroove: {
      const Vec2 lr = feature(w, "left_root"), rr = feature(w, "right_root");
      return {s.spacing_along(lr, (feature(w, "left_top") - lr).normalized()),
              s.spacing_along(rr, (feature(w, "right_top") - rr).normalized())};
    }
    default: return {};
  }
}

inline tk::ProfileView view_of(const Profile& p) { return {p.y_mm, p.z_mm, p.valid}; }

// The largest value seen per joint and quantity, for the summary line.
struct Worst {
  std::map<std::string, double> value;
  int scans = 0;
  int unsure = 0;  // rejected as weak or ambiguous (tracker::ConfidenceParams)
  void add(const std::string& key, double v) { value[key] = std::max(value[key], v); }
  std::string str() const {
    std::ostringstream o;
    for (const auto& [k, v] : value) o << k << " " << v << "; ";
    if (scans > 0) o << unsure << " of " << scans << " scans not sure";
    return o.str();
  }
};

}  // namespace vts::test
