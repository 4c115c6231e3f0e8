#version 450 core
// Range along this column's ray, computed as the exact ray/plane intersection
// with the covering triangle's plane instead of interpolated depth, so the
// raster matches a ray caster to well under a micrometre. In double: there are
// only about N fragments per surface per profile, and float lost up to 0.3 um
// against the reference at grazing incidence. Also the cosine of the incidence
// angle (ray to surface normal), which the error model needs.

// Column ray directions in the sensor frame (xyz, unit), from sensor/rays.h.
layout(std430, binding = 0) readonly buffer Directions { vec4 u_directions[]; };
// Per triangle (gl_PrimitiveID): unit world normal xyz and offset w, such that
// dot(normal, p) = w for points p on the triangle, p in mesh-centred world mm.
layout(std430, binding = 1) readonly buffer Planes { dvec4 u_planes[]; };

// The pose of this profile, mesh-centred world frame.
layout(std140, binding = 0) uniform Pose {
  dmat3 u_world_from_sensor_rot;  // rotation of world_from_sensor
  dvec3 u_laser_origin_mm;        // laser origin, mm
};
uniform float u_max_hit_mm;
uniform float u_depth_per_mm;   // linear depth scale: depth = range * this

// x: range, mm; y: |cos| of the incidence angle.
layout(location = 0) out vec2 o_range_mm_cos;

void main() {
  int column = int(gl_FragCoord.x);
  dvec3 dir_world = u_world_from_sensor_rot * dvec3(u_directions[column].xyz);
  dvec4 plane = u_planes[gl_PrimitiveID];
  double along_normal = dot(plane.xyz, dir_world);
  float range = float((plane.w - dot(plane.xyz, u_laser_origin_mm)) / along_normal);
  // Behind the laser, beyond the maximum hit distance, grazing (inf) or NaN.
  if (!(range > 0.0 && range <= u_max_hit_mm)) discard;
  o_range_mm_cos = vec2(range, float(abs(along_normal)));
  gl_FragDepth = range * u_depth_per_mm;
}
