#include "geometry.h"

#include "dmath.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace vts_corpus {

namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kPi = std::numbers::pi;
}  // namespace

const char* face_name(int face) {
  static const char* const names[kFaceCount] = {
      "other",  "rounding", "flange_top", "web_open",    "web_bottom", "outer1",   "outer2",
      "end1",   "end2",     "lower_top",  "upper_top",   "upper_edge", "upper_bottom",
      "top1",   "top2",     "edge1",      "edge2",       "bevel1",     "bevel2",   "root1",
      "root2",  "backing",  "tack",       "decoy",       "body",       "arc1",     "arc2",
      "cap"};
  return (face >= 0 && face < kFaceCount) ? names[face] : "?";
}

Polygon make_polygon(const std::vector<Corner>& in, double max_arc_step_deg) {
  // Drop a corner that coincides with the next one (a zero-length face, e.g. a
  // v-groove root face of 0 mm): the next corner keeps its own outgoing face.
  std::vector<Corner> c;
  c.reserve(in.size());
  for (std::size_t i = 0; i < in.size(); ++i) {
    const Corner& next = in[(i + 1) % in.size()];
    if ((next.p - in[i].p).norm() < 1e-9) continue;
    c.push_back(in[i]);
  }
  Polygon poly;
  const std::size_t n = c.size();
  if (n < 3) return poly;
  const double step = max_arc_step_deg * kPi / 180.0;
  auto emit = [&](const Vec2& p, int face) {
    poly.pts.push_back(p);
    poly.faces.push_back(face);
  };
  for (std::size_t i = 0; i < n; ++i) {
    const Corner& k = c[i];
    const Vec2& prev = c[(i + n - 1) % n].p;
    const Vec2& next = c[(i + 1) % n].p;
    const double len1 = (prev - k.p).norm(), len2 = (next - k.p).norm();
    const Vec2 u1 = (prev - k.p) / len1, u2 = (next - k.p) / len2;
    const double phi = dm::acos(std::clamp(u1.dot(u2), -1.0, 1.0));  // angle at the corner
    if (k.kind == CornerKind::Sharp || k.size_mm <= 0.0 || phi > kPi - 1e-6 || phi < 1e-6) {
      emit(k.p, k.face_out);
      continue;
    }
    const double max_leg = 0.45 * std::min(len1, len2);
    if (k.kind == CornerKind::Chamfer) {
      const double leg = std::min(k.size_mm, max_leg);
      emit(k.p + leg * u1, kFaceRounding);
      emit(k.p + leg * u2, k.face_out);
      continue;
    }
    // Round: an arc tangent to both edges.
    const double half = 0.5 * phi;
    double leg = k.size_mm / dm::tan(half);
    leg = std::min(leg, max_leg);
    const double r = leg * dm::tan(half);
    const Vec2 t1 = k.p + leg * u1, t2 = k.p + leg * u2;
    const Vec2 centre = k.p + (u1 + u2).normalized() * (r / dm::sin(half));
    const double a1 = dm::atan2(t1.y() - centre.y(), t1.x() - centre.x());
    const double a2 = dm::atan2(t2.y() - centre.y(), t2.x() - centre.x());
    double sweep = a2 - a1;
    while (sweep > kPi) sweep -= 2 * kPi;
    while (sweep <= -kPi) sweep += 2 * kPi;
    const int segments = std::max(1, static_cast<int>(std::ceil(std::abs(sweep) / step)));
    emit(t1, kFaceRounding);
    for (int s = 1; s < segments; ++s) {
      const double a = a1 + sweep * s / segments;
      emit(centre + r * Vec2(dm::cos(a), dm::sin(a)), kFaceRounding);
    }
    emit(t2, k.face_out);
  }
  return poly;
}

Polygon make_circle(const Vec2& centre, double radius_mm, int face, int segments) {
  Polygon poly;
  for (int i = 0; i < segments; ++i) {
    const double a = 2 * kPi * i / segments;
    poly.pts.push_back(centre + radius_mm * Vec2(dm::cos(a), dm::sin(a)));
    poly.faces.push_back(face);
  }
  return poly;
}

Polygon transformed(const Polygon& poly, const Mat2& A, const Vec2& t) {
  Polygon out = poly;
  for (auto& p : out.pts) p = mul(A, p) + t;
  return out;
}

Polygon clipped_above(const Polygon& poly, double z_min) {
  Polygon out;
  const std::size_t n = poly.pts.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2& a = poly.pts[i];
    const Vec2& b = poly.pts[(i + 1) % n];
    const bool a_in = a.y() >= z_min, b_in = b.y() >= z_min;
    if (a_in) {
      out.pts.push_back(a);
      out.faces.push_back(poly.faces[i]);
    }
    if (a_in != b_in) {
      const double s = (z_min - a.y()) / (b.y() - a.y());
      Vec2 p = a + s * (b - a);
      p.y() = z_min;
      out.pts.push_back(p);
      out.faces.push_back(b_in ? poly.faces[i] : kFaceOther);  // leaving: the cut edge follows
    }
  }
  if (out.pts.size() < 3) return {};
  return out;
}

void Scene::add(const Polygon& poly) {
  const std::size_t n = poly.pts.size();
  double area2 = 0;  // shoelace: > 0 for counter-clockwise
  for (std::size_t i = 0; i < n; ++i) area2 += cross(poly.pts[i], poly.pts[(i + 1) % n]);
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2& a = poly.pts[i];
    const Vec2& b = poly.pts[(i + 1) % n];
    edges.push_back(area2 >= 0 ? Edge{a, b, poly.faces[i]} : Edge{b, a, poly.faces[i]});
  }
}

double nearest_hit_bruteforce(const Scene& scene, const Vec2& origin, const Vec2& dir,
                              double t_min, int* edge_index) {
  double best = kNaN;
  int best_edge = -1;
  for (std::size_t i = 0; i < scene.edges.size(); ++i) {
    const double t = ray_edge_param(origin, dir, scene.edges[i]);
    if (t > t_min && !(t >= best)) {
      best = t;
      best_edge = static_cast<int>(i);
    }
  }
  if (edge_index) *edge_index = best_edge;
  return best;
}

int segment_blocker_bruteforce(const Scene& scene, const Vec2& from, const Vec2& to) {
  // Cast from `to` (a camera) towards `from` so that shared vertices are
  // classified by the same operations as in FanIndex-based queries.
  const Vec2 dir = from - to;
  int blocker = -1;
  double best = -1;
  for (std::size_t i = 0; i < scene.edges.size(); ++i) {
    const double lambda = ray_edge_param(to, dir, scene.edges[i]);
    if (lambda > 0 && lambda < 1.0 - 1e-9 && lambda > best) {
      best = lambda;
      blocker = static_cast<int>(i);
    }
  }
  return blocker;
}

template <class BinRange>
void FanIndex::fill(const Scene& scene, int bins, BinRange bin_range) {
  start_.assign(static_cast<std::size_t>(bins) + 1, 0);
  std::vector<std::pair<int, int>> ranges(scene.edges.size());
  for (std::size_t i = 0; i < scene.edges.size(); ++i) {
    const Edge& e = scene.edges[i];
    // Outward normal of a counter-clockwise edge: the direction rotated by -90 degrees.
    const Vec2 d = e.b - e.a;
    if (Vec2(d.y(), -d.x()).dot(apex_ - e.a) < 0) {  // facing away
      ranges[i] = {0, -1};
      continue;
    }
    const double za = e.a.y() - apex_.y(), zb = e.b.y() - apex_.y();
    int first = 0, last = bins - 1;
    if (za > 0 && zb > 0) {  // else conservatively in every bin
      const double ua = (e.a.x() - apex_.x()) / za, ub = (e.b.x() - apex_.x()) / zb;
      double lo = std::min(ua, ub), hi = std::max(ua, ub);
      lo -= 1e-9 * (1 + std::abs(lo));
      hi += 1e-9 * (1 + std::abs(hi));
      std::tie(first, last) = bin_range(lo, hi);
    }
    ranges[i] = {first, last};
    for (int b = first; b <= last; ++b) ++start_[b + 1];
  }
  for (int b = 0; b < bins; ++b) start_[b + 1] += start_[b];
  entries_.resize(start_[bins]);
  std::vector<int> cursor(start_.begin(), start_.end() - 1);
  for (std::size_t i = 0; i < ranges.size(); ++i)
    for (int b = ranges[i].first; b <= ranges[i].second; ++b) entries_[cursor[b]++] = static_cast<int>(i);
}

void FanIndex::build_columns(const Scene& scene, const Vec2& apex, const std::vector<double>& column_u) {
  apex_ = apex;
  const int bins = static_cast<int>(column_u.size());
  fill(scene, bins, [&](double lo, double hi) {
    const int first = static_cast<int>(std::lower_bound(column_u.begin(), column_u.end(), lo) - column_u.begin());
    const int last = static_cast<int>(std::upper_bound(column_u.begin(), column_u.end(), hi) - column_u.begin()) - 1;
    return std::pair<int, int>(first, last);
  });
}

void FanIndex::build_uniform(const Scene& scene, const Vec2& apex, double u_lo, double u_hi, int bins) {
  apex_ = apex;
  u_lo_ = u_lo;
  du_ = (u_hi - u_lo) / bins;
  fill(scene, bins, [&](double lo, double hi) {
    if (hi < u_lo || lo > u_hi) return std::pair<int, int>(0, -1);
    const int first = std::max(0, static_cast<int>(std::floor((lo - u_lo) / du_)));
    const int last = std::min(bins - 1, static_cast<int>(std::floor((hi - u_lo) / du_)));
    return std::pair<int, int>(first, last);
  });
}


}  // namespace vts_corpus
