#version 450 core
// Camera image (render/camera_renderer.cpp): the part as the sensor's camera
// sees it. Positions arrive in the mesh's own centred frame; sensor_from_mesh
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

// The slab around the sheet, |x| <= 3 w(r) + (2 + 3 psf) r pitch / f (the
// sheet's 1/e^2 half thickness w, two pixel footprints and three lens
// blurs; the CPU stripe's bound, sensor/camera_image.cpp), as two clip
// distances. The ambient pass does not enable them, but llvmpipe (Mesa
// 22.3) draws it far faster when the shader writes them: a full 1280 x 1024
// frame cost ~20 ms more without them; with them, no more than not drawing
// at all, within the noise (vts-bench BM_CameraImage/image_full, 2026-11-27).
uniform vec3 slab;          // waist, focus, Rayleigh range (mm)
uniform float slab_footprint;  // (2 + 3 psf) pitch / f: the margin per mm of range

out vec3 p_sensor;

void main() {
  p_sensor = (sensor_from_mesh * vec4(position, 1.0)).xyz;
  float r = length(p_sensor);
  float q = (r - slab.y) / slab.z;
  float half_width = 3.0 * slab.x * sqrt(1.0 + q * q) + r * slab_footprint;
  gl_ClipDistance[0] = half_width - p_sensor.x;
  gl_ClipDistance[1] = half_width + p_sensor.x;
  vec3 x = cam_rot * (p_sensor - cam_centre);
  float d = x.z * cos_tilt - x.x * sin_tilt;
  float col = f_px * cos_tilt * x.y + principal.x * d;  // column * D
  float row = f_px * x.x + (principal.y - first_row) * d;  // (row - first_row) * D
  gl_Position = vec4(2.0 * (col + 0.5 * d) / target.x - d,
                     2.0 * (row + 0.5 * d) / target.y - d,
                     depth_ab.x * d + depth_ab.y, d);
}
