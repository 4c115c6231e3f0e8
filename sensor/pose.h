#pragma once
// Rigid poses in millimetres. A Pose maps coordinates of its child frame into
// its parent frame: world_from_sensor * p_sensor = p_world.
#include <Eigen/Geometry>

namespace vts {

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;
using Pose = Eigen::Isometry3d;

// Fixed-axis roll-pitch-yaw in degrees: R = Rz(yaw) * Ry(pitch) * Rx(roll).
Pose pose_from_xyz_rpy(const Vec3& position_mm, const Vec3& rpy_deg);
Vec3 rpy_deg_of(const Pose& pose);

// Sensor pose at eye_mm whose optical axis (z) points at target_mm and whose
// travel direction (x) is travel projected perpendicular to z.
// Returns false (pose untouched) if eye == target or travel is parallel to z.
bool pose_look_at(const Vec3& eye_mm, const Vec3& target_mm, const Vec3& travel, Pose& out);

// Unit quaternion (w, x, y, z) of the rotation, w >= 0.
Eigen::Quaterniond rotation_quat(const Pose& pose);
Pose pose_from_quat(const Vec3& position_mm, const Eigen::Quaterniond& q);

}  // namespace vts
