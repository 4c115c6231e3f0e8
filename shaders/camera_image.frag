#version 450 core
// Camera image (render/camera_renderer.cpp): the radiance each pixel sees,
// W/(mm^2 sr): the laser pass, drawn over the slab around the sheet only
// (camera_image.vert) and added to the ambient pass (camera_ambient.frag) in
// the red channel. The formulas are docs/SENSOR_MODEL.md's, "The camera image":
//   sheet: a Gaussian across the laser plane, 1/e^2 half thickness
//     w(r) = w0 sqrt(1 + ((r - r_f) / z_R)^2), power P spread evenly over
//     the fan angle phi: irradiance E = P / (phi r) g(x) cos(i); what a pixel
//     records is g blurred by the lens (a Gaussian of psf_px pixels, taken
//     to the surface through the pixel's gradient of x) and averaged over
//     the pixel's footprint across the sheet (erf), so a line thinner than
//     a pixel keeps its sub-pixel position;
//   surface: diffuse rho_d / pi plus a Gaussian specular lobe of share rho_s
//     and width sigma around the mirror direction;
//   lit only where the laser sees the point (laser_range: the laser's own
//     depth map, nearest range per direction);
//   cos^4 of the angle off the camera's axis.
in vec3 p_sensor;
layout(location = 0) out vec2 radiance;

uniform vec3 cam_centre;
uniform vec3 cam_axis;      // sensor frame
uniform float power_w;
uniform float fan_rad;
uniform float tan_half_fan;
uniform float waist_mm;
uniform float focus_mm;
uniform float rayleigh_mm;
uniform float diffuse;      // rho_d
uniform float specular;     // rho_s
uniform float lobe_rad;     // sigma
uniform float psf_px;       // the lens blur's std dev, px
uniform sampler2D laser_range;
uniform vec2 laser_tan;     // tan of the laser map's half angles across (x) and along (y) the sheet

const float kPi = 3.14159265358979;
float lambert_of(float rho) { return rho / kPi; }

// Abramowitz and Stegun 7.1.26 (|error| < 1.5e-7).
float erf_approx(float x) {
  float s = sign(x);
  x = abs(x);
  float t = 1.0 / (1.0 + 0.3275911 * x);
  float y = 1.0 - (((((1.061405429 * t - 1.453152027) * t) + 1.421413741) * t - 0.284496736) * t +
                   0.254829592) * t * exp(-x * x);
  return s * y;
}

void main() {
  vec3 p = p_sensor;
  // Derivatives first, while every pixel of the quad is still running.
  vec3 dpx = dFdx(p), dpy = dFdy(p);
  float h = 0.5 * (abs(dpx.x) + abs(dpy.x));  // the pixel's half footprint across the sheet
  radiance = vec2(0.0);
  vec3 v = normalize(cam_centre - p);
  vec3 n = normalize(cross(dpx, dpy));
  if (dot(n, v) < 0.0) n = -n;
  float r = length(p);
  vec3 l = p / r;
  float cos_i = -dot(l, n);
  if (p.z <= 0.0 || abs(p.y) > tan_half_fan * p.z || cos_i <= 0.0) return;
  // Seen by the laser? Its depth map holds the nearest range per direction.
  vec2 s = vec2(p.y / (p.z * laser_tan.y), p.x / (p.z * laser_tan.x)) * 0.5 + 0.5;
  if (any(lessThan(s, vec2(0.0))) || any(greaterThan(s, vec2(1.0)))) return;
  ivec2 size = textureSize(laser_range, 0);
  float nearest = texelFetch(laser_range, clamp(ivec2(s * vec2(size)), ivec2(0), size - 1), 0).r;
  float texel = 2.0 * laser_tan.y / float(size.x);
  float bias = 0.02 + r * texel * 3.0 / max(cos_i, 0.1);
  if (r > nearest + bias) return;

  float q = (r - focus_mm) / rayleigh_mm;
  float w = waist_mm * sqrt(1.0 + q * q);
  float x = p.x;
  float blur = psf_px * length(vec2(dpx.x, dpy.x));  // the lens blur, mm across the sheet
  float sigma = sqrt(0.25 * w * w + blur * blur);
  float k = 0.70710678 / sigma;
  float g;  // the sheet's profile across, unit integral, blurred and averaged over the pixel
  if (h * k > 1e-3) g = 0.25 * (erf_approx((x + h) * k) - erf_approx((x - h) * k)) / h;
  else g = 0.39894228 / sigma * exp(-0.5 * x * x / (sigma * sigma));
  float e = power_w / (fan_rad * r) * g * cos_i;
  // The lobe's angle a to the mirror direction enters as a^2 ~ 2 (1 - cos a)
  // (within 1 % of the exponent up to 14 degrees; beyond, the lobe is gone).
  float spec = 0.0;
  if (specular > 0.0) {
    float a2 = 2.0 * (1.0 - dot(reflect(l, n), v));
    spec = specular * exp(-0.5 * a2 / (lobe_rad * lobe_rad)) / (2.0 * kPi * lobe_rad * lobe_rad * max(dot(n, v), 0.05));
  }
  float cos_off = max(dot(cam_axis, -v), 0.0);
  radiance.x = e * (lambert_of(diffuse) + spec) * (cos_off * cos_off) * (cos_off * cos_off);
}
