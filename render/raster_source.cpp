#include "render/raster_source.h"

#include <GL/gl.h>
#include <GL/glext.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "render/gl_context.h"
#include "sensor/error_model.h"
#include "sensor/rays.h"
#include "shaders/embedded.h"

namespace vts {
namespace {

// Surfaces closer than this to the laser are clipped away. Far below any
// usable min_range_mm, so it only matters for occluders touching the laser.
constexpr double kNearClipMm = 1e-3;

// Colour clear value: no fragment reached this column.
constexpr float kClearRange = 0.0f;

// Camera shadow map: texels along the epipolar direction (one row per column).
// Candidates are tested exactly, so this only sets how thin a face seen
// edge-on from the camera may be before the rasterizer misses it.
constexpr int kShadowTexels = 32;
// The shadow pass draws only the slab between the laser plane and the
// camera's plane parallel to it, widened by this on each side.
constexpr double kShadowSlabMarginMm = 1.0;
// Smallest half-width of the shadow map's window (tangent units), so a profile
// whose points all project to one direction still gets a well-conditioned view.
constexpr double kMinShadowHalfWidth = 1e-3;

std::string shader_log(GLuint shader) {
  GLint length = 0;
  glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
  std::string log(static_cast<std::size_t>(std::max(length, 1)), '\0');
  glGetShaderInfoLog(shader, length, nullptr, log.data());
  log.resize(std::char_traits<char>::length(log.c_str()));
  return log;
}

std::string program_log(GLuint program) {
  GLint length = 0;
  glGetProgramiv(program, GL_INFO_LOG_LENGTH, &length);
  std::string log(static_cast<std::size_t>(std::max(length, 1)), '\0');
  glGetProgramInfoLog(program, length, nullptr, log.data());
  log.resize(std::char_traits<char>::length(log.c_str()));
  return log;
}

GLuint compile_shader(GLenum type, const char* source, const char* name) {
  const GLuint shader = glCreateShader(type);
  glShaderSource(shader, 1, &source, nullptr);
  glCompileShader(shader);
  GLint ok = GL_FALSE;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    const std::string log = shader_log(shader);
    glDeleteShader(shader);
    throw std::runtime_error(std::string("raster source: shader ") + name +
                             " failed to compile:\n" + log);
  }
  return shader;
}

GLuint link_program(const char* vert_source, const char* vert_name, const char* frag_source,
                    const char* frag_name) {
  const GLuint vert = compile_shader(GL_VERTEX_SHADER, vert_source, vert_name);
  GLuint frag = 0;
  try {
    frag = compile_shader(GL_FRAGMENT_SHADER, frag_source, frag_name);
  } catch (...) {
    glDeleteShader(vert);
    throw;
  }
  const GLuint program = glCreateProgram();
  glAttachShader(program, vert);
  glAttachShader(program, frag);
  glLinkProgram(program);
  glDeleteShader(vert);
  glDeleteShader(frag);
  GLint ok = GL_FALSE;
  glGetProgramiv(program, GL_LINK_STATUS, &ok);
  if (!ok) {
    const std::string log = program_log(program);
    glDeleteProgram(program);
    throw std::runtime_error(std::string("raster source: ") + vert_name + " + " + frag_name +
                             " failed to link:\n" + log);
  }
  return program;
}

GLint uniform(GLuint program, const char* name) {
  const GLint location = glGetUniformLocation(program, name);
  if (location < 0)
    throw std::runtime_error(std::string("raster source: uniform ") + name +
                             " not found in the shaders");
  return location;
}

void check_gl(const char* what) {
  const GLenum error = glGetError();
  if (error == GL_NO_ERROR) return;
  char code[16];
  std::snprintf(code, sizeof code, "0x%04x", error);
  throw std::runtime_error(std::string("raster source: GL error ") + code + " after " + what);
}

// Mesh prepared for upload: positions relative to a centre (so float keeps
// precision far from the world origin), non-degenerate triangles only, and
// each kept triangle's plane in the same centred frame.
struct PreparedMesh {
  Eigen::Vector3d centre_mm = Eigen::Vector3d::Zero();
  std::vector<float> positions;          // xyz per vertex, centred world mm
  std::vector<std::uint32_t> indices;    // 3 per kept triangle
  std::vector<double> planes;            // (nx, ny, nz, w) per kept triangle
};

PreparedMesh prepare(const Mesh& mesh) {
  PreparedMesh out;
  const std::size_t nv = mesh.vertices.size();
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
    for (std::uint32_t v : mesh.triangles[t])
      if (v >= nv)
        throw std::invalid_argument("raster source: mesh triangle " + std::to_string(t) +
                                    " uses vertex " + std::to_string(v) + " but the mesh has " +
                                    std::to_string(nv) + " vertices");

  // Centre of the bounding box of the vertices in use.
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  for (const auto& tri : mesh.triangles)
    for (std::uint32_t v : tri) {
      const Eigen::Vector3d p = mesh.vertices[v].cast<double>();
      if (!p.allFinite()) continue;
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
  if ((lo.array() <= hi.array()).all()) out.centre_mm = 0.5 * (lo + hi);

  out.positions.resize(3 * nv);
  for (std::size_t v = 0; v < nv; ++v) {
    const Eigen::Vector3d p = mesh.vertices[v].cast<double>() - out.centre_mm;
    for (int k = 0; k < 3; ++k) out.positions[3 * v + k] = static_cast<float>(p[k]);
  }

  out.indices.reserve(3 * mesh.triangles.size());
  out.planes.reserve(4 * mesh.triangles.size());
  for (const auto& tri : mesh.triangles) {
    const Eigen::Vector3d a = mesh.vertices[tri[0]].cast<double>() - out.centre_mm;
    const Eigen::Vector3d b = mesh.vertices[tri[1]].cast<double>() - out.centre_mm;
    const Eigen::Vector3d c = mesh.vertices[tri[2]].cast<double>() - out.centre_mm;
    const Eigen::Vector3d cross = (b - a).cross(c - a);
    const double norm = cross.norm();
    if (!(norm > 0.0) || !std::isfinite(norm)) continue;  // zero area or non-finite
    const Eigen::Vector3d n = cross / norm;
    const double w = n.dot((a + b + c) / 3.0);
    out.indices.insert(out.indices.end(), tri.begin(), tri.end());
    out.planes.insert(out.planes.end(), {n.x(), n.y(), n.z(), w});
  }
  return out;
}

class RasterSource final : public ProfileSource {
 public:
  RasterSource(const ScannerDesc& desc, const Mesh& mesh_world)
      : desc_(desc), directions_(column_directions(desc)) {
    const int n = desc_.points;
    readback_.resize(2 * static_cast<std::size_t>(n));
    lit_.resize(2 * static_cast<std::size_t>(n));
    shadowed_.resize(static_cast<std::size_t>(n));

    // Column i is the centre of pixel i of an n-wide image whose horizontal
    // half-angle is fan/2 (sensor/rays.h). The row's half-height is chosen to
    // make pixels square, so edges snap equally finely across and along the
    // laser plane.
    tan_half_fan_ = std::tan(0.5 * desc_.fan_deg * std::numbers::pi / 180.0);
    tan_half_row_ = tan_half_fan_ / n;
    camera_mm_ = camera_model(desc_).centre_mm;

    const PreparedMesh mesh = prepare(mesh_world);
    centre_mm_ = mesh.centre_mm;
    index_count_ = static_cast<GLsizei>(mesh.indices.size());

    program_ = link_program(shaders::raster_vert, "raster.vert", shaders::raster_frag, "raster.frag");
    glUseProgram(program_);
    u_clip_from_mesh_ = uniform(program_, "u_clip_from_mesh");
    glUniform1f(uniform(program_, "u_max_hit_mm"), static_cast<float>(desc_.max_hit_mm));
    // Depth clears to 1; ranges up to max_hit map into [0, 0.5].
    glUniform1f(uniform(program_, "u_depth_per_mm"), static_cast<float>(0.5 / desc_.max_hit_mm));

    shadow_program_ =
        link_program(shaders::shadow_vert, "shadow.vert", shaders::shadow_frag, "shadow.frag");
    glUseProgram(shadow_program_);
    u_shadow_clip_from_mesh_ = uniform(shadow_program_, "u_clip_from_mesh");
    u_shadow_slab_ = uniform(shadow_program_, "u_slab");

    glGenVertexArrays(1, &vao_);
    glBindVertexArray(vao_);
    // An empty buffer cannot be bound as storage; a mesh with no triangles never draws.
    const std::vector<float> no_positions(3, 0.0f);
    const std::vector<std::uint32_t> no_indices(3, 0u);
    const auto& positions = mesh.positions.empty() ? no_positions : mesh.positions;
    const auto& indices = mesh.indices.empty() ? no_indices : mesh.indices;
    glGenBuffers(1, &vbo_);
    glBindBuffer(GL_ARRAY_BUFFER, vbo_);
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(positions.size() * sizeof(float)),
                 positions.data(), GL_STATIC_DRAW);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 3 * sizeof(float), nullptr);
    glEnableVertexAttribArray(0);
    glGenBuffers(1, &ebo_);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, ebo_);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER,
                 static_cast<GLsizeiptr>(indices.size() * sizeof(std::uint32_t)), indices.data(),
                 GL_STATIC_DRAW);
    // The shadow pass reads the triangles' corners from the same buffers.
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, vbo_);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, ebo_);

    std::vector<float> dirs4(4 * static_cast<std::size_t>(n), 0.0f);
    for (int i = 0; i < n; ++i)
      for (int k = 0; k < 3; ++k) dirs4[4 * i + k] = directions_[i][k];
    glGenBuffers(1, &directions_ssbo_);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, directions_ssbo_);
    glBufferData(GL_SHADER_STORAGE_BUFFER, static_cast<GLsizeiptr>(dirs4.size() * sizeof(float)),
                 dirs4.data(), GL_STATIC_DRAW);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, directions_ssbo_);
    const std::vector<double> no_planes(4, 0.0);
    const auto& planes = mesh.planes.empty() ? no_planes : mesh.planes;
    glGenBuffers(1, &planes_ssbo_);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, planes_ssbo_);
    glBufferData(GL_SHADER_STORAGE_BUFFER, static_cast<GLsizeiptr>(planes.size() * sizeof(double)),
                 planes.data(), GL_STATIC_DRAW);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, planes_ssbo_);
    glGenBuffers(1, &lit_ssbo_);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, lit_ssbo_);
    glBufferData(GL_SHADER_STORAGE_BUFFER, static_cast<GLsizeiptr>(lit_.size() * sizeof(float)),
                 nullptr, GL_DYNAMIC_DRAW);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, lit_ssbo_);
    glGenBuffers(1, &shadowed_ssbo_);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, shadowed_ssbo_);
    glBufferData(GL_SHADER_STORAGE_BUFFER,
                 static_cast<GLsizeiptr>(shadowed_.size() * sizeof(std::uint32_t)), nullptr,
                 GL_DYNAMIC_READ);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 5, shadowed_ssbo_);

    // std140 Camera block: dvec3 camera centre, then the shadow epsilon (both double).
    glGenBuffers(1, &camera_ubo_);
    glBindBuffer(GL_UNIFORM_BUFFER, camera_ubo_);
    glBufferData(GL_UNIFORM_BUFFER, sizeof camera_block_, nullptr, GL_DYNAMIC_DRAW);
    glBindBufferBase(GL_UNIFORM_BUFFER, 1, camera_ubo_);

    glGenBuffers(1, &pose_ubo_);
    glBindBuffer(GL_UNIFORM_BUFFER, pose_ubo_);
    glBufferData(GL_UNIFORM_BUFFER, sizeof pose_block_, nullptr, GL_DYNAMIC_DRAW);
    glBindBufferBase(GL_UNIFORM_BUFFER, 0, pose_ubo_);

    // Laser pass target: range and |cos incidence| per column.
    glGenRenderbuffers(1, &colour_rb_);
    glBindRenderbuffer(GL_RENDERBUFFER, colour_rb_);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_RG32F, n, 1);
    glGenRenderbuffers(1, &depth_rb_);
    glBindRenderbuffer(GL_RENDERBUFFER, depth_rb_);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT32F, n, 1);
    glGenFramebuffers(1, &fbo_);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, colour_rb_);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth_rb_);
    GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE)
      throw std::runtime_error("raster source: RG32F + DEPTH32F framebuffer of " +
                               std::to_string(n) + "x1 is incomplete (status " +
                               std::to_string(status) + ")");
    glDrawBuffer(GL_COLOR_ATTACHMENT0);
    glReadBuffer(GL_COLOR_ATTACHMENT0);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);

    // Shadow pass target: no attachments, kShadowTexels x n; the fragment
    // shader writes its verdicts into shadowed_ssbo_.
    glGenFramebuffers(1, &shadow_fbo_);
    glBindFramebuffer(GL_FRAMEBUFFER, shadow_fbo_);
    glFramebufferParameteri(GL_FRAMEBUFFER, GL_FRAMEBUFFER_DEFAULT_WIDTH, kShadowTexels);
    glFramebufferParameteri(GL_FRAMEBUFFER, GL_FRAMEBUFFER_DEFAULT_HEIGHT, n);
    status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE)
      throw std::runtime_error("raster source: attachment-less shadow framebuffer of " +
                               std::to_string(kShadowTexels) + "x" + std::to_string(n) +
                               " is incomplete (status " + std::to_string(status) + ")");

    glDepthFunc(GL_LESS);
    glDisable(GL_CULL_FACE);
    glDisable(GL_BLEND);
    glDisable(GL_DITHER);
    check_gl("creating the raster pipeline");
    // The context is private to this source, so all this state stays bound.
  }

  // GL objects go with the context (GlContext's destructor).
  ~RasterSource() override = default;

  void scan(const Pose& world_from_sensor, Profile& out) override {
    context_.make_current();
    const int n = desc_.points;

    // Mesh-centred world -> sensor, in double: p_s = R^T (p_c + c - t).
    const Eigen::Matrix3d r = world_from_sensor.linear();
    const Eigen::Vector3d origin_c = world_from_sensor.translation() - centre_mm_;
    Eigen::Matrix4d sensor_from_mesh = Eigen::Matrix4d::Identity();
    sensor_from_mesh.topLeftCorner<3, 3>() = r.transpose();
    sensor_from_mesh.topRightCorner<3, 1>() = -(r.transpose() * origin_c);

    // Sensor -> clip. GL's w is the sensor z (optical axis) directly, so the
    // view looks down +z and no axis flip is needed: NDC x = (y/z) / tan(fan/2)
    // puts column 0 at the most negative y; NDC y = (x/z) / tan_half_row puts
    // the row's pixel centre on the laser plane x = 0. clip z = z - 2 near
    // clips only at z = near (no far plane); depth comes from the fragment
    // shader.
    Eigen::Matrix4d clip_from_sensor = Eigen::Matrix4d::Zero();
    clip_from_sensor(0, 1) = 1.0 / tan_half_fan_;
    clip_from_sensor(1, 0) = 1.0 / tan_half_row_;
    clip_from_sensor(2, 2) = 1.0;
    clip_from_sensor(2, 3) = -2.0 * kNearClipMm;
    clip_from_sensor(3, 2) = 1.0;

    glUseProgram(program_);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
    glViewport(0, 0, n, 1);
    glEnable(GL_DEPTH_TEST);
    const Eigen::Matrix4f clip_from_mesh = (clip_from_sensor * sensor_from_mesh).cast<float>();
    glUniformMatrix4fv(u_clip_from_mesh_, 1, GL_FALSE, clip_from_mesh.data());
    // std140: each dmat3 column and the dvec3 take a 32-byte slot.
    for (int c = 0; c < 3; ++c)
      for (int k = 0; k < 3; ++k) pose_block_[4 * c + k] = r(k, c);
    for (int k = 0; k < 3; ++k) pose_block_[12 + k] = origin_c[k];
    glBindBuffer(GL_UNIFORM_BUFFER, pose_ubo_);
    glBufferSubData(GL_UNIFORM_BUFFER, 0, sizeof pose_block_, pose_block_);

    const GLfloat clear_range[4] = {kClearRange, 0.0f, 0.0f, 0.0f};
    const GLfloat clear_depth = 1.0f;
    glClearBufferfv(GL_COLOR, 0, clear_range);
    glClearBufferfv(GL_DEPTH, 0, &clear_depth);
    if (index_count_ > 0) glDrawElements(GL_TRIANGLES, index_count_, GL_UNSIGNED_INT, nullptr);
    glReadPixels(0, 0, n, 1, GL_RG, GL_FLOAT, readback_.data());

    if (!out.sized(n)) out.resize(n);
    out.world_from_sensor = world_from_sensor;
    for (int i = 0; i < n; ++i) {
      const float range = readback_[2 * i];
      set_column(desc_, directions_[i], i, range > 0.0f ? range : kNoHit, out,
                 readback_[2 * i + 1]);
    }
    if (!desc_.ideal && index_count_ > 0) camera_shadow(sensor_from_mesh, r, origin_c, out);
  }

  const ScannerDesc& scanner() const override { return desc_; }
  std::string_view kind() const override { return "raster"; }

 private:
  // The camera shadow pass (shaders/shadow.frag). A virtual pinhole camera at
  // the camera centre c (sensor frame, c_y = 0) with x' along c (the baseline
  // from the laser origin), y' = sensor y and z' = x' cross y' sees the plane
  // through c, the laser origin and column i's ray (0, t_i, 1) as the line
  // y'/z' = t_i |c| / c_x. Its n rows, uniform in y'/z' over the fan, are
  // therefore exactly the columns' epipolar planes; along x' the window spans
  // the directions of this profile's lit points.
  void camera_shadow(const Eigen::Matrix4d& sensor_from_mesh, const Eigen::Matrix3d& r,
                     const Eigen::Vector3d& origin_c, Profile& out) {
    const int n = desc_.points;
    const Eigen::Vector3d c = camera_mm_;
    const Eigen::Vector3d xa = c.normalized();
    const Eigen::Vector3d ya = Eigen::Vector3d::UnitY();
    const Eigen::Vector3d za = xa.cross(ya);

    // Direction of each lit point from the camera, x'/z'.
    double q_lo = std::numeric_limits<double>::infinity(), q_hi = -q_lo;
    int lit = 0;
    for (int i = 0; i < n; ++i) {
      if (!out.valid[i]) continue;
      const Eigen::Vector3d d = double(out.range_mm[i]) * directions_[i].cast<double>() - c;
      const double q = d.dot(xa) / d.dot(za);
      shadowed_[i] = 0;
      lit_[2 * i + 1] = static_cast<float>(q);  // texel filled in below
      q_lo = std::min(q_lo, q);
      q_hi = std::max(q_hi, q);
      ++lit;
    }
    if (lit == 0) return;
    // Two texels of margin on each side.
    const double mid = 0.5 * (q_lo + q_hi);
    const double half =
        std::max(0.5 * (q_hi - q_lo) * kShadowTexels / (kShadowTexels - 4.0), kMinShadowHalfWidth);
    for (int i = 0; i < n; ++i) {
      if (!out.valid[i]) {
        lit_[2 * i] = 0.0f;
        lit_[2 * i + 1] = -2.0f;
        continue;
      }
      const double q = lit_[2 * i + 1];
      const double texel = std::floor((q - (mid - half)) / (2.0 * half) * kShadowTexels);
      lit_[2 * i] = out.range_mm[i];
      lit_[2 * i + 1] = static_cast<float>(std::clamp(texel, 0.0, kShadowTexels - 1.0));
    }

    // Sensor -> camera (rows x', y', z'; centre at c) -> clip.
    Eigen::Matrix4d camera_from_sensor = Eigen::Matrix4d::Identity();
    camera_from_sensor.block<1, 3>(0, 0) = xa.transpose();
    camera_from_sensor.block<1, 3>(1, 0) = ya.transpose();
    camera_from_sensor.block<1, 3>(2, 0) = za.transpose();
    camera_from_sensor.topRightCorner<3, 1>() =
        -(camera_from_sensor.topLeftCorner<3, 3>() * c);
    const double tan_half_rows = tan_half_fan_ * c.norm() / c.x();
    Eigen::Matrix4d clip_from_camera = Eigen::Matrix4d::Zero();
    clip_from_camera(0, 0) = 1.0 / half;
    clip_from_camera(0, 2) = -mid / half;
    clip_from_camera(1, 1) = 1.0 / tan_half_rows;
    clip_from_camera(2, 2) = 1.0;
    clip_from_camera(2, 3) = -2.0 * kNearClipMm;
    clip_from_camera(3, 2) = 1.0;
    const Eigen::Matrix4f clip_from_mesh =
        (clip_from_camera * camera_from_sensor * sensor_from_mesh).cast<float>();
    const Eigen::Vector3d camera_c = r * c + origin_c;

    glUseProgram(shadow_program_);
    glBindFramebuffer(GL_FRAMEBUFFER, shadow_fbo_);
    glViewport(0, 0, kShadowTexels, n);
    glDisable(GL_DEPTH_TEST);
    glEnable(GL_CLIP_DISTANCE0);
    glEnable(GL_CLIP_DISTANCE1);
    glUniformMatrix4fv(u_shadow_clip_from_mesh_, 1, GL_FALSE, clip_from_mesh.data());
    // Sensor x = row 0 of sensor_from_mesh; keep -margin <= x <= baseline + margin.
    const Eigen::Vector4d x_of = sensor_from_mesh.row(0).transpose();
    const Eigen::Vector4f slab[2] = {
        (x_of + Eigen::Vector4d(0, 0, 0, kShadowSlabMarginMm)).cast<float>(),
        (-x_of + Eigen::Vector4d(0, 0, 0, c.x() + kShadowSlabMarginMm)).cast<float>()};
    glUniform4fv(u_shadow_slab_, 2, slab[0].data());
    for (int k = 0; k < 3; ++k) camera_block_[k] = camera_c[k];
    camera_block_[3] = kShadowEpsilonMm;
    glBindBuffer(GL_UNIFORM_BUFFER, camera_ubo_);
    glBufferSubData(GL_UNIFORM_BUFFER, 0, sizeof camera_block_, camera_block_);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, lit_ssbo_);
    glBufferSubData(GL_SHADER_STORAGE_BUFFER, 0,
                    static_cast<GLsizeiptr>(lit_.size() * sizeof(float)), lit_.data());
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, shadowed_ssbo_);
    const GLuint zero = 0;
    glClearBufferData(GL_SHADER_STORAGE_BUFFER, GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
    glDrawElements(GL_TRIANGLES, index_count_, GL_UNSIGNED_INT, nullptr);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    glGetBufferSubData(GL_SHADER_STORAGE_BUFFER, 0,
                       static_cast<GLsizeiptr>(shadowed_.size() * sizeof(std::uint32_t)),
                       shadowed_.data());
    glDisable(GL_CLIP_DISTANCE0);
    glDisable(GL_CLIP_DISTANCE1);
    for (int i = 0; i < n; ++i)
      if (out.valid[i] && shadowed_[i]) out.camera_visible[i] = 0;
  }

  ScannerDesc desc_;
  std::vector<Eigen::Vector3f> directions_;  // sensor frame, unit, per column
  std::vector<float> readback_;              // per column: raw range (0 = no hit), |cos|
  std::vector<float> lit_;                   // per column: range (0 = none), shadow texel
  std::vector<std::uint32_t> shadowed_;      // per column: 1 = occluded
  double tan_half_fan_ = 0.0;
  double tan_half_row_ = 0.0;
  Eigen::Vector3d camera_mm_ = Eigen::Vector3d::Zero();  // camera centre, sensor frame
  Eigen::Vector3d centre_mm_ = Eigen::Vector3d::Zero();  // mesh centre, world mm
  GlContext context_;  // created before, destroyed after, every GL object below
  GLsizei index_count_ = 0;
  GLuint program_ = 0, shadow_program_ = 0;
  GLint u_clip_from_mesh_ = -1;
  GLint u_shadow_clip_from_mesh_ = -1, u_shadow_slab_ = -1;
  double pose_block_[16] = {};  // the Pose uniform block, std140
  double camera_block_[4] = {};  // the Camera uniform block, std140
  GLuint pose_ubo_ = 0, camera_ubo_ = 0;
  GLuint vao_ = 0, vbo_ = 0, ebo_ = 0;
  GLuint directions_ssbo_ = 0, planes_ssbo_ = 0, lit_ssbo_ = 0, shadowed_ssbo_ = 0;
  GLuint colour_rb_ = 0, depth_rb_ = 0, fbo_ = 0, shadow_fbo_ = 0;
};

}  // namespace

std::unique_ptr<ProfileSource> make_raster_source(const ScannerDesc& desc,
                                                  const Mesh& mesh_world) {
  if (const std::string problem = validate(desc); !problem.empty())
    throw std::invalid_argument("raster source: scanner " + problem);
  return std::make_unique<RasterSource>(desc, mesh_world);
}

}  // namespace vts
