#version 450 core
// The laser's depth map for the camera image (render/camera_renderer.cpp):
// the scene seen from the laser's origin through a thin frustum around the
// sheet (x across it, y along the fan), keeping the nearest range per
// direction, so the camera image lights only what the laser reaches.
layout(location = 0) in vec3 position;
uniform mat4 sensor_from_mesh;
uniform vec2 laser_tan;   // tan of the half angles across (x) and along (y) the sheet
uniform vec2 depth_ab;    // z_clip = a z + b
out vec3 p_sensor;
void main() {
  p_sensor = (sensor_from_mesh * vec4(position, 1.0)).xyz;
  vec3 p = p_sensor;
  gl_Position = vec4(p.y / laser_tan.y, p.x / laser_tan.x, depth_ab.x * p.z + depth_ab.y, p.z);
}
