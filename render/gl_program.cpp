#include "render/gl_program.h"

#include <GL/gl.h>
#include <GL/glext.h>

#include <algorithm>
#include <cstdio>
#include <stdexcept>
#include <string>

namespace vts {
namespace {

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

}  // namespace

GLuint compile_shader(const char* who, GLenum type, const char* source, const char* name) {
  const GLuint shader = glCreateShader(type);
  glShaderSource(shader, 1, &source, nullptr);
  glCompileShader(shader);
  GLint ok = GL_FALSE;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    const std::string log = shader_log(shader);
    glDeleteShader(shader);
    throw std::runtime_error(std::string(who) + ": shader " + name +
                             " failed to compile:\n" + log);
  }
  return shader;
}

GLuint link_program(const char* who, const char* vert_source, const char* vert_name, const char* frag_source,
                    const char* frag_name) {
  const GLuint vert = compile_shader(who, GL_VERTEX_SHADER, vert_source, vert_name);
  GLuint frag = 0;
  try {
    frag = compile_shader(who, GL_FRAGMENT_SHADER, frag_source, frag_name);
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
    throw std::runtime_error(std::string(who) + ": " + vert_name + " + " + frag_name +
                             " failed to link:\n" + log);
  }
  return program;
}

void check_gl(const char* who, const char* what) {
  const GLenum error = glGetError();
  if (error == GL_NO_ERROR) return;
  char code[16];
  std::snprintf(code, sizeof code, "0x%04x", error);
  throw std::runtime_error(std::string(who) + ": GL error " + code + " after " + what);
}

}  // namespace vts
