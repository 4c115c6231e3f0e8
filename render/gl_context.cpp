#include "render/gl_context.h"

#include <GL/osmesa.h>
#include <GL/gl.h>

#include <array>
#include <stdexcept>

namespace vts {

namespace {
// The context of ours current on this thread (as far as we made it so).
thread_local GlContext::Impl* t_current = nullptr;
}  // namespace

struct GlContext::Impl {
  OSMesaContext context = nullptr;
  // OSMesa needs a bound colour buffer; all real rendering goes to FBOs.
  std::array<unsigned char, 4> dummy{};
  std::string version;
  std::string renderer;

  ~Impl() {
    if (!context) return;
    // Unbind first so this thread is not left with a dangling current context.
    if (OSMesaGetCurrentContext() == context) OSMesaMakeCurrent(nullptr, nullptr, 0, 0, 0);
    if (t_current == this) t_current = nullptr;
    // Frees every GL object the context still owns.
    OSMesaDestroyContext(context);
  }
};

namespace {

// Makes `impl` current on this thread, or none when null.
void bind(GlContext::Impl* impl) {
  if (!impl) {
    if (OSMesaGetCurrentContext()) OSMesaMakeCurrent(nullptr, nullptr, 0, 0, 0);
  } else if (OSMesaGetCurrentContext() != impl->context &&
             !OSMesaMakeCurrent(impl->context, impl->dummy.data(), GL_UNSIGNED_BYTE, 1, 1)) {
    throw std::runtime_error("GlContext: OSMesaMakeCurrent failed");
  }
  t_current = impl;
}

std::string gl_string(GLenum name) {
  const auto* s = reinterpret_cast<const char*>(glGetString(name));
  return s ? std::string(s) : std::string();
}
}  // namespace

GlContext::GlContext(After after) : impl_(std::make_unique<Impl>()) {
  Impl* const previous = t_current;
  const int attribs[] = {OSMESA_FORMAT,       OSMESA_RGBA,
                         OSMESA_DEPTH_BITS,   0,
                         OSMESA_STENCIL_BITS, 0,
                         OSMESA_ACCUM_BITS,   0,
                         OSMESA_PROFILE,      OSMESA_CORE_PROFILE,
                         OSMESA_CONTEXT_MAJOR_VERSION, 4,
                         OSMESA_CONTEXT_MINOR_VERSION, 5,
                         0};
  impl_->context = OSMesaCreateContextAttribs(attribs, nullptr);
  if (!impl_->context)
    throw std::runtime_error(
        "GlContext: OSMesaCreateContextAttribs failed to create an OpenGL 4.5 core "
        "profile context (is Mesa's OSMesa with llvmpipe installed?)");
  make_current();
  impl_->version = gl_string(GL_VERSION);
  impl_->renderer = gl_string(GL_RENDERER);
  // NULL strings mean the gl* symbols resolved to another libGL (link order).
  if (impl_->version.empty())
    throw std::runtime_error(
        "GlContext: glGetString(GL_VERSION) returned NULL with a current OSMesa context; "
        "libOSMesa must come before libGL/libOpenGL on the link line");
  if (after == After::Previous) bind(previous);
}

GlContext::~GlContext() = default;
GlContext::GlContext(GlContext&&) noexcept = default;
GlContext& GlContext::operator=(GlContext&&) noexcept = default;

void GlContext::make_current() {
  if (!impl_ || !impl_->context) throw std::runtime_error("GlContext: used after move");
  bind(impl_.get());
}

GlContext::Binding::Binding(GlContext& context) : previous_(t_current) { context.make_current(); }

GlContext::Binding::~Binding() {
  try {
    bind(previous_);
  } catch (...) {
    // Re-binding a context that worked before cannot fail short of a
    // broken driver; nothing better to do in a destructor.
  }
}

bool GlContext::is_current() const {
  return impl_ && impl_->context && OSMesaGetCurrentContext() == impl_->context;
}

const std::string& GlContext::version() const { return impl_->version; }
const std::string& GlContext::renderer() const { return impl_->renderer; }

}  // namespace vts
