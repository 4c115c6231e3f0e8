#version 330 core
// vts-view: solid meshes (workpieces, torch, sensor housing), world mm.
layout(location = 0) in vec3 a_position_mm;
layout(location = 1) in vec3 a_normal;

uniform mat4 u_clip_from_world;
uniform mat4 u_world_from_model;  // rigid: its 3x3 part also maps normals

out vec3 v_position_world;
out vec3 v_normal_world;

void main() {
  vec4 p = u_world_from_model * vec4(a_position_mm, 1.0);
  v_position_world = p.xyz;
  v_normal_world = mat3(u_world_from_model) * a_normal;
  gl_Position = u_clip_from_world * p;
}
