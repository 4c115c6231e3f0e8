#include "sensor/pose.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace vts {
namespace {
constexpr double kDeg = std::numbers::pi / 180.0;
}

Pose pose_from_xyz_rpy(const Vec3& position_mm, const Vec3& rpy_deg) {
  Pose p = Pose::Identity();
  p.linear() = (Eigen::AngleAxisd(rpy_deg.z() * kDeg, Vec3::UnitZ()) *
                Eigen::AngleAxisd(rpy_deg.y() * kDeg, Vec3::UnitY()) *
                Eigen::AngleAxisd(rpy_deg.x() * kDeg, Vec3::UnitX()))
                   .toRotationMatrix();
  p.translation() = position_mm;
  return p;
}

Vec3 rpy_deg_of(const Pose& pose) {
  const Eigen::Matrix3d& r = pose.linear();
  // R = Rz(y) Ry(p) Rx(r): r20 = -sin(p). atan2 of both the sine and the
  // cosine keeps full precision near pitch = +-90 degrees, where asin does not.
  const double cos_pitch = std::hypot(r(0, 0), r(1, 0));
  const double pitch = std::atan2(-r(2, 0), cos_pitch);
  if (cos_pitch < 1e-12)  // gimbal lock: roll and yaw share one axis; put it all in yaw
    return Vec3(0.0, pitch, std::atan2(-r(0, 1), r(1, 1))) / kDeg;
  return Vec3(std::atan2(r(2, 1), r(2, 2)), pitch, std::atan2(r(1, 0), r(0, 0))) / kDeg;
}

bool pose_look_at(const Vec3& eye_mm, const Vec3& target_mm, const Vec3& travel, Pose& out) {
  const Vec3 axis = target_mm - eye_mm;
  if (axis.norm() < 1e-9) return false;
  const Vec3 z = axis.normalized();
  const Vec3 x_raw = travel - travel.dot(z) * z;
  if (x_raw.norm() < 1e-9) return false;
  const Vec3 x = x_raw.normalized();
  const Vec3 y = z.cross(x);  // right-handed: x = y cross z
  out = Pose::Identity();
  out.linear().col(0) = x;
  out.linear().col(1) = y;
  out.linear().col(2) = z;
  out.translation() = eye_mm;
  return true;
}

Eigen::Quaterniond rotation_quat(const Pose& pose) {
  Eigen::Quaterniond q(pose.linear());
  q.normalize();
  if (q.w() < 0) q.coeffs() *= -1.0;
  return q;
}

Pose pose_from_quat(const Vec3& position_mm, const Eigen::Quaterniond& q) {
  Pose p = Pose::Identity();
  p.linear() = q.normalized().toRotationMatrix();
  p.translation() = position_mm;
  return p;
}

}  // namespace vts
