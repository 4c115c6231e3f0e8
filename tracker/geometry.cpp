#include "tracker/geometry.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>

#include <Eigen/Eigenvalues>

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

LineCov line_cov(const Line& line, const Moments& m, double sigma2) {
  LineCov lc;
  lc.mean = m.mean;
  lc.n = line.n;
  const Vec2 d = line.direction();
  const double spread = d.x() * d.x() * m.syy + 2.0 * d.x() * d.y() * m.syz + d.y() * d.y() * m.szz;
  lc.var_offset = m.count > 0 ? sigma2 / m.count : std::numeric_limits<double>::infinity();
  lc.var_angle = spread > 0.0 ? sigma2 / spread : std::numeric_limits<double>::infinity();
  return lc;
}

double residual_variance(const Line& line, const Moments& m, double prior_var, double prior_dof) {
  const Vec2& n = line.n;
  const double off = line.signed_distance(m.mean);
  const double rss = n.x() * n.x() * m.syy + 2.0 * n.x() * n.y() * m.syz + n.y() * n.y() * m.szz + m.count * off * off;
  const double dof = m.count - 2 + prior_dof;
  if (!(dof > 0.0)) return prior_var;
  return (std::max(rss, 0.0) + prior_dof * prior_var) / dof;
}

Eigen::Matrix2d intersection_cov(const LineCov& a, const LineCov& b, const Vec2& x) {
  // n_a . x = c_a, n_b . x = c_b: a shift of each line along its normal by
  // da, db moves x by N^-1 (da, db), N's rows the normals.
  Eigen::Matrix2d nn;
  nn << a.n.x(), a.n.y(), b.n.x(), b.n.y();
  const double det = nn.determinant();
  if (!(std::abs(det) > 1e-12)) return Eigen::Matrix2d::Constant(std::numeric_limits<double>::infinity());
  const Eigen::Matrix2d inv = nn.inverse();
  return inv * Eigen::Vector2d(a.across_var(x), b.across_var(x)).asDiagonal() * inv.transpose();
}

double prob_outside_circle(const Eigen::Matrix2d& cov, double r) {
  if (!cov.allFinite()) return 1.0;
  if (!(r > 0.0)) return 1.0;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(0.5 * (cov + cov.transpose()));
  const double l1 = std::max(es.eigenvalues()(1), 0.0), l2 = std::max(es.eigenvalues()(0), 0.0);
  if (l1 <= 0.0) return 0.0;
  // e = sqrt(l1) z1 u1 + sqrt(l2) z2 u2, z standard normal: P(|e| <= r) is
  // the integral over |z1| <= a = r / sqrt(l1) of phi(z1) P(|z2| <= h(z1)),
  // h = sqrt((r^2 - l1 z1^2) / l2); with z1 = a sin t it is smooth in t
  // (Simpson's rule over t in [0, pi / 2], the integrand symmetric in z1;
  // a at most 9: phi beyond is below 1e-17).
  const double a = std::min(r / std::sqrt(l1), 9.0);
  constexpr int n = 64;  // even
  const double h = 0.5 * std::numbers::pi / n;
  // sin and cos of the nodes t = k h, the same for every call.
  static const std::array<std::array<double, 2>, n + 1> trig = [h] {
    std::array<std::array<double, 2>, n + 1> v{};
    for (int k = 0; k <= n; ++k) v[k] = {std::sin(k * h), std::cos(k * h)};
    return v;
  }();
  double sum = 0.0;
  for (int k = 0; k <= n; ++k) {
    const double z = a * trig[k][0];
    const double rest = std::max(r * r - l1 * z * z, 0.0);
    // erf is 1 exactly from 6 on (glibc: from about 5.92): most nodes of a
    // narrow ellipse need no call.
    const double q = l2 > 0.0 ? rest / (2.0 * l2) : 0.0;
    const double inner = l2 > 0.0 && q < 36.0 ? std::erf(std::sqrt(q)) : 1.0;
    const double f = std::exp(-0.5 * z * z) * inner * a * trig[k][1];
    sum += f * (k == 0 || k == n ? 1.0 : (k % 2 ? 4.0 : 2.0));
  }
  const double inside = 2.0 * sum * h / 3.0 / std::sqrt(2.0 * std::numbers::pi);
  return std::clamp(1.0 - inside, 0.0, 1.0);
}

}  // namespace vts::tracker
