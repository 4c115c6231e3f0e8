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
#include "sensor/rays.h"
#include "shaders/embedded.h"

namespace vts {
namespace {

// Surfaces closer than this to the laser are clipped away. Far below any
// usable min_range_mm, so it only matters for occluders touching the laser.
constexpr double kNearClipMm = 1e-3;

// Colour clear value: no fragment reached this column.
constexpr float kClearRange = 0.0f;

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

GLuint link_program(const char* vert_source, const char* frag_source) {
  const GLuint vert = compile_shader(GL_VERTEX_SHADER, vert_source, "raster.vert");
  GLuint frag = 0;
  try {
    frag = compile_shader(GL_FRAGMENT_SHADER, frag_source, "raster.frag");
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
    throw std::runtime_error("raster source: raster.vert + raster.frag failed to link:\n" +
                             log);
  }
  return program;
}

GLint uniform(GLuint program, const char* name) {
  const GLint location = glGetUniformLocation(program, name);
  if (location < 0)
    throw std::runtime_error(std::string("raster source: uniform ") + name +
                             " not found in raster.vert/raster.frag");
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
    readback_.resize(static_cast<std::size_t>(n));

    // Column i is the centre of pixel i of an n-wide image whose horizontal
    // half-angle is fan/2 (sensor/rays.h). The row's half-height is chosen to
    // make pixels square, so edges snap equally finely across and along the
    // laser plane.
    tan_half_fan_ = std::tan(0.5 * desc_.fan_deg * std::numbers::pi / 180.0);
    tan_half_row_ = tan_half_fan_ / n;

    const PreparedMesh mesh = prepare(mesh_world);
    centre_mm_ = mesh.centre_mm;
    index_count_ = static_cast<GLsizei>(mesh.indices.size());

    program_ = link_program(shaders::raster_vert, shaders::raster_frag);
    glUseProgram(program_);
    u_clip_from_mesh_ = uniform(program_, "u_clip_from_mesh");
    glUniform1f(uniform(program_, "u_max_hit_mm"), static_cast<float>(desc_.max_hit_mm));
    // Depth clears to 1; ranges up to max_hit map into [0, 0.5].
    glUniform1f(uniform(program_, "u_depth_per_mm"), static_cast<float>(0.5 / desc_.max_hit_mm));

    glGenVertexArrays(1, &vao_);
    glBindVertexArray(vao_);
    glGenBuffers(1, &vbo_);
    glBindBuffer(GL_ARRAY_BUFFER, vbo_);
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(mesh.positions.size() * sizeof(float)),
                 mesh.positions.data(), GL_STATIC_DRAW);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 3 * sizeof(float), nullptr);
    glEnableVertexAttribArray(0);
    glGenBuffers(1, &ebo_);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, ebo_);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER,
                 static_cast<GLsizeiptr>(mesh.indices.size() * sizeof(std::uint32_t)),
                 mesh.indices.data(), GL_STATIC_DRAW);

    std::vector<float> dirs4(4 * static_cast<std::size_t>(n), 0.0f);
    for (int i = 0; i < n; ++i)
      for (int k = 0; k < 3; ++k) dirs4[4 * i + k] = directions_[i][k];
    glGenBuffers(1, &directions_ssbo_);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, directions_ssbo_);
    glBufferData(GL_SHADER_STORAGE_BUFFER, static_cast<GLsizeiptr>(dirs4.size() * sizeof(float)),
                 dirs4.data(), GL_STATIC_DRAW);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, directions_ssbo_);
    // An empty SSBO cannot be bound; a mesh with no triangles never draws.
    const std::vector<double> no_planes(4, 0.0);
    const auto& planes = mesh.planes.empty() ? no_planes : mesh.planes;
    glGenBuffers(1, &planes_ssbo_);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, planes_ssbo_);
    glBufferData(GL_SHADER_STORAGE_BUFFER, static_cast<GLsizeiptr>(planes.size() * sizeof(double)),
                 planes.data(), GL_STATIC_DRAW);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, planes_ssbo_);

    glGenBuffers(1, &pose_ubo_);
    glBindBuffer(GL_UNIFORM_BUFFER, pose_ubo_);
    glBufferData(GL_UNIFORM_BUFFER, sizeof pose_block_, nullptr, GL_DYNAMIC_DRAW);
    glBindBufferBase(GL_UNIFORM_BUFFER, 0, pose_ubo_);

    glGenRenderbuffers(1, &colour_rb_);
    glBindRenderbuffer(GL_RENDERBUFFER, colour_rb_);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_R32F, n, 1);
    glGenRenderbuffers(1, &depth_rb_);
    glBindRenderbuffer(GL_RENDERBUFFER, depth_rb_);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT32F, n, 1);
    glGenFramebuffers(1, &fbo_);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, colour_rb_);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth_rb_);
    const GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE)
      throw std::runtime_error("raster source: R32F + DEPTH32F framebuffer of " +
                               std::to_string(n) + "x1 is incomplete (status " +
                               std::to_string(status) + ")");
    glDrawBuffer(GL_COLOR_ATTACHMENT0);
    glReadBuffer(GL_COLOR_ATTACHMENT0);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);

    glViewport(0, 0, n, 1);
    glEnable(GL_DEPTH_TEST);
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

    const Eigen::Matrix4f clip_from_mesh = (clip_from_sensor * sensor_from_mesh).cast<float>();
    glUniformMatrix4fv(u_clip_from_mesh_, 1, GL_FALSE, clip_from_mesh.data());
    // std140: each dmat3 column and the dvec3 take a 32-byte slot.
    for (int c = 0; c < 3; ++c)
      for (int k = 0; k < 3; ++k) pose_block_[4 * c + k] = r(k, c);
    for (int k = 0; k < 3; ++k) pose_block_[12 + k] = origin_c[k];
    glBufferSubData(GL_UNIFORM_BUFFER, 0, sizeof pose_block_, pose_block_);  // pose_ubo_ is bound

    const GLfloat clear_range[4] = {kClearRange, 0.0f, 0.0f, 0.0f};
    const GLfloat clear_depth = 1.0f;
    glClearBufferfv(GL_COLOR, 0, clear_range);
    glClearBufferfv(GL_DEPTH, 0, &clear_depth);
    if (index_count_ > 0) glDrawElements(GL_TRIANGLES, index_count_, GL_UNSIGNED_INT, nullptr);
    glReadPixels(0, 0, n, 1, GL_RED, GL_FLOAT, readback_.data());

    if (out.size() != n) out.resize(n);
    out.world_from_sensor = world_from_sensor;
    for (int i = 0; i < n; ++i) {
      const float range = readback_[i];
      set_column(desc_, directions_[i], i, range > 0.0f ? range : kNoHit, out);
    }
  }

  const ScannerDesc& scanner() const override { return desc_; }
  std::string_view kind() const override { return "raster"; }

 private:
  ScannerDesc desc_;
  std::vector<Eigen::Vector3f> directions_;  // sensor frame, unit, per column
  std::vector<float> readback_;              // raw range per column, 0 = no hit
  double tan_half_fan_ = 0.0;
  double tan_half_row_ = 0.0;
  Eigen::Vector3d centre_mm_ = Eigen::Vector3d::Zero();  // mesh centre, world mm
  GlContext context_;  // created before, destroyed after, every GL object below
  GLsizei index_count_ = 0;
  GLuint program_ = 0;
  GLint u_clip_from_mesh_ = -1;
  double pose_block_[16] = {};  // the Pose uniform block, std140
  GLuint pose_ubo_ = 0;
  GLuint vao_ = 0, vbo_ = 0, ebo_ = 0;
  GLuint directions_ssbo_ = 0, planes_ssbo_ = 0;
  GLuint colour_rb_ = 0, depth_rb_ = 0, fbo_ = 0;
};

}  // namespace

std::unique_ptr<ProfileSource> make_raster_source(const ScannerDesc& desc,
                                                  const Mesh& mesh_world) {
  if (const std::string problem = validate(desc); !problem.empty())
    throw std::invalid_argument("raster source: scanner " + problem);
  return std::make_unique<RasterSource>(desc, mesh_world);
}

}  // namespace vts
