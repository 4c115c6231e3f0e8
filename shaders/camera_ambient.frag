#version 450 core
// Camera image (render/camera_renderer.cpp): every surface the camera sees,
// nearest first, and the ambient light it reflects, diffusely: E_amb rho_d /
// pi, times cos^4 of the angle off the camera's axis. The laser light is
// traced on the CPU (sensor/camera_image.h, trace_laser_paths).
in vec3 p_sensor;
layout(location = 0) out float radiance;
uniform vec3 cam_centre;
uniform vec3 cam_axis;
uniform float diffuse;
uniform float ambient;  // W/mm^2
void main() {
  float cos_off = max(dot(cam_axis, normalize(p_sensor - cam_centre)), 0.0);
  radiance = ambient * diffuse / 3.14159265358979 * (cos_off * cos_off) * (cos_off * cos_off);
}
