#include "render/camera_renderer.h"

#include <GL/gl.h>
#include <GL/glext.h>

#include <algorithm>
#include <cstdint>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "render/gl_context.h"
#include "render/gl_program.h"
#include "shaders/embedded.h"

namespace vts {
namespace {

constexpr const char* kWho = "camera image";
// Depth range of the projection, mm.
constexpr double kNearMm = 1.0;
// GL's face (counter-clockwise in the window is GL_FRONT) of a triangle
// wound counter-clockwise seen from the camera: its normal faces the camera
// (-z in camera coordinates), so its signed area in the camera's (x, y) is
// negative, also after the perspective division (z > 0); the window's x is
// the image column (the camera's y) and its y the row (the camera's x), a
// swap, which makes the area positive: counter-clockwise in the window.
constexpr GLenum kTowardCamera = GL_FRONT;
constexpr GLenum kAwayFromCamera = GL_BACK;

// z_clip = a w + b maps w = near..far to -1..1.
Eigen::Vector2f depth_ab(double near, double far) {
  return {static_cast<float>((far + near) / (far - near)), static_cast<float>(-2.0 * far * near / (far - near))};
}

}  // namespace

struct CameraRenderer::Impl {
  ScannerDesc desc;
  CameraGeometry cam;
  GlContext context{GlContext::After::Previous};
  Eigen::Vector3d mesh_centre = Eigen::Vector3d::Zero();
  GLsizei index_count = 0;
  GLuint vao = 0, vbo = 0, ebo = 0;
  GLuint coverage_program = 0;
  GLuint fbo = 0, colour = 0;
  int width = 0, rows = 0, first_row = 0;
  double far_mm = 0.0;
  // The ambient radiance of each pixel of the region where it sees a
  // surface (ambient_radiance), and which pixels do (the draw, 0 or 255).
  std::vector<float> ambient;
  std::vector<std::uint8_t> seen;
  MeshOrientation orientation = MeshOrientation::Open;

  Impl(const ScannerDesc& d, const Mesh& mesh) : desc(d), cam(camera_geometry(d)) {
    if (const std::string why = validate(d); !why.empty())
      throw std::invalid_argument(std::string(kWho) + ": scanner " + why);
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
      for (std::uint32_t v : mesh.triangles[t])
        if (v >= mesh.vertices.size())
          throw std::invalid_argument(std::string(kWho) + ": triangle " + std::to_string(t) + " uses vertex " +
                                      std::to_string(v) + " but the mesh has " +
                                      std::to_string(mesh.vertices.size()) + " vertices");
    const auto [first, count] = image_roi(d);
    orientation = mesh_orientation(mesh);
    first_row = first;
    rows = count;
    width = d.image_width_px;
    far_mm = 2.0 * d.max_hit_mm + 2.0 * d.baseline_mm + 10.0;

    const GlContext::Binding bind(context);
    upload(mesh);
    coverage_program = link_program(kWho, shaders::camera_image_vert, "camera_image.vert",
                                    shaders::camera_coverage_frag, "camera_coverage.frag");
    make_targets();
    ambient.resize(static_cast<std::size_t>(width) * rows);
    seen.resize(ambient.size());
    for (int k = 0; k < rows; ++k)
      for (int c = 0; c < width; ++c)
        ambient[static_cast<std::size_t>(k) * width + c] =
            static_cast<float>(ambient_radiance(d, cam, c, static_cast<double>(first_row + k)));
    check_gl(kWho, "creating the camera-image pipeline");
  }

  ~Impl() {
    try {
      const GlContext::Binding bind(context);
      glDeleteProgram(coverage_program);
      glDeleteFramebuffers(1, &fbo);
      glDeleteRenderbuffers(1, &colour);
      glDeleteBuffers(1, &vbo);
      glDeleteBuffers(1, &ebo);
      glDeleteVertexArrays(1, &vao);
    } catch (...) {
      // The context is gone with the renderer either way.
    }
  }

  void upload(const Mesh& mesh) {
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(0.0), hi = lo;
    if (!mesh.vertices.empty()) {
      lo = hi = mesh.vertices[0].cast<double>();
      for (const auto& v : mesh.vertices) {
        lo = lo.cwiseMin(v.cast<double>());
        hi = hi.cwiseMax(v.cast<double>());
      }
    }
    mesh_centre = 0.5 * (lo + hi);
    std::vector<float> positions;
    positions.reserve(mesh.vertices.size() * 3);
    for (const auto& v : mesh.vertices)
      for (int k = 0; k < 3; ++k) positions.push_back(static_cast<float>(v[k] - mesh_centre[k]));
    std::vector<std::uint32_t> indices;
    indices.reserve(mesh.triangles.size() * 3);
    for (const auto& t : mesh.triangles) indices.insert(indices.end(), t.begin(), t.end());
    index_count = static_cast<GLsizei>(indices.size());
    glGenVertexArrays(1, &vao);
    glBindVertexArray(vao);
    glGenBuffers(1, &vbo);
    glBindBuffer(GL_ARRAY_BUFFER, vbo);
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(positions.size() * sizeof(float)), positions.data(),
                 GL_STATIC_DRAW);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 3 * sizeof(float), nullptr);
    glGenBuffers(1, &ebo);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, ebo);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(indices.size() * sizeof(std::uint32_t)),
                 indices.data(), GL_STATIC_DRAW);
    glBindVertexArray(0);
  }

  void make_targets() {
    glGenRenderbuffers(1, &colour);
    glBindRenderbuffer(GL_RENDERBUFFER, colour);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_R8, width, rows);
    glGenFramebuffers(1, &fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, colour);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
      throw std::runtime_error(std::string(kWho) + ": the image framebuffer is incomplete");
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
  }

  static void set(GLuint program, const char* name, float v) { glUniform1f(glGetUniformLocation(program, name), v); }
  static void set(GLuint program, const char* name, const Eigen::Vector2f& v) {
    glUniform2f(glGetUniformLocation(program, name), v.x(), v.y());
  }
  static void set(GLuint program, const char* name, const Eigen::Vector3d& v) {
    glUniform3f(glGetUniformLocation(program, name), static_cast<float>(v.x()), static_cast<float>(v.y()),
                static_cast<float>(v.z()));
  }

  void render(const Pose& world_from_sensor, RadianceImage& out) {
    const GlContext::Binding bind(context);
    // sensor_from_mesh in double, then to float (the mesh is centred, so the
    // translation is of the order of the standoff).
    const Eigen::Isometry3d sensor_from_world = world_from_sensor.inverse();
    Eigen::Matrix4d m = (sensor_from_world * Eigen::Translation3d(mesh_centre)).matrix();
    const Eigen::Matrix4f mf = m.cast<float>();

    glBindVertexArray(vao);
    // Which pixels see a surface: every triangle drawn, none hidden (no
    // depth test: the ambient light is the same on every surface, so only
    // the union of their images matters; near and far planes as before).
    glDisable(GL_DEPTH_TEST);
    if (orientation == MeshOrientation::Open) {
      glDisable(GL_CULL_FACE);
    } else {
      // Only the triangles facing the camera (every ray into a solid enters
      // through one of them first), about half the pixels to draw.
      glEnable(GL_CULL_FACE);
      glCullFace(orientation == MeshOrientation::Outward ? kAwayFromCamera : kTowardCamera);
    }
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glViewport(0, 0, width, rows);
    const float zero[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    glClearBufferfv(GL_COLOR, 0, zero);
    const GLuint p = coverage_program;
    glUseProgram(p);
    glUniformMatrix4fv(glGetUniformLocation(p, "sensor_from_mesh"), 1, GL_FALSE, mf.data());
    set(p, "cam_centre", cam.centre);
    const Eigen::Matrix3f rot = cam.camera_from_sensor.cast<float>();
    glUniformMatrix3fv(glGetUniformLocation(p, "cam_rot"), 1, GL_TRUE, Eigen::Matrix3f(rot.transpose()).data());
    set(p, "f_px", static_cast<float>(cam.f_px));
    set(p, "cos_tilt", static_cast<float>(cam.cos_tilt));
    set(p, "sin_tilt", static_cast<float>(cam.sin_tilt));
    set(p, "principal", Eigen::Vector2f(static_cast<float>(cam.cx), static_cast<float>(cam.cy)));
    set(p, "target", Eigen::Vector2f(static_cast<float>(width), static_cast<float>(rows)));
    set(p, "first_row", static_cast<float>(first_row));
    set(p, "depth_ab", depth_ab(kNearMm, far_mm));
    glDrawElements(GL_TRIANGLES, index_count, GL_UNSIGNED_INT, nullptr);

    if (out.width != width || out.rows != rows || out.first_row != first_row) out.resize(width, rows, first_row);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, width, rows, GL_RED, GL_UNSIGNED_BYTE, seen.data());
    check_gl(kWho, "drawing the camera image");
    for (std::size_t i = 0; i < seen.size(); ++i) out.ambient[i] = seen[i] != 0 ? ambient[i] : 0.0f;
    std::fill(out.laser.begin(), out.laser.end(), 0.0f);
  }
};

CameraRenderer::CameraRenderer(const ScannerDesc& desc, const Mesh& mesh_world)
    : impl_(std::make_unique<Impl>(desc, mesh_world)) {}

CameraRenderer::~CameraRenderer() = default;

void CameraRenderer::render(const Pose& world_from_sensor, RadianceImage& out) {
  impl_->render(world_from_sensor, out);
}

}  // namespace vts
