#version 450 core
// Camera-view projection of the mesh for the shadow pass (render/raster_source.cpp
// builds the matrix). Every occluder of a lit point lies on the sight line from
// the camera (sensor x = baseline) to the point (x = 0), so everything outside
// the slab between those two planes is clipped away before rasterization.
layout(location = 0) in vec3 a_position_mm;  // mesh-centred world mm

uniform mat4 u_clip_from_mesh;
// The slab as two planes in mesh-centred world coordinates: a point is kept
// where dot(plane.xyz, p) + plane.w >= 0 for both.
uniform vec4 u_slab[2];

out float gl_ClipDistance[2];

void main() {
  gl_Position = u_clip_from_mesh * vec4(a_position_mm, 1.0);
  gl_ClipDistance[0] = dot(u_slab[0].xyz, a_position_mm) + u_slab[0].w;
  gl_ClipDistance[1] = dot(u_slab[1].xyz, a_position_mm) + u_slab[1].w;
}
