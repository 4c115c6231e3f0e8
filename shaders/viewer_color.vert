#version 330 core
// vts-view: unlit coloured lines, points and translucent triangles, world mm.
layout(location = 0) in vec3 a_position_mm;
layout(location = 1) in vec4 a_color;

uniform mat4 u_clip_from_world;
uniform float u_point_size_px;

out vec4 v_color;

void main() {
  v_color = a_color;
  gl_PointSize = u_point_size_px;
  gl_Position = u_clip_from_world * vec4(a_position_mm, 1.0);
}
