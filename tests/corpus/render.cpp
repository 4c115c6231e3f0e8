// Casting the columns and turning ideal hits into a measured profile.
#include "internal.h"

#include <algorithm>
#include <cmath>

namespace vts_corpus {

std::vector<Vec2> column_directions(const Sensor& sensor) {
  const int n = sensor.columns;
  const double half = detail::rad(sensor.fan_deg / 2);
  std::vector<Vec2> dirs(static_cast<std::size_t>(n));
  const double tan_half = dm::tan(half);
  for (int i = 0; i < n; ++i) {
    const double f = n > 1 ? static_cast<double>(i) / (n - 1) : 0.5;
    if (sensor.tangent_spacing) {
      // Evenly spaced pixels on a flat sensor: tan(angle) evenly spaced.
      const double u = tan_half * (2 * f - 1);
      dirs[i] = Vec2(u, 1.0).normalized();
    } else {
      double sin_a, cos_a;
      dm::sincos(half * (2 * f - 1), sin_a, cos_a);
      dirs[i] = Vec2(sin_a, cos_a);
    }
  }
  return dirs;
}

namespace detail {

Cast cast_scene(const Scene& scene, const Sensor& sensor, std::vector<Vec2> dirs) {
  Cast c;
  c.dir = std::move(dirs);
  const std::size_t n = c.dir.size();
  c.u.resize(n);
  for (std::size_t i = 0; i < n; ++i) c.u[i] = c.dir[i].x() / c.dir[i].y();
  c.range_mm.assign(n, kNaN);
  c.edge.assign(n, -1);
  c.status.assign(n, kNoHit);

  // Laser: nearest crossing along each column's ray from the origin.
  FanIndex laser;
  laser.build_columns(scene, Vec2(0, 0), c.u);
  const Vec2 origin(0, 0);
  double u_lo = 1e300, u_hi = -1e300;
  const Vec2 cam = sensor.camera_yz;
  for (std::size_t i = 0; i < n; ++i) {
    double best = kNaN;
    int best_edge = -1;
    for (const int* e = laser.begin(static_cast<int>(i)); e != laser.end(static_cast<int>(i)); ++e) {
      const double t = ray_edge_param(origin, c.dir[i], scene.edges[*e]);
      if (t > 1e-9 && !(t >= best)) {
        best = t;
        best_edge = *e;
      }
    }
    if (best_edge < 0) continue;
    c.range_mm[i] = best;
    c.edge[i] = best_edge;
    const double z = best * c.dir[i].y();
    if (z < sensor.z_near_mm || z > sensor.z_far_mm) {
      c.status[i] = scene.edges[best_edge].face == kFaceBody ? kBodyShadow : kOutOfRange;
      continue;
    }
    const Vec2 p = best * c.dir[i];
    if (p.y() <= cam.y() + 1e-6) {  // level with the camera: it cannot see it
      c.status[i] = kCameraShadow;
      continue;
    }
    c.status[i] = kValid;
    const double u = (p.x() - cam.x()) / (p.y() - cam.y());
    u_lo = std::min(u_lo, u);
    u_hi = std::max(u_hi, u);
  }
  if (u_lo > u_hi) return c;

  // Camera: the sight line from each hit to the camera must cross no edge.
  FanIndex camera;
  const double pad = 1e-6 * (1 + u_hi - u_lo);
  camera.build_uniform(scene, cam, u_lo - pad, u_hi + pad, static_cast<int>(n));
  for (std::size_t i = 0; i < n; ++i) {
    if (c.status[i] != kValid) continue;
    const Vec2 p = c.range_mm[i] * c.dir[i];
    const Vec2 sight = p - cam;
    const int bin = camera.bin_of(sight.x() / sight.y());
    if (bin < 0) continue;  // cannot happen: the bins span every hit
    for (const int* e = camera.begin(bin); e != camera.end(bin); ++e) {
      if (*e == c.edge[i]) continue;  // the surface the point lies on
      const double lambda = ray_edge_param(cam, sight, scene.edges[*e]);
      if (lambda > 0 && lambda < 1.0 - 1e-9) {
        c.status[i] = scene.edges[*e].face == kFaceBody ? kBodyShadow : kCameraShadow;
        break;
      }
    }
  }
  return c;
}

void finish_profile(const Scene& scene, const Cast& cast, const Imperfections& imp, Rng& noise_rng,
                    Profile& out, std::vector<std::uint8_t>& status) {
  const std::size_t n = cast.dir.size();
  std::vector<double> range = cast.range_mm;
  status = cast.status;
  auto valid = [&](std::size_t i) { return status[i] == kValid; };

  // Mill-scale waviness: the surface moved along its normal by a smooth w(s),
  // s the position along the face; tapered to 0 within 1 mm of the face's ends
  // so corners stay where they are.
  if (!imp.waves.empty()) {
    for (std::size_t i = 0; i < n; ++i) {
      if (!valid(i)) continue;
      const Edge& e = scene.edges[cast.edge[i]];
      const Vec2 ab = e.b - e.a;
      const double len = ab.norm();
      if (len < 2.0) continue;
      const Vec2 p = range[i] * cast.dir[i];
      const double s = (p - e.a).dot(ab) / len;
      const double x = std::clamp(std::min(s, len - s), 0.0, 1.0);
      const double taper = x * x * (3 - 2 * x);
      double w = 0;
      for (const auto& wave : imp.waves)
        w += wave.amplitude_mm * dm::sin(2 * detail::kPi * (s + 13.7 * e.face) / wave.wavelength_mm + wave.phase);
      const Vec2 normal(-ab.y() / len, ab.x() / len);
      const double dn = -std::max(std::abs(cast.dir[i].dot(normal)), 0.2);  // facing the ray
      range[i] += taper * w / dn;
    }
  }
  // Reflection clusters: a few consecutive columns displaced along their rays.
  for (const auto& cl : imp.reflections)
    for (int k = 0; k < cl.count; ++k) {
      const std::size_t i = static_cast<std::size_t>(cl.first + k);
      if (i < n && valid(i)) range[i] += cl.offset_mm * (1.0 + 0.05 * ((k * 7) % 5 - 2));  // not all equal
    }
  // Noise: one draw per column whatever its state, so the draws of one column
  // do not depend on the others (none without noise: its stream is its own).
  if (imp.noise_mm > 0)
    for (std::size_t i = 0; i < n; ++i) {
      const double r = noise_rng.normal();
      if (valid(i)) range[i] += imp.noise_mm * r;
    }
  if (imp.quant_step_mm > 0)
    for (std::size_t i = 0; i < n; ++i)
      if (valid(i)) range[i] = std::round(range[i] / imp.quant_step_mm) * imp.quant_step_mm;
  for (const auto& run : imp.dropout_runs)
    for (int k = 0; k < run.second; ++k) {
      const std::size_t i = static_cast<std::size_t>(run.first + k);
      if (i < n && valid(i)) status[i] = kDropout;
    }
  for (int i : imp.single_dropouts)
    if (static_cast<std::size_t>(i) < n && valid(static_cast<std::size_t>(i))) status[i] = kDropout;

  out.y.assign(n, std::numeric_limits<float>::quiet_NaN());
  out.z.assign(n, std::numeric_limits<float>::quiet_NaN());
  out.valid.assign(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    if (!valid(i) || !(range[i] > 0)) continue;
    out.y[i] = static_cast<float>(range[i] * cast.dir[i].x());
    out.z[i] = static_cast<float>(range[i] * cast.dir[i].y());
    out.valid[i] = 1;
  }
}

std::shared_ptr<Debug> make_debug(const Scene& scene, const Sensor& sensor, const Cast& cast,
                                  const std::vector<std::uint8_t>& status, const Mat2& A, const Vec2& t) {
  auto debug = std::make_shared<Debug>();
  debug->scene = scene;
  debug->sensor = sensor;
  debug->ray_dir = cast.dir;
  debug->ideal_range_mm = cast.range_mm;
  debug->hit_face.resize(cast.edge.size());
  for (std::size_t i = 0; i < cast.edge.size(); ++i)
    debug->hit_face[i] = cast.edge[i] < 0 ? -1 : scene.edges[cast.edge[i]].face;
  debug->status = status;
  debug->joint_to_sensor_A = A;
  debug->joint_to_sensor_t = t;
  return debug;
}

}  // namespace detail

Profile render_scene(const Scene& scene, const Sensor& sensor, double noise_mm, std::uint64_t seed) {
  const detail::Cast cast = detail::cast_scene(scene, sensor, column_directions(sensor));
  detail::Imperfections imp;
  imp.noise_mm = noise_mm;
  Rng noise = Rng::stream(seed, "noise");
  Profile out;
  std::vector<std::uint8_t> status;
  detail::finish_profile(scene, cast, imp, noise, out, status);
  out.truth.noise_mm = noise_mm;
  out.truth.columns = sensor.columns;
  out.truth.seed = seed;
  out.debug = detail::make_debug(scene, sensor, cast, status);
  return out;
}

}  // namespace vts_corpus
