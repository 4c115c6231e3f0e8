#include "viewer/camera.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace vts::viewer {
namespace {
constexpr double kDeg = std::numbers::pi / 180.0;
}

Vec3 OrbitCamera::eye_mm() const {
  const double y = yaw_deg * kDeg, p = pitch_deg * kDeg;
  return target_mm + distance_mm * Vec3(std::cos(p) * std::cos(y), std::cos(p) * std::sin(y), std::sin(p));
}

Eigen::Matrix4d OrbitCamera::clip_from_world(double aspect) const {
  const Vec3 eye = eye_mm();
  const Vec3 f = (target_mm - eye).normalized();
  Vec3 s = f.cross(Vec3::UnitZ());
  if (s.norm() < 1e-9) s = Vec3::UnitX();
  s.normalize();
  const Vec3 u = s.cross(f);
  Eigen::Matrix4d view = Eigen::Matrix4d::Identity();
  view.block<1, 3>(0, 0) = s.transpose();
  view.block<1, 3>(1, 0) = u.transpose();
  view.block<1, 3>(2, 0) = -f.transpose();
  view(0, 3) = -s.dot(eye);
  view(1, 3) = -u.dot(eye);
  view(2, 3) = f.dot(eye);

  // Near and far follow the distance so depth precision stays useful at
  // every zoom level.
  const double near = std::max(0.5, 0.02 * distance_mm);
  const double far = 20.0 * distance_mm + 2000.0;
  const double t = 1.0 / std::tan(0.5 * fov_y_deg * kDeg);
  Eigen::Matrix4d proj = Eigen::Matrix4d::Zero();
  proj(0, 0) = t / std::max(aspect, 1e-6);
  proj(1, 1) = t;
  proj(2, 2) = -(far + near) / (far - near);
  proj(2, 3) = -2.0 * far * near / (far - near);
  proj(3, 2) = -1.0;
  return proj * view;
}

void OrbitCamera::orbit(double dx_px, double dy_px) {
  yaw_deg = std::remainder(yaw_deg - 0.3 * dx_px, 360.0);
  pitch_deg = std::clamp(pitch_deg + 0.3 * dy_px, -89.0, 89.0);
}

void OrbitCamera::pan(double dx_px, double dy_px, int viewport_height_px) {
  const Vec3 eye = eye_mm();
  const Vec3 f = (target_mm - eye).normalized();
  Vec3 s = f.cross(Vec3::UnitZ());
  if (s.norm() < 1e-9) s = Vec3::UnitX();
  s.normalize();
  const Vec3 u = s.cross(f);
  // One pixel at the target's depth, in mm: the target stays under the cursor.
  const double mm_per_px =
      2.0 * distance_mm * std::tan(0.5 * fov_y_deg * kDeg) / std::max(viewport_height_px, 1);
  target_mm += mm_per_px * (-dx_px * s + dy_px * u);
}

void OrbitCamera::zoom(double wheel_steps) {
  distance_mm = std::clamp(distance_mm * std::pow(0.88, wheel_steps), 20.0, 20000.0);
}

OrbitCamera camera_looking_at(const Vec3& target, const Vec3& view_from, double distance_mm) {
  OrbitCamera c;
  c.target_mm = target;
  c.distance_mm = distance_mm;
  const Vec3 d = view_from.normalized();
  c.pitch_deg = std::clamp(std::asin(std::clamp(d.z(), -1.0, 1.0)) / kDeg, -89.0, 89.0);
  c.yaw_deg = std::atan2(d.y(), d.x()) / kDeg;
  return c;
}

std::optional<Vec2> project_to_pixel(const Eigen::Matrix4d& clip_from_world, const Vec3& p,
                                     int width, int height) {
  const Eigen::Vector4d c = clip_from_world * p.homogeneous();
  if (c.w() <= 1e-9) return std::nullopt;
  const double x = c.x() / c.w(), y = c.y() / c.w();
  return Vec2((x * 0.5 + 0.5) * width, (0.5 - y * 0.5) * height);
}

}  // namespace vts::viewer
