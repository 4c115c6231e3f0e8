#pragma once
// vts-view's OpenGL drawing. Only plain data crosses this header: meshes go in
// as vts::Mesh, each frame as a SceneView (instances, lines, translucent
// triangles, points), screenshots come out as RGB bytes. The caller owns the
// window and its OpenGL 3.3+ core context; every call needs it current.
#include <cstdint>
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "sensor/mesh.h"

namespace vts::viewer {

// Linear colour, components 0..1.
struct Rgba {
  float r = 1.0f, g = 1.0f, b = 1.0f, a = 1.0f;
};

struct ColorVertex {
  Eigen::Vector3f position_mm = Eigen::Vector3f::Zero();  // world frame
  Rgba color;
};

// An uploaded mesh (Renderer::add_mesh) placed in the world.
struct MeshInstance {
  int mesh = -1;
  Eigen::Matrix4f world_from_model = Eigen::Matrix4f::Identity();  // rigid
  Rgba color;
};

// One frame's content besides the uploaded meshes. Drawn in this order:
// meshes (lit, pushed back slightly in depth so lines and points lying on
// their surfaces win), lines, translucent triangles (blended, no depth
// write), points (opaque, unlit, exactly their colour: the viewer's laser
// line relies on this).
struct SceneView {
  int x = 0, y = 0, width = 0, height = 0;  // viewport, framebuffer pixels, origin bottom-left
  Eigen::Matrix4f clip_from_world = Eigen::Matrix4f::Identity();
  Eigen::Vector3f eye_world = Eigen::Vector3f::Zero();  // camera position, mm
  std::vector<MeshInstance> meshes;
  std::vector<ColorVertex> lines;                  // pairs
  std::vector<ColorVertex> translucent_triangles;  // triples
  std::vector<ColorVertex> points;
  float point_size_px = 4.0f;
};

class Renderer {
 public:
  // Compiles the viewer shaders. Throws std::runtime_error naming the shader
  // and the compiler's log on failure.
  Renderer();
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  // Uploads a mesh (model frame, mm); returns its id for MeshInstance::mesh.
  // smooth_normals averages the normals of triangles sharing a vertex (for
  // round things such as the torch); otherwise every triangle is flat.
  int add_mesh(const Mesh& mesh, bool smooth_normals = false);
  // Frees every uploaded mesh; ids restart at 0.
  void clear_meshes();

  // Clears the whole framebuffer (width x height pixels) to `background`.
  void clear(int width, int height, Rgba background);
  void draw(const SceneView& view);

  // Uploads a greyscale image (`bits` per pixel in 16-bit words, rows top to
  // bottom) into the renderer's one image texture, shown as 8 bits, and
  // returns the texture's OpenGL name (for ImGui::Image).
  unsigned grey_texture(const std::vector<std::uint16_t>& pixels, int width, int height, int bits);

  // The current read buffer (the window's back buffer after drawing), RGB8,
  // rows top to bottom, width * height * 3 bytes.
  std::vector<std::uint8_t> read_pixels_rgb(int width, int height) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace vts::viewer
