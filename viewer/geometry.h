#pragma once
// Simple solids for vts-view: the torch, the sensor housing, the camera.
// Plain meshes (mm), no GL; Renderer::add_mesh uploads them.
//
// Tool frame (the torch): origin at the TCP (wire tip), z along the torch
// axis pointing into the work, x the travel direction, y = z cross x.
// Laser frame: the sensor frame of sensor/scanner.h (origin at the laser,
// z the optical axis, y along the laser line, x = y cross z).
#include <Eigen/Core>

#include "sensor/mesh.h"

namespace vts::viewer {

// Closed truncated cone along z from z0 (radius r0) to z1 (radius r1).
Mesh cone_z(float r0, float r1, float z0, float z1, int segments = 32);
// Axis-aligned closed box.
Mesh box(const Eigen::Vector3f& lo, const Eigen::Vector3f& hi);
// A square beam of width w from a to b (a != b).
Mesh beam(const Eigen::Vector3f& a, const Eigen::Vector3f& b, float width);

// Torch nozzle and wire, tool frame: wire stick-out 15 mm, nozzle up to
// 70 mm above the TCP. Drawn in copper.
Mesh torch_nozzle_mesh();
// The torch neck and body above the nozzle, tool frame, up to 260 mm.
Mesh torch_body_mesh();

// Sensor housing, laser frame: a box above the laser origin (z < 0)
// enclosing the camera at camera_centre_mm (laser frame), whose lens pokes
// out of the bottom.
Mesh sensor_housing_mesh(const Eigen::Vector3f& camera_centre_mm);
// Camera body, its own frame: z the viewing direction, lens at the origin.
Mesh camera_body_mesh();

}  // namespace vts::viewer
