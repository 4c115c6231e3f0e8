#pragma once
// A headless OpenGL 4.5 core context (OSMesa, llvmpipe), owned RAII-style.
// No GL type crosses this header: callers that issue GL calls include the GL
// headers themselves, in their .cpp.
#include <memory>
#include <string>

namespace vts {

class GlContext {
 public:
  struct Impl;  // opaque: no OSMesa type in this header

  // What the constructor leaves current on the calling thread.
  enum class After { Current, Previous };

  // Creates an OSMesa 4.5 core-profile context on a 1x1 dummy colour buffer
  // (render into your own framebuffer objects) and leaves it current, or
  // with After::Previous makes current again what was current before (a
  // context of ours, or none). Throws std::runtime_error naming the reason
  // if creation fails.
  explicit GlContext(After after = After::Current);
  ~GlContext();
  GlContext(GlContext&&) noexcept;
  GlContext& operator=(GlContext&&) noexcept;
  GlContext(const GlContext&) = delete;
  GlContext& operator=(const GlContext&) = delete;

  // Makes this context current on the calling thread; cheap when it already is.
  // Throws std::runtime_error if OSMesa refuses.
  void make_current();
  bool is_current() const;

  // Makes a context current on the calling thread for the binding's life,
  // then what was current before (a context of ours, or none). A context
  // used only through bindings is current nowhere between them: the next use
  // may come from another thread (a pool's), and it may be destroyed on any
  // thread. A context is current on one thread at a time.
  class Binding {
   public:
    explicit Binding(GlContext& context);
    ~Binding();
    Binding(const Binding&) = delete;
    Binding& operator=(const Binding&) = delete;

   private:
    Impl* previous_;
  };

  // GL_VERSION and GL_RENDERER strings, read once at creation.
  const std::string& version() const;
  const std::string& renderer() const;

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace vts
