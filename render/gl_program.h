#pragma once
// Shader programs and GL error checks shared by the renderers of render/
// (raster source, camera image). Include the GL headers before this one.
// `who` names the renderer in every message ("raster source: shader
// raster.frag failed to compile: ...").
#include <GL/gl.h>

namespace vts {

// Compiles one shader; throws std::runtime_error with the compiler's log.
GLuint compile_shader(const char* who, GLenum type, const char* source, const char* name);
// Compiles and links a vertex + fragment program; throws std::runtime_error
// with the log of whatever failed.
GLuint link_program(const char* who, const char* vert_source, const char* vert_name, const char* frag_source,
                    const char* frag_name);
// Throws std::runtime_error "<who>: GL error 0x.... after <what>" if GL has
// an error pending.
void check_gl(const char* who, const char* what);

}  // namespace vts
