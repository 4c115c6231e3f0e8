#include "viewer/renderer.h"

#include <GL/gl.h>
#include <GL/glext.h>

#include <algorithm>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <utility>

#include <Eigen/Geometry>

#include "render/gl_program.h"
#include "shaders/embedded.h"

namespace vts::viewer {
namespace {

// The viewer's programs, built as the renderers of render/ build theirs.
GLuint link(const char* vert, const char* frag, const char* name) {
  const std::string v = std::string(name) + ".vert", f = std::string(name) + ".frag";
  return vts::link_program("vts-view", vert, v.c_str(), frag, f.c_str());
}

// A vertex array with one interleaved buffer; move-only, frees both.
struct VertexArray {
  GLuint vao = 0, vbo = 0;
  GLsizei count = 0;

  VertexArray() {
    glGenVertexArrays(1, &vao);
    glGenBuffers(1, &vbo);
  }
  ~VertexArray() {
    if (vbo) glDeleteBuffers(1, &vbo);
    if (vao) glDeleteVertexArrays(1, &vao);
  }
  VertexArray(VertexArray&& o) noexcept
      : vao(std::exchange(o.vao, 0)), vbo(std::exchange(o.vbo, 0)), count(o.count) {}
  VertexArray& operator=(VertexArray&&) = delete;
  VertexArray(const VertexArray&) = delete;
};

// Mesh vertex as uploaded: position and normal, model frame.
struct MeshVertex {
  float p[3];
  float n[3];
};
static_assert(sizeof(MeshVertex) == 6 * sizeof(float));

// Streamed vertex: world position and colour.
struct StreamVertex {
  float p[3];
  float c[4];
};
static_assert(sizeof(StreamVertex) == 7 * sizeof(float));

}  // namespace

struct Renderer::Impl {
  GLuint mesh_program = 0, color_program = 0;
  GLint mesh_clip = -1, mesh_model = -1, mesh_eye = -1, mesh_color = -1;
  GLint color_clip = -1, color_point_size = -1;
  std::vector<VertexArray> meshes;
  VertexArray stream;
  std::vector<StreamVertex> scratch;
  GLuint image_texture = 0;
  std::vector<std::uint8_t> image_bytes;

  ~Impl() {
    if (image_texture) glDeleteTextures(1, &image_texture);
    if (mesh_program) glDeleteProgram(mesh_program);
    if (color_program) glDeleteProgram(color_program);
  }

  void draw_stream(const std::vector<ColorVertex>& vertices, GLenum mode) {
    if (vertices.empty()) return;
    scratch.resize(vertices.size());
    for (std::size_t i = 0; i < vertices.size(); ++i) {
      const ColorVertex& v = vertices[i];
      scratch[i] = {{v.position_mm.x(), v.position_mm.y(), v.position_mm.z()},
                    {v.color.r, v.color.g, v.color.b, v.color.a}};
    }
    glBindVertexArray(stream.vao);
    glBindBuffer(GL_ARRAY_BUFFER, stream.vbo);
    // Orphan and refill: no stall on the previous frame's use of the buffer.
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(scratch.size() * sizeof(StreamVertex)),
                 scratch.data(), GL_STREAM_DRAW);
    glDrawArrays(mode, 0, static_cast<GLsizei>(scratch.size()));
  }
};

Renderer::Renderer() : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.mesh_program = link(shaders::viewer_mesh_vert, shaders::viewer_mesh_frag, "viewer_mesh");
  m.color_program = link(shaders::viewer_color_vert, shaders::viewer_color_frag, "viewer_color");
  m.mesh_clip = glGetUniformLocation(m.mesh_program, "u_clip_from_world");
  m.mesh_model = glGetUniformLocation(m.mesh_program, "u_world_from_model");
  m.mesh_eye = glGetUniformLocation(m.mesh_program, "u_eye_world");
  m.mesh_color = glGetUniformLocation(m.mesh_program, "u_color");
  m.color_clip = glGetUniformLocation(m.color_program, "u_clip_from_world");
  m.color_point_size = glGetUniformLocation(m.color_program, "u_point_size_px");

  glBindVertexArray(m.stream.vao);
  glBindBuffer(GL_ARRAY_BUFFER, m.stream.vbo);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(StreamVertex),
                        reinterpret_cast<const void*>(offsetof(StreamVertex, p)));
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(1, 4, GL_FLOAT, GL_FALSE, sizeof(StreamVertex),
                        reinterpret_cast<const void*>(offsetof(StreamVertex, c)));
  glBindVertexArray(0);
}

Renderer::~Renderer() = default;

int Renderer::add_mesh(const Mesh& mesh, bool smooth_normals) {
  std::vector<MeshVertex> vertices;
  vertices.reserve(mesh.triangles.size() * 3);
  std::vector<Eigen::Vector3f> vertex_normals;
  if (smooth_normals) {
    vertex_normals.assign(mesh.vertices.size(), Eigen::Vector3f::Zero());
    for (const auto& t : mesh.triangles) {
      const Eigen::Vector3f& a = mesh.vertices[t[0]];
      // Area-weighted: the unnormalised cross product.
      const Eigen::Vector3f n = (mesh.vertices[t[1]] - a).cross(mesh.vertices[t[2]] - a);
      for (std::uint32_t i : t) vertex_normals[i] += n;
    }
    for (auto& n : vertex_normals) n.normalize();
  }
  for (const auto& t : mesh.triangles) {
    const Eigen::Vector3f& a = mesh.vertices[t[0]];
    const Eigen::Vector3f& b = mesh.vertices[t[1]];
    const Eigen::Vector3f& c = mesh.vertices[t[2]];
    const Eigen::Vector3f face = (b - a).cross(c - a);
    if (face.squaredNorm() == 0.0f) continue;
    const Eigen::Vector3f fn = face.normalized();
    for (std::uint32_t i : t) {
      const Eigen::Vector3f& p = mesh.vertices[i];
      const Eigen::Vector3f n = smooth_normals ? vertex_normals[i] : fn;
      vertices.push_back({{p.x(), p.y(), p.z()}, {n.x(), n.y(), n.z()}});
    }
  }
  VertexArray va;
  va.count = static_cast<GLsizei>(vertices.size());
  glBindVertexArray(va.vao);
  glBindBuffer(GL_ARRAY_BUFFER, va.vbo);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(vertices.size() * sizeof(MeshVertex)),
               vertices.data(), GL_STATIC_DRAW);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(MeshVertex),
                        reinterpret_cast<const void*>(offsetof(MeshVertex, p)));
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, sizeof(MeshVertex),
                        reinterpret_cast<const void*>(offsetof(MeshVertex, n)));
  glBindVertexArray(0);
  impl_->meshes.push_back(std::move(va));
  return static_cast<int>(impl_->meshes.size()) - 1;
}

void Renderer::clear_meshes() { impl_->meshes.clear(); }

void Renderer::clear(int width, int height, Rgba background) {
  glViewport(0, 0, width, height);
  glDisable(GL_SCISSOR_TEST);
  glClearColor(background.r, background.g, background.b, background.a);
  glDepthMask(GL_TRUE);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
}

void Renderer::draw(const SceneView& view) {
  Impl& m = *impl_;
  if (view.width <= 0 || view.height <= 0) return;
  glViewport(view.x, view.y, view.width, view.height);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LEQUAL);
  glDepthMask(GL_TRUE);
  glDisable(GL_CULL_FACE);
  glDisable(GL_BLEND);

  // Lines and points lying on a surface (the lit laser line, the seam) must
  // win the depth test against it.
  glEnable(GL_POLYGON_OFFSET_FILL);
  glPolygonOffset(1.0f, 2.0f);
  glUseProgram(m.mesh_program);
  glUniformMatrix4fv(m.mesh_clip, 1, GL_FALSE, view.clip_from_world.data());
  glUniform3fv(m.mesh_eye, 1, view.eye_world.data());
  for (const MeshInstance& inst : view.meshes) {
    if (inst.mesh < 0 || inst.mesh >= static_cast<int>(m.meshes.size())) continue;
    const VertexArray& va = m.meshes[static_cast<std::size_t>(inst.mesh)];
    glUniformMatrix4fv(m.mesh_model, 1, GL_FALSE, inst.world_from_model.data());
    glUniform4f(m.mesh_color, inst.color.r, inst.color.g, inst.color.b, inst.color.a);
    glBindVertexArray(va.vao);
    glDrawArrays(GL_TRIANGLES, 0, va.count);
  }
  glDisable(GL_POLYGON_OFFSET_FILL);

  glUseProgram(m.color_program);
  glUniformMatrix4fv(m.color_clip, 1, GL_FALSE, view.clip_from_world.data());
  glUniform1f(m.color_point_size, view.point_size_px);
  m.draw_stream(view.lines, GL_LINES);

  glEnable(GL_BLEND);
  glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
  glDepthMask(GL_FALSE);
  m.draw_stream(view.translucent_triangles, GL_TRIANGLES);
  glDepthMask(GL_TRUE);
  glDisable(GL_BLEND);

  glEnable(GL_PROGRAM_POINT_SIZE);
  m.draw_stream(view.points, GL_POINTS);
  glDisable(GL_PROGRAM_POINT_SIZE);

  glBindVertexArray(0);
  glUseProgram(0);
  glDisable(GL_DEPTH_TEST);
  // Leave the viewport and state as a 2D overlay (ImGui) expects to find them.
}

unsigned Renderer::grey_texture(const std::vector<std::uint16_t>& pixels, int width, int height, int bits) {
  Impl& m = *impl_;
  const std::size_t n = static_cast<std::size_t>(width) * height;
  if (pixels.size() < n || width <= 0 || height <= 0) return m.image_texture;
  m.image_bytes.resize(n);
  const int shift = std::max(0, bits - 8);
  for (std::size_t i = 0; i < n; ++i) m.image_bytes[i] = static_cast<std::uint8_t>(std::min(255, pixels[i] >> shift));
  if (!m.image_texture) {
    glGenTextures(1, &m.image_texture);
    glBindTexture(GL_TEXTURE_2D, m.image_texture);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    // One channel shown as grey.
    const GLint swizzle[4] = {GL_RED, GL_RED, GL_RED, GL_ONE};
    glTexParameteriv(GL_TEXTURE_2D, GL_TEXTURE_SWIZZLE_RGBA, swizzle);
  }
  glBindTexture(GL_TEXTURE_2D, m.image_texture);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_R8, width, height, 0, GL_RED, GL_UNSIGNED_BYTE, m.image_bytes.data());
  glBindTexture(GL_TEXTURE_2D, 0);
  return m.image_texture;
}

std::vector<std::uint8_t> Renderer::read_pixels_rgb(int width, int height) const {
  std::vector<std::uint8_t> rows(static_cast<std::size_t>(width) * height * 3);
  if (rows.empty()) return rows;
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, width, height, GL_RGB, GL_UNSIGNED_BYTE, rows.data());
  // GL's rows run bottom to top; images run top to bottom.
  const std::size_t stride = static_cast<std::size_t>(width) * 3;
  std::vector<std::uint8_t> flipped(rows.size());
  for (int y = 0; y < height; ++y)
    std::copy_n(rows.data() + static_cast<std::size_t>(height - 1 - y) * stride, stride,
                flipped.data() + static_cast<std::size_t>(y) * stride);
  return flipped;
}

}  // namespace vts::viewer
