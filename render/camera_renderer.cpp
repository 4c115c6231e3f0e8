#include "render/camera_renderer.h"

#include <GL/gl.h>
#include <GL/glext.h>

#include <algorithm>
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
// The laser's depth map: texels along the fan and across the sheet.
constexpr int kLaserMapAlong = 2048;
constexpr int kLaserMapAcross = 16;
// Depth range of both projections, mm.
constexpr double kNearMm = 1.0;

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
  GLuint camera_program = 0, ambient_program = 0, laser_program = 0;
  GLuint fbo = 0, colour = 0, depth = 0;
  GLuint laser_fbo = 0, laser_tex = 0, laser_depth = 0;
  int width = 0, rows = 0, first_row = 0;
  double far_mm = 0.0;
  Eigen::Vector2f laser_tan;
  std::vector<float> readback;

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
    first_row = first;
    rows = count;
    width = d.image_width_px;
    far_mm = 2.0 * d.max_hit_mm + 2.0 * d.baseline_mm + 10.0;
    // The laser map's frustum: along the fan, and across the sheet three
    // half thicknesses at the widest ratio over the depth of field.
    double across = 0.0;
    for (int k = 0; k <= 64; ++k) {
      const double r = d.min_range_mm + (std::min(d.max_range_mm, d.max_hit_mm) - d.min_range_mm) * k / 64.0;
      across = std::max(across, 3.0 * sheet_half_thickness_mm(d, r) / r);
    }
    laser_tan = {static_cast<float>(std::clamp(across, 1e-3, 0.2)),
                 static_cast<float>(std::tan(0.5 * d.fan_deg * std::numbers::pi / 180.0) * 1.01)};

    const GlContext::Binding bind(context);
    upload(mesh);
    camera_program = link_program(kWho, shaders::camera_image_vert, "camera_image.vert", shaders::camera_image_frag,
                                  "camera_image.frag");
    ambient_program = link_program(kWho, shaders::camera_image_vert, "camera_image.vert",
                                   shaders::camera_ambient_frag, "camera_ambient.frag");
    laser_program = link_program(kWho, shaders::laser_range_vert, "laser_range.vert", shaders::laser_range_frag,
                                 "laser_range.frag");
    make_targets();
    check_gl(kWho, "creating the camera-image pipeline");
  }

  ~Impl() {
    try {
      const GlContext::Binding bind(context);
      glDeleteProgram(camera_program);
      glDeleteProgram(ambient_program);
      glDeleteProgram(laser_program);
      glDeleteFramebuffers(1, &fbo);
      glDeleteFramebuffers(1, &laser_fbo);
      glDeleteRenderbuffers(1, &colour);
      glDeleteRenderbuffers(1, &depth);
      glDeleteRenderbuffers(1, &laser_depth);
      glDeleteTextures(1, &laser_tex);
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
    glRenderbufferStorage(GL_RENDERBUFFER, GL_RG32F, width, rows);
    glGenRenderbuffers(1, &depth);
    glBindRenderbuffer(GL_RENDERBUFFER, depth);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT32F, width, rows);
    glGenFramebuffers(1, &fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, colour);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
      throw std::runtime_error(std::string(kWho) + ": the image framebuffer is incomplete");

    glGenTextures(1, &laser_tex);
    glBindTexture(GL_TEXTURE_2D, laser_tex);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_R32F, kLaserMapAlong, kLaserMapAcross, 0, GL_RED, GL_FLOAT, nullptr);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glGenRenderbuffers(1, &laser_depth);
    glBindRenderbuffer(GL_RENDERBUFFER, laser_depth);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT32F, kLaserMapAlong, kLaserMapAcross);
    glGenFramebuffers(1, &laser_fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, laser_fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, laser_tex, 0);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, laser_depth);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
      throw std::runtime_error(std::string(kWho) + ": the laser-map framebuffer is incomplete");
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
    const double fan_rad = desc.fan_deg * std::numbers::pi / 180.0;
    const double rayleigh = sheet_rayleigh_mm(desc);

    glBindVertexArray(vao);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDisable(GL_CULL_FACE);

    // 1. The laser's depth map.
    glBindFramebuffer(GL_FRAMEBUFFER, laser_fbo);
    glViewport(0, 0, kLaserMapAlong, kLaserMapAcross);
    const float clear_far[4] = {1e30f, 0.0f, 0.0f, 0.0f};
    glClearBufferfv(GL_COLOR, 0, clear_far);
    glClear(GL_DEPTH_BUFFER_BIT);
    glUseProgram(laser_program);
    glUniformMatrix4fv(glGetUniformLocation(laser_program, "sensor_from_mesh"), 1, GL_FALSE, mf.data());
    set(laser_program, "laser_tan", laser_tan);
    set(laser_program, "depth_ab", depth_ab(kNearMm, far_mm));
    glDrawElements(GL_TRIANGLES, index_count, GL_UNSIGNED_INT, nullptr);

    // 2. The camera's view: every surface with its depth and ambient light,
    // then the laser light added over the slab around the sheet only (the
    // same depth, drawn with the slab's clip distances: a pixel in front
    // passes LEQUAL, pulled a little towards the camera against rounding).
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glViewport(0, 0, width, rows);
    const float zero[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    glClearBufferfv(GL_COLOR, 0, zero);
    glClear(GL_DEPTH_BUFFER_BIT);
    for (const GLuint p : {ambient_program, camera_program}) {
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
      set(p, "cam_axis", Eigen::Vector3d(cam.camera_from_sensor.row(2).transpose()));
      set(p, "diffuse", static_cast<float>(desc.reflectivity));
      set(p, "slab", Eigen::Vector3d(desc.sheet_waist_mm, desc.sheet_focus_mm, rayleigh));
      set(p, "slab_footprint",
          static_cast<float>((2.0 + 3.0 * desc.psf_sigma_px) * desc.pixel_pitch_um * 1e-3 / desc.focal_length_mm));
      if (p == ambient_program) {
        set(p, "ambient", static_cast<float>(desc.ambient_w_m2 * 1e-6));
        glDrawElements(GL_TRIANGLES, index_count, GL_UNSIGNED_INT, nullptr);
        continue;
      }
      set(p, "power_w", static_cast<float>(desc.laser_power_mw * 1e-3));
      set(p, "fan_rad", static_cast<float>(fan_rad));
      set(p, "tan_half_fan", static_cast<float>(std::tan(0.5 * fan_rad)));
      set(p, "waist_mm", static_cast<float>(desc.sheet_waist_mm));
      set(p, "focus_mm", static_cast<float>(desc.sheet_focus_mm));
      set(p, "rayleigh_mm", static_cast<float>(rayleigh));
      set(p, "specular", static_cast<float>(desc.specular_reflectance));
      set(p, "lobe_rad", static_cast<float>(std::max(1e-3, desc.specular_lobe_deg * std::numbers::pi / 180.0)));
      set(p, "laser_tan", laser_tan);
      set(p, "psf_px", static_cast<float>(desc.psf_sigma_px));
      glActiveTexture(GL_TEXTURE0);
      glBindTexture(GL_TEXTURE_2D, laser_tex);
      glUniform1i(glGetUniformLocation(p, "laser_range"), 0);
      glEnable(GL_CLIP_DISTANCE0);
      glEnable(GL_CLIP_DISTANCE1);
      glDepthFunc(GL_LEQUAL);
      glDepthMask(GL_FALSE);
      glEnable(GL_POLYGON_OFFSET_FILL);
      glPolygonOffset(-1.0f, -4.0f);
      glEnable(GL_BLEND);
      glBlendFunc(GL_ONE, GL_ONE);
      glDrawElements(GL_TRIANGLES, index_count, GL_UNSIGNED_INT, nullptr);
      glDisable(GL_BLEND);
      glDisable(GL_POLYGON_OFFSET_FILL);
      glDepthMask(GL_TRUE);
      glDepthFunc(GL_LESS);
      glDisable(GL_CLIP_DISTANCE0);
      glDisable(GL_CLIP_DISTANCE1);
    }

    readback.resize(static_cast<std::size_t>(width) * rows * 2);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glReadPixels(0, 0, width, rows, GL_RG, GL_FLOAT, readback.data());
    check_gl(kWho, "drawing the camera image");
    if (out.width != width || out.rows != rows || out.first_row != first_row) out.resize(width, rows, first_row);
    for (std::size_t i = 0, n = static_cast<std::size_t>(width) * rows; i < n; ++i) {
      out.laser[i] = readback[2 * i];
      out.ambient[i] = readback[2 * i + 1];
    }
  }
};

CameraRenderer::CameraRenderer(const ScannerDesc& desc, const Mesh& mesh_world)
    : impl_(std::make_unique<Impl>(desc, mesh_world)) {}

CameraRenderer::~CameraRenderer() = default;

void CameraRenderer::render(const Pose& world_from_sensor, RadianceImage& out) {
  impl_->render(world_from_sensor, out);
}

}  // namespace vts
