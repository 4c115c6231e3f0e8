#pragma once
// The camera image's drawing (the physics is sensor/camera_image.h): renders
// the part as the sensor's camera sees it lit by the laser sheet, the
// radiance of every pixel of the region of interest in two channels (laser,
// ambient), with OSMesa. Two draws per image: the laser's own depth map over
// a thin frustum around the sheet (what the laser reaches), then the
// camera's view with the sheet's irradiance, the surface's diffuse and
// specular reflection and the vignetting evaluated per pixel
// (shaders/camera_image.frag). Only plain data leaves: a RadianceImage.
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

  // The radiance of the description's region of interest (image_roi) for
  // the laser at world_from_sensor. No allocation once `out` has this size.
  void render(const Pose& world_from_sensor, RadianceImage& out);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace vts
