#pragma once
// vts-view's orbit camera: pure math, no GL. World z is up.
#include <optional>

#include <Eigen/Core>

#include "sensor/pose.h"

namespace vts::viewer {

struct OrbitCamera {
  Vec3 target_mm = Vec3::Zero();  // world point the camera orbits and looks at
  double distance_mm = 400.0;     // eye to target
  double yaw_deg = -60.0;         // eye direction around world z, from +x
  double pitch_deg = 30.0;        // eye elevation above the x-y plane, -89..89
  double fov_y_deg = 35.0;

  Vec3 eye_mm() const;
  Eigen::Matrix4d clip_from_world(double aspect) const;  // OpenGL clip space

  // Mouse gestures, in window pixels.
  void orbit(double dx_px, double dy_px);
  void pan(double dx_px, double dy_px, int viewport_height_px);
  void zoom(double wheel_steps);  // > 0 moves closer
};

// A camera looking at `target` from the side of `view_from` (a world
// direction from the target towards the eye), at distance_mm.
OrbitCamera camera_looking_at(const Vec3& target, const Vec3& view_from, double distance_mm);

// Window pixel (x right, y down from the viewport's top-left) of a world
// point, or nothing if it is behind the camera.
std::optional<Vec2> project_to_pixel(const Eigen::Matrix4d& clip_from_world, const Vec3& p_world,
                                     int viewport_width, int viewport_height);

}  // namespace vts::viewer
