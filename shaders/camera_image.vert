#version 450 core
// Camera image (render/camera_renderer.cpp): where the sensor's camera sees
// the part. Positions arrive in the mesh's own centred frame; sensor_from_mesh
// takes them to the sensor frame. The projection is the camera's, with its
// Scheimpflug tilt (sensor/camera_image.h): for camera coordinates X,
//   D = X.z cos(tau) - X.x sin(tau),  column = cx + F cos(tau) X.y / D,
//   row = cy + F X.x / D,
// written as clip coordinates with w = D, the target covering image columns
// 0..W-1 and rows first_row..first_row+rows-1 (pixel centres at integers).
layout(location = 0) in vec3 position;

uniform mat4 sensor_from_mesh;
uniform vec3 cam_centre;   // sensor frame
uniform mat3 cam_rot;      // camera_from_sensor (GLSL: column-major, set transposed)
uniform float f_px;
uniform float cos_tilt;
uniform float sin_tilt;
uniform vec2 principal;    // cx, cy
uniform vec2 target;       // width, rows
uniform float first_row;
uniform vec2 depth_ab;     // z_clip = a D + b

void main() {
  vec3 p_sensor = (sensor_from_mesh * vec4(position, 1.0)).xyz;
  vec3 x = cam_rot * (p_sensor - cam_centre);
  float d = x.z * cos_tilt - x.x * sin_tilt;
  float col = f_px * cos_tilt * x.y + principal.x * d;  // column * D
  float row = f_px * x.x + (principal.y - first_row) * d;  // (row - first_row) * D
  gl_Position = vec4(2.0 * (col + 0.5 * d) / target.x - d,
                     2.0 * (row + 0.5 * d) / target.y - d,
                     depth_ab.x * d + depth_ab.y, d);
}
