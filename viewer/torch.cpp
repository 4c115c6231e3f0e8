#include "viewer/torch.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "sensor/reference_source.h"

namespace vts::viewer {
namespace {
constexpr double kDeg = std::numbers::pi / 180.0;

Eigen::Matrix3d rotation_of(const Vec3& axes, double angle_rad) {
  const Eigen::Matrix3d r = (Eigen::AngleAxisd(axes.x() * angle_rad, Vec3::UnitX()) *
                             Eigen::AngleAxisd(axes.y() * angle_rad, Vec3::UnitY()) *
                             Eigen::AngleAxisd(axes.z() * angle_rad, Vec3::UnitZ()))
                                .toRotationMatrix();
  return r;
}
}  // namespace

Pose default_tool_from_laser(double standoff_mm) {
  Pose p = Pose::Identity();
  p.translation() = Vec3(kLookAheadMm, 0.0, -standoff_mm);
  return p;
}

double standoff_at_start(const Cell& cell, double fallback_mm) {
  ScannerDesc desc = cell.scanner;
  // An odd column count has a column exactly on the optical axis.
  desc.points = 65;
  auto source = make_reference_source(desc, cell.mesh());
  Profile p;
  source->scan(cell.path.start, p);
  for (int k : {32, 31, 33, 30, 34})
    if (p.valid[k]) return p.range_mm[k];
  return fallback_mm;
}

Pose move_torch(const Pose& world_from_torch, const MotionInput& in, double speed_mm_s,
                double turn_deg_s, double dt_s, bool world_axes) {
  Pose out = world_from_torch;
  const Vec3 step = in.translate * speed_mm_s * dt_s;
  const Eigen::Matrix3d turn = rotation_of(in.rotate, turn_deg_s * kDeg * dt_s);
  if (world_axes) {
    out.translation() += step;
    out.linear() = turn * out.linear();
  } else {
    out.translation() += out.linear() * step;
    out.linear() = out.linear() * turn;
  }
  // Keep the rotation orthonormal over many small steps.
  out.linear() = Eigen::Quaterniond(out.linear()).normalized().toRotationMatrix();
  return out;
}

Pose interpolate(const Pose& a, const Pose& b, double t) {
  const Eigen::Quaterniond qa(a.linear()), qb(b.linear());
  Pose p = Pose::Identity();
  p.linear() = qa.slerp(t, qb).toRotationMatrix();
  p.translation() = (1.0 - t) * a.translation() + t * b.translation();
  return p;
}

std::vector<ScanClock::Due> ScanClock::advance(double dt_s, int max_scans) {
  std::vector<Due> due;
  if (dt_s <= 0.0 || rate_hz <= 0.0) return due;
  double end = time_s + dt_s;
  while (static_cast<double>(next_scan) / rate_hz <= end) {
    if (static_cast<int>(due.size()) == max_scans) {
      end = due.back().time_s;
      break;
    }
    const double t = static_cast<double>(next_scan) / rate_hz;
    due.push_back({next_scan, t, 0.0});
    ++next_scan;
  }
  const double span = end - time_s;
  for (Due& d : due) d.fraction = span > 0.0 ? std::clamp((d.time_s - time_s) / span, 0.0, 1.0) : 1.0;
  time_s = end;
  return due;
}

}  // namespace vts::viewer
