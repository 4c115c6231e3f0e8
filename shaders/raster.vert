#version 450 core
// Laser-view projection of the mesh (render/raster_source.cpp builds the matrix).
// Positions are world mm relative to the mesh centre, so the float transform
// does not lose precision far from the world origin.
layout(location = 0) in vec3 a_position_mm;

uniform mat4 u_clip_from_mesh;

void main() {
  gl_Position = u_clip_from_mesh * vec4(a_position_mm, 1.0);
}
