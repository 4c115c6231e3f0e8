#pragma once
// A headless OpenGL 4.5 core context (OSMesa, llvmpipe), owned RAII-style.
// No GL type crosses this header: callers that issue GL calls include the GL
// headers themselves, in their .cpp.
#include <memory>
#include <string>

namespace vts {

class GlContext {
 public:
  // Creates an OSMesa 4.5 core-profile context and makes it current on a 1x1
  // dummy colour buffer (render into your own framebuffer objects).
  // Throws std::runtime_error naming the reason if creation fails.
  GlContext();
  ~GlContext();
  GlContext(GlContext&&) noexcept;
  GlContext& operator=(GlContext&&) noexcept;
  GlContext(const GlContext&) = delete;
  GlContext& operator=(const GlContext&) = delete;

  // Makes this context current on the calling thread; cheap when it already is.
  // Throws std::runtime_error if OSMesa refuses.
  void make_current();
  bool is_current() const;

  // GL_VERSION and GL_RENDERER strings, read once at creation.
  const std::string& version() const;
  const std::string& renderer() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace vts
