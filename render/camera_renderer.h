#pragma once
// The camera image's drawing (the physics is sensor/camera_image.h): the
// ambient light's radiance of every pixel of the region of interest, from
// which pixels see the part, drawn with OSMesa (one draw per image,
// shaders/camera_image.vert and camera_coverage.frag; the triangles facing
// away from the camera culled on a closed mesh, mesh_orientation), and each
// such pixel's ambient_radiance (a table made once). The laser
// light (the stripe, its bounce and mirror images) is traced on the CPU
// (trace_laser_paths) and added by form_image. Only plain data leaves: a
// RadianceImage whose laser channel is zero.
#include <memory>

#include "sensor/camera_image.h"
#include "sensor/mesh.h"
#include "sensor/pose.h"
#include "sensor/scanner.h"

namespace vts {

class CameraRenderer {
 public:
  // Uploads the mesh (world frame, mm) once, into an OpenGL context of the
  // renderer's own. Throws std::invalid_argument if validate(desc) fails or a
  // triangle indexes past the vertex list, std::runtime_error if the context
  // or a shader fails. One renderer is used by one thread at a time; it may
  // be destroyed on any thread.
  CameraRenderer(const ScannerDesc& desc, const Mesh& mesh_world);
  ~CameraRenderer();
  CameraRenderer(const CameraRenderer&) = delete;
  CameraRenderer& operator=(const CameraRenderer&) = delete;

  // The ambient radiance of the description's region of interest
  // (image_roi) for the sensor at world_from_sensor; the laser channel is
  // cleared. No allocation once `out` has this size.
  void render(const Pose& world_from_sensor, RadianceImage& out);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace vts
