#version 450 core
// Camera shadow pass (render/raster_source.cpp). The mesh is drawn from the
// camera centre into a target of one row per profile column: row i is the
// epipolar plane through the camera, the laser origin and column i's ray, so
// every occluder of column i's lit point lies in row i, at the texel that the
// lit point itself projects to. Fragments within one texel of that texel test
// their triangle exactly: does the segment from the camera to the
// lit point cross it farther than u_eps_mm from the point? If so the column is
// in shadow. The rasterizer only finds the candidate triangles.

// Column ray directions in the sensor frame (xyz, unit), from sensor/rays.h.
layout(std430, binding = 0) readonly buffer Directions { vec4 u_directions[]; };
// Per triangle: unit world normal xyz and offset w (mesh-centred world mm).
layout(std430, binding = 1) readonly buffer Planes { dvec4 u_planes[]; };
// Mesh vertices (xyz per vertex, mesh-centred world mm) and triangles.
layout(std430, binding = 2) readonly buffer Positions { float u_positions[]; };
layout(std430, binding = 3) readonly buffer Indices { uint u_indices[]; };
// Per column: x = range of the lit point (0: nothing lit), y = its texel.
layout(std430, binding = 4) readonly buffer Lit { vec2 u_lit[]; };
// Per column: set to 1 when an occluder is found (cleared before the draw).
layout(std430, binding = 5) writeonly buffer Shadowed { uint u_shadowed[]; };

layout(std140, binding = 0) uniform Pose {
  dmat3 u_world_from_sensor_rot;
  dvec3 u_laser_origin_mm;
};
layout(std140, binding = 1) uniform Camera {
  dvec3 u_camera_mm;  // camera centre, mesh-centred world mm
  double u_eps_mm;    // occluders nearer than this to the lit point do not count
};

vec3 vertex(uint index) {
  return vec3(u_positions[3 * index], u_positions[3 * index + 1], u_positions[3 * index + 2]);
}

void main() {
  int column = int(gl_FragCoord.y);
  vec2 lit = u_lit[column];
  if (!(lit.x > 0.0) || abs(int(gl_FragCoord.x) - int(lit.y)) > 1) discard;

  // In float: coordinates are mesh-centred, so float keeps ~1e-4 mm, far
  // below u_eps_mm (llvmpipe runs double arithmetic several times slower).
  vec3 camera = vec3(u_camera_mm);
  vec3 point = vec3(u_laser_origin_mm) +
               mat3(u_world_from_sensor_rot) * (lit.x * u_directions[column].xyz);
  vec3 to_point = point - camera;
  vec4 plane = vec4(u_planes[gl_PrimitiveID]);
  float den = dot(plane.xyz, to_point);
  if (den == 0.0) discard;
  // Crossing at camera + s * to_point; its distance from the lit point.
  float s = (plane.w - dot(plane.xyz, camera)) / den;
  float from_point = (1.0 - s) * length(to_point);
  if (!(s > 0.0 && from_point > float(u_eps_mm))) discard;

  vec3 x = camera + s * to_point;
  uint t = 3u * uint(gl_PrimitiveID);
  vec3 a = vertex(u_indices[t]), b = vertex(u_indices[t + 1u]), c = vertex(u_indices[t + 2u]);
  vec3 n = plane.xyz;
  if (dot(cross(b - a, x - a), n) < 0.0 || dot(cross(c - b, x - b), n) < 0.0 ||
      dot(cross(a - c, x - c), n) < 0.0)
    discard;
  u_shadowed[column] = 1u;
}
