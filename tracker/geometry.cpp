#include "tracker/geometry.h"

#include <algorithm>
#include <limits>
#include <numbers>

namespace vts::tracker {

void Line::orient_towards(const Vec2& point) {
  if (signed_distance(point) < 0.0) {
    n = -n;
    c = -c;
  }
}

Moments moments_of(std::span<const Vec2> points) {
  Moments m;
  m.count = static_cast<int>(points.size());
  if (points.empty()) return m;
  for (const auto& p : points) m.mean += p;
  m.mean /= static_cast<double>(points.size());
  for (const auto& p : points) {
    const Vec2 d = p - m.mean;
    m.syy += d.x() * d.x();
    m.szz += d.y() * d.y();
    m.syz += d.x() * d.y();
  }
  return m;
}

std::optional<LineFit> fit_line(const Moments& m) {
  if (m.count < 2) return std::nullopt;
  const double a = m.syy, b = m.syz, c = m.szz;
  const double half_diff = 0.5 * (a - c);
  const double root = std::sqrt(half_diff * half_diff + b * b);
  const double mid = 0.5 * (a + c);
  const double l_max = mid + root;
  const double l_min = std::max(0.0, mid - root);
  if (!(l_max > 0.0)) return std::nullopt;
  // Eigenvector of l_max is the direction: take the better conditioned of the
  // two equivalent forms (b, l - a) and (l - c, b). In scalars, its norm from
  // the squared norm already compared (the fit's latency counts: the tracker
  // fits many short lines).
  const double d1y = b, d1z = l_max - a, d2y = l_max - c, d2z = b;
  const double n1 = d1y * d1y + d1z * d1z, n2 = d2y * d2y + d2z * d2z;
  const bool first = n1 >= n2;
  Vec2 d(first ? d1y : d2y, first ? d1z : d2z);
  const double norm = std::sqrt(first ? n1 : n2);
  if (!(norm > 0.0)) {
    // Isotropic scatter cannot happen for l_max > 0 unless b == 0 and a == c;
    // then any direction fits equally badly: pick y.
    d = Vec2(1.0, 0.0);
  } else {
    d /= norm;
  }
  LineFit f;
  f.line.n = Vec2(-d.y(), d.x());
  f.line.c = f.line.n.dot(m.mean);
  f.rms_mm = std::sqrt(l_min / m.count);
  f.count = m.count;
  f.centroid = m.mean;
  return f;
}

std::optional<LineFit> fit_line(std::span<const Vec2> points) { return fit_line(moments_of(points)); }

std::optional<Vec2> intersect(const Line& a, const Line& b, double min_sin) {
  const double det = a.n.x() * b.n.y() - a.n.y() * b.n.x();
  if (!(std::abs(det) >= min_sin)) return std::nullopt;
  return Vec2((a.c * b.n.y() - a.n.y() * b.c) / det, (a.n.x() * b.c - a.c * b.n.x()) / det);
}

double acute_angle_deg(const Line& a, const Line& b) {
  const double cosine = std::clamp(std::abs(a.n.dot(b.n)), 0.0, 1.0);
  return std::acos(cosine) * 180.0 / std::numbers::pi;
}

double angle_between_deg(const Vec2& u, const Vec2& v) {
  const double nu = u.norm(), nv = v.norm();
  if (!(nu > 0.0) || !(nv > 0.0)) return std::numeric_limits<double>::quiet_NaN();
  const double cosine = std::clamp(u.dot(v) / (nu * nv), -1.0, 1.0);
  return std::acos(cosine) * 180.0 / std::numbers::pi;
}

}  // namespace vts::tracker
