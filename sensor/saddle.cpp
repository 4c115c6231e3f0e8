#include "sensor/saddle.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <unordered_map>
#include <vector>

#include "sensor/field_error.h"
#include "sensor/workpiece.h"

namespace vts {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kTwoPi = 2.0 * std::numbers::pi;
// The flanks' open angle 90 + asin(r/R) stays within the tracker's fillet
// range (<= 150 degrees): r / R below sin 60 degrees.
constexpr double kMaxRadiusRatio = 0.8660254037844386;

// The O-grid's reach beyond the hole (unrolled mm), see Layout.
double ogrid_margin(const SaddleParams& p) { return std::max(3.0 * p.cell_mm, 0.2 * p.branch_radius_mm); }

// The tessellation's counts and the patch of the lattice the O-grid replaces.
struct Layout {
  double R, r, L, H, h;
  int nu, nv;          // lattice columns (along x) and points around
  double hu, hv;       // their steps
  double au, av;       // the patch: an ellipse (u/au)^2 + (v/av)^2 < 1 around the hole
  explicit Layout(const SaddleParams& p)
      : R(p.main_radius_mm), r(p.branch_radius_mm), L(p.main_length_mm), H(p.branch_height_mm), h(p.cell_mm) {
    nu = std::max(2, static_cast<int>(std::ceil(L / h - 1e-9)));
    nv = std::max(8, static_cast<int>(std::ceil(kTwoPi * R / h - 1e-9)));
    hu = L / nu;
    hv = kTwoPi * R / nv;
    const double m = ogrid_margin(p);
    au = r + m;
    av = R * std::asin(r / R) + m;
  }
  // Lattice point (i, j): u, and v in [-pi R, pi R) (v = 0 on the top).
  double u(int i) const { return i == nu ? 0.5 * L : -0.5 * L + i * hu; }
  double v(int i, int j) const {
    double v = (j + 0.5 * (i & 1)) * hv - kPi * R;
    if (v >= kPi * R) v -= kTwoPi * R;
    return v;
  }
  bool in_patch(double u, double v) const { return (u / au) * (u / au) + (v / av) * (v / av) < 1.0; }
  Vec3 on_main(double u, double v) const { return Vec3(u, R * std::sin(v / R), R * std::cos(v / R)); }
  // The hole (the saddle curve) in unrolled coordinates, and its angle in
  // the patch's normalized coordinates, unwrapped to follow t.
  Vec2 curve_uv(double t) const { return Vec2(r * std::cos(t), R * std::asin(r * std::sin(t) / R)); }
  double angle(const Vec2& uv) const { return std::atan2(uv.y() / av, uv.x() / au); }
  double curve_angle(double t) const { return t + std::remainder(angle(curve_uv(t)) - t, kTwoPi); }
  // The curve parameter whose normalized angle is theta (in [t0, t0 + 2 pi)).
  double t_at_angle(double theta) const {
    double lo = theta - 1.0, hi = theta + 1.0;  // |curve_angle(t) - t| < 1 rad
    for (int k = 0; k < 60; ++k) {
      const double mid = 0.5 * (lo + hi);
      (curve_angle(mid) < theta ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
  }
  double curve_z(double t) const { return std::sqrt(R * R - r * r * std::sin(t) * std::sin(t)); }
};

double cross2(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

struct Builder {
  Mesh m;
  const Pose& pose;
  explicit Builder(const Pose& p) : pose(p) {}
  std::uint32_t vertex(const Vec3& p) {
    m.vertices.push_back((pose * p).cast<float>());
    return static_cast<std::uint32_t>(m.vertices.size() - 1);
  }
  void tri(std::uint32_t a, std::uint32_t b, std::uint32_t c) { m.triangles.push_back({a, b, c}); }
};

}  // namespace

std::string validate(const SaddleParams& p) {
  for (const auto& k : kSaddleParamNumbers) {
    const double v = p.*k.member;
    if (!std::isfinite(v)) return field_error(k.key, v, "must be a finite number");
    if (v <= 0.0) return field_error(k.key, v, "must be > 0");
  }
  const double R = p.main_radius_mm, r = p.branch_radius_mm, h = p.cell_mm;
  if (r >= kMaxRadiusRatio * R)
    return field_error("branch_radius_mm", r,
                       "must be below 0.866 * main_radius_mm = " + message_number(kMaxRadiusRatio * R) +
                           " (the flanks' open angle 90 + asin(r/R) must stay under 150 degrees)");
  if (h > 0.25 * r)
    return field_error("cell_mm", h, "must be at most branch_radius_mm / 4 = " + message_number(0.25 * r));
  const double min_length = 2.0 * (r + ogrid_margin(p) + 2.0 * h);
  if (p.main_length_mm < min_length)
    return field_error(
        "main_length_mm", p.main_length_mm,
        "must be at least " + message_number(min_length) + " (the branch, the mesh around it and two cells each side)");
  if (p.branch_height_mm < R + 2.0 * h)
    return field_error("branch_height_mm", p.branch_height_mm,
                       "must be at least main_radius_mm + 2 * cell_mm = " + message_number(R + 2.0 * h) +
                           " (the branch's top stands above the main pipe's crown)");
  if (saddle_triangle_estimate(p) > static_cast<double>(kMaxWorkpieceTriangles))
    return field_error(
        "cell_mm", h,
        "too small: the mesh would have more than " + std::to_string(kMaxWorkpieceTriangles) + " triangles");
  return {};
}

double saddle_triangle_estimate(const SaddleParams& p) {
  const double area = kTwoPi * p.main_radius_mm * p.main_length_mm +
                      kTwoPi * p.branch_radius_mm * (p.branch_height_mm - p.main_radius_mm + p.branch_radius_mm);
  return 2.0 * area / (p.cell_mm * p.cell_mm);
}

Mesh saddle_mesh(const SaddleParams& params, const Pose& world_from_saddle) {
  const Layout g(params);
  Builder b(world_from_saddle);
  Mesh& m = b.m;
  m.vertices.reserve(static_cast<std::size_t>(0.6 * saddle_triangle_estimate(params)));
  m.triangles.reserve(static_cast<std::size_t>(1.1 * saddle_triangle_estimate(params)));

  // 1. The main pipe's lattice: column i at u_i, point j around at v_j,
  // odd columns turned half a step. Points inside the patch are left out.
  const int nu = g.nu, nv = g.nv;
  constexpr std::uint32_t kNone = ~0u;
  std::vector<std::uint32_t> id(static_cast<std::size_t>(nu + 1) * nv, kNone);
  std::vector<Vec2> uv_of;  // unrolled coordinates of the main pipe's vertices, by index
  const auto at = [&](int i, int j) -> std::uint32_t& { return id[static_cast<std::size_t>(i) * nv + (j % nv)]; };
  std::vector<char> inside(id.size(), 0);
  for (int i = 0; i <= nu; ++i)
    for (int j = 0; j < nv; ++j)
      inside[static_cast<std::size_t>(i) * nv + j] = g.in_patch(g.u(i), g.v(i, j));
  for (int i = 0; i <= nu; ++i)
    for (int j = 0; j < nv; ++j) {
      if (inside[static_cast<std::size_t>(i) * nv + j]) continue;
      at(i, j) = b.vertex(g.on_main(g.u(i), g.v(i, j)));
      uv_of.resize(m.vertices.size());
      uv_of.back() = Vec2(g.u(i), g.v(i, j));
    }
  // Two triangles per (i, j), counter-clockwise in (u, v), which is outward.
  // Those touching the patch are left out; their edges give its outline.
  std::unordered_map<std::uint64_t, std::uint64_t> removed_edges;  // key (a, b) -> 1
  const auto key = [](std::uint64_t a, std::uint64_t c) { return a << 32 | c; };
  struct LatticeId { int i, j; };
  const auto flat = [&](LatticeId p) { return static_cast<std::uint64_t>(p.i) * nv + (p.j % nv); };
  const auto emit = [&](LatticeId p, LatticeId q, LatticeId s) {
    const std::uint64_t fp = flat(p), fq = flat(q), fs = flat(s);
    if (inside[fp] || inside[fq] || inside[fs]) {
      removed_edges[key(fp, fq)] = 1;
      removed_edges[key(fq, fs)] = 1;
      removed_edges[key(fs, fp)] = 1;
      return;
    }
    b.tri(at(p.i, p.j), at(q.i, q.j), at(s.i, s.j));
  };
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      const LatticeId a0{i, j}, a1{i, j + 1}, b0{i + 1, j}, b1{i + 1, j + 1};
      if (i % 2 == 0) {  // column i at j, column i + 1 at j + 1/2
        emit(a0, b0, a1);
        emit(a1, b0, b1);
      } else {           // column i at j + 1/2, column i + 1 at j
        emit(b0, b1, a0);
        emit(a0, b1, a1);
      }
    }

  // 2. The patch's outline: its triangles' edges not shared among them, in
  // order counter-clockwise around the hole.
  std::unordered_map<std::uint64_t, std::uint64_t> next;
  for (const auto& [k, unused] : removed_edges) {
    const std::uint64_t a = k >> 32, c = k & 0xffffffffu;
    if (removed_edges.count(key(c, a))) continue;
    if (!next.emplace(a, c).second) throw std::logic_error("saddle_mesh: the patch's outline touches itself");
  }
  if (next.empty()) throw std::logic_error("saddle_mesh: no patch");
  // Start at the outline point nearest the +u axis, so the loop's angles rise from about 0.
  std::uint64_t start = next.begin()->first;
  const auto uv_flat = [&](std::uint64_t f) {
    const int i = static_cast<int>(f / nv), j = static_cast<int>(f % nv);
    return Vec2(g.u(i), g.v(i, j));
  };
  for (const auto& [a, unused] : next)
    if (std::abs(g.angle(uv_flat(a))) < std::abs(g.angle(uv_flat(start)))) start = a;
  std::vector<std::uint64_t> loop;
  for (std::uint64_t f = start;;) {
    loop.push_back(f);
    f = next.at(f);
    if (f == start) break;
    if (loop.size() > next.size()) throw std::logic_error("saddle_mesh: the patch's outline is not one loop");
  }
  if (loop.size() != next.size()) throw std::logic_error("saddle_mesh: the patch's outline is several loops");
  const int K = static_cast<int>(loop.size());

  // 3. The curve's points: for each outline point, the curve point at the
  // same angle in the patch's normalized coordinates (so the O-grid's lines
  // run about radially). If the outline's angles do not rise all the way
  // round, the outline's length fraction is used instead.
  std::vector<Vec2> outer(K);
  std::vector<double> theta(K), t(K);
  for (int k = 0; k < K; ++k) {
    outer[k] = uv_flat(loop[k]);
    theta[k] = g.angle(outer[k]);
    if (k > 0) theta[k] = theta[k - 1] + std::remainder(theta[k] - theta[k - 1], kTwoPi);
  }
  bool rising = std::abs(theta.back() - theta.front() + std::remainder(theta.front() - theta.back(), kTwoPi) - kTwoPi) < 1e-6;
  for (int k = 1; k < K && rising; ++k) rising = theta[k] > theta[k - 1];
  if (!rising) {
    double total = 0.0;
    for (int k = 0; k < K; ++k) total += (outer[(k + 1) % K] - outer[k]).norm();
    double s = 0.0;
    for (int k = 0; k < K; ++k) {
      theta[k] = theta[0] + kTwoPi * s / total;
      s += (outer[(k + 1) % K] - outer[k]).norm();
    }
  }
  for (int k = 0; k < K; ++k) t[k] = g.t_at_angle(theta[k]);
  std::vector<std::uint32_t> curve(K);
  for (int k = 0; k < K; ++k) {
    const double tk = t[k];
    curve[k] = b.vertex(Vec3(g.r * std::cos(tk), g.r * std::sin(tk), g.curve_z(tk)));
  }

  // 4. The O-grid between the curve (ring 0) and the outline (ring M),
  // straight lines in (u, v) from each curve point to its outline point.
  double longest = 0.0;
  std::vector<Vec2> inner(K);
  for (int k = 0; k < K; ++k) {
    inner[k] = g.curve_uv(t[k]);
    longest = std::max(longest, (outer[k] - inner[k]).norm());
  }
  const int M = std::max(1, static_cast<int>(std::ceil(longest / g.h - 1e-9)));
  std::vector<std::uint32_t> ring_id(static_cast<std::size_t>(K) * (M + 1));
  std::vector<Vec2> ring_uv(ring_id.size());
  const auto rid = [&](int k, int mm) { return static_cast<std::size_t>(mm) * K + (k % K); };
  for (int k = 0; k < K; ++k)
    for (int mm = 0; mm <= M; ++mm) {
      const Vec2 p = inner[k] + (outer[k] - inner[k]) * (static_cast<double>(mm) / M);
      ring_uv[rid(k, mm)] = p;
      if (mm == 0) ring_id[rid(k, mm)] = curve[k];
      else if (mm == M) {
        const int i = static_cast<int>(loop[k] / nv), j = static_cast<int>(loop[k] % nv);
        ring_id[rid(k, mm)] = at(i, j);
      } else ring_id[rid(k, mm)] = b.vertex(g.on_main(p.x(), p.y()));
    }
  const auto oriented_uv = [&](std::size_t a, std::size_t c, std::size_t d) {
    if (cross2(ring_uv[c] - ring_uv[a], ring_uv[d] - ring_uv[a]) <= 0.0)
      throw std::logic_error("saddle_mesh: a folded O-grid cell (the parameters give too coarse a grid)");
    b.tri(ring_id[a], ring_id[c], ring_id[d]);
  };
  for (int k = 0; k < K; ++k)
    for (int mm = 0; mm < M; ++mm) {
      // a = (k, m), b = (k + 1, m), c = (k + 1, m + 1), d = (k, m + 1):
      // k runs counter-clockwise, m outward; split along the shorter diagonal.
      const std::size_t qa = rid(k, mm), qb = rid(k + 1, mm), qc = rid(k + 1, mm + 1), qd = rid(k, mm + 1);
      if ((ring_uv[qc] - ring_uv[qa]).norm() <= (ring_uv[qd] - ring_uv[qb]).norm()) {
        oriented_uv(qa, qc, qb);
        oriented_uv(qa, qd, qc);
      } else {
        oriented_uv(qa, qd, qb);
        oriented_uv(qb, qd, qc);
      }
    }

  // 5. The branch: rings from the curve (row 0) up to z = H (row nz); odd
  // rows at the angles halfway between the curve's. Counter-clockwise in
  // (t, z) is outward.
  const double zmin = std::sqrt(g.R * g.R - g.r * g.r);
  const int nz = std::max(2, static_cast<int>(std::ceil((g.H - zmin) / g.h - 1e-9)));
  const auto row_t = [&](int j, int k) {  // unwrapped: k = K is t[0] + 2 pi
    const double a = k < K ? t[k] : t[k - K] + kTwoPi;
    if (j % 2 == 0) return a;
    const double c = k + 1 < K ? t[k + 1] : t[k + 1 - K] + kTwoPi;
    return 0.5 * (a + c);
  };
  std::vector<std::uint32_t> prev(curve), cur(K);
  for (int j = 1; j <= nz; ++j) {
    for (int k = 0; k < K; ++k) {
      const double tk = row_t(j, k), zc = g.curve_z(tk);
      cur[k] = b.vertex(Vec3(g.r * std::cos(tk), g.r * std::sin(tk), zc + (g.H - zc) * j / nz));
    }
    for (int k = 0; k < K; ++k) {
      const int k1 = (k + 1) % K;
      if ((j - 1) % 2 == 0) {  // lower row at t_k, upper halfway
        b.tri(prev[k], prev[k1], cur[k]);
        b.tri(cur[k], prev[k1], cur[k1]);
      } else {                 // lower row halfway, upper at t_k
        b.tri(prev[k], cur[k1], cur[k]);
        b.tri(prev[k], prev[k1], cur[k1]);
      }
    }
    std::swap(prev, cur);
  }

  // 6. The ends: flat discs fanned from their centres.
  const auto fan = [&](const std::vector<std::uint32_t>& ring, const Vec3& centre, const Vec3& outward) {
    const std::uint32_t c = b.vertex(centre);
    const Vec3 n = world_from_saddle.linear() * outward;
    for (std::size_t k = 0; k < ring.size(); ++k) {
      const std::uint32_t p = ring[k], q = ring[(k + 1) % ring.size()];
      const Vec3 pc = m.vertices[c].cast<double>(), pp = m.vertices[p].cast<double>(), pq = m.vertices[q].cast<double>();
      if ((pp - pc).cross(pq - pc).dot(n) >= 0.0) b.tri(c, p, q);
      else b.tri(c, q, p);
    }
  };
  for (const int i : {0, nu}) {
    std::vector<std::uint32_t> ring(nv);
    for (int j = 0; j < nv; ++j) ring[j] = at(i, j);
    fan(ring, Vec3(g.u(i), 0.0, 0.0), Vec3(i == 0 ? -1.0 : 1.0, 0.0, 0.0));
  }
  fan(prev, Vec3(0.0, 0.0, g.H), Vec3::UnitZ());
  return m;
}

SaddlePoint saddle_point(const SaddleParams& p, double t) {
  const double R = p.main_radius_mm, r = p.branch_radius_mm;
  t = t - kTwoPi * std::floor(t / kTwoPi);
  const double s = std::sin(t), c = std::cos(t);
  const double z = std::sqrt(R * R - r * r * s * s);
  SaddlePoint q;
  q.t = t;
  q.root = Vec3(r * c, r * s, z);
  q.tangent = Vec3(-r * s, r * c, -r * r * s * c / z).normalized();
  q.main_normal = Vec3(0.0, q.root.y(), q.root.z()) / R;
  q.branch_normal = Vec3(c, s, 0.0);
  q.branch_side = q.branch_normal.cross(q.tangent).normalized();
  if (q.branch_side.z() < 0.0) q.branch_side = -q.branch_side;
  q.main_side = q.main_normal.cross(q.tangent).normalized();
  if (q.main_side.dot(q.branch_normal) < 0.0) q.main_side = -q.main_side;
  q.bisector = (q.main_side + q.branch_side).normalized();
  q.open_angle_deg = std::acos(std::clamp(q.main_side.dot(q.branch_side), -1.0, 1.0)) * 180.0 / kPi;
  return q;
}

SaddlePoint transformed(const SaddlePoint& p, const Pose& pose) {
  SaddlePoint q = p;
  const Eigen::Matrix3d& rot = pose.linear();
  q.root = pose * p.root;
  for (Vec3* v : {&q.tangent, &q.main_normal, &q.branch_normal, &q.main_side, &q.branch_side, &q.bisector})
    *v = rot * *v;
  return q;
}

std::optional<SaddlePoint> saddle_truth_in_plane(const SaddleParams& p, const Pose& world_from_saddle,
                                                 const Pose& world_from_sensor) {
  const Pose saddle_from_sensor = world_from_saddle.inverse() * world_from_sensor;
  const Vec3 n = saddle_from_sensor.linear().col(0);  // the laser plane's normal
  const Vec3 o = saddle_from_sensor.translation();
  const Vec3 axis = saddle_from_sensor.linear().col(2);
  const double R = p.main_radius_mm, r = p.branch_radius_mm;
  const auto side = [&](double t) {
    const double s = std::sin(t);
    return n.dot(Vec3(r * std::cos(t), r * s, std::sqrt(R * R - r * r * s * s)) - o);
  };
  constexpr int kSamples = 2048;
  std::optional<SaddlePoint> best;
  double best_distance = 0.0;
  double t0 = 0.0, f0 = side(0.0);
  for (int k = 1; k <= kSamples; ++k) {
    const double t1 = kTwoPi * k / kSamples, f1 = side(t1);
    if ((f0 <= 0.0) != (f1 <= 0.0)) {
      double lo = t0, hi = t1, flo = f0;
      for (int it = 0; it < 60; ++it) {
        const double mid = 0.5 * (lo + hi), fm = side(mid);
        if ((fm <= 0.0) == (flo <= 0.0)) lo = mid, flo = fm;
        else hi = mid;
      }
      const SaddlePoint q = saddle_point(p, 0.5 * (lo + hi));
      const Vec3 d = q.root - o;
      const double distance = (d - d.dot(axis) * axis).norm();  // from the optical axis
      if (!best || distance < best_distance) best = q, best_distance = distance;
    }
    t0 = t1, f0 = f1;
  }
  if (!best) return std::nullopt;
  return transformed(*best, world_from_saddle);
}

Pose saddle_sensor_pose(const SaddleParams& params, const Pose& world_from_saddle, double t, double standoff_mm) {
  const SaddlePoint q = transformed(saddle_point(params, t), world_from_saddle);
  Pose pose = Pose::Identity();
  if (!pose_look_at(q.root + standoff_mm * q.bisector, q.root, q.tangent, pose))
    throw std::logic_error("saddle_sensor_pose: the tangent is parallel to the bisector");
  return pose;
}

}  // namespace vts
