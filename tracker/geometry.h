#pragma once
// Lines in the laser plane, in normal form so that vertical walls need no
// special case, and their total least-squares fit.
#include <cmath>
#include <optional>
#include <span>

#include <Eigen/Core>

#include "tracker/types.h"

namespace vts::tracker {

// The points p with n . p = c; n is a unit vector. The tracker orients every
// fitted line so that n points towards the sensor (the ray origin lies on the
// positive side): signed_distance > 0 is in front of the surface, < 0 behind it.
struct Line {
  Vec2 n = Vec2(0.0, -1.0);
  double c = 0.0;

  double signed_distance(const Vec2& p) const { return n.dot(p) - c; }
  double distance(const Vec2& p) const { return std::abs(signed_distance(p)); }
  // Unit direction along the line (n turned by +90 degrees).
  Vec2 direction() const { return Vec2(-n.y(), n.x()); }
  // Foot of the perpendicular from p.
  Vec2 project(const Vec2& p) const { return p - signed_distance(p) * n; }
  // Flips n and c if needed so that `point` is on the positive side.
  void orient_towards(const Vec2& point);
};

// Count, mean and centred second moments of a point set (mm, mm^2).
struct Moments {
  int count = 0;
  Vec2 mean = Vec2::Zero();
  double syy = 0.0;  // sum (y - mean_y)^2
  double szz = 0.0;  // sum (z - mean_z)^2
  double syz = 0.0;  // sum (y - mean_y)(z - mean_z)
};

Moments moments_of(std::span<const Vec2> points);

struct LineFit {
  Line line;
  double rms_mm = 0.0;  // root mean square perpendicular residual
  int count = 0;
  Vec2 centroid = Vec2::Zero();
};

// Total least squares: the line through the centroid whose normal is the
// eigenvector of the 2x2 scatter matrix with the smaller eigenvalue. Empty if
// there are fewer than two points or all points coincide. The normal's sign is
// arbitrary; orient it with Line::orient_towards.
std::optional<LineFit> fit_line(const Moments& m);
std::optional<LineFit> fit_line(std::span<const Vec2> points);

// Intersection of two lines; empty when the sine of the angle between them is
// below min_sin (parallel or nearly so).
std::optional<Vec2> intersect(const Line& a, const Line& b, double min_sin = 1e-6);

// How precisely a least-squares line is known (docs/JOINTS.md
// "Localization"): for N points whose distances from the true line are
// independent with variance sigma^2, the fitted line's offset at the points'
// mean and its direction are independent, with variances sigma^2 / N (mm^2)
// and sigma^2 / S (rad^2), S = sum (u - u_mean)^2 the points' spread along
// the line (mm^2). Across itself the line is then known at a point whose
// foot lies u from the mean to sigma^2 (1 / N + u^2 / S).
struct LineCov {
  Vec2 mean = Vec2::Zero();  // the points' mean
  Vec2 n = Vec2(0.0, -1.0);  // the line's unit normal
  double var_offset = 0.0;   // mm^2
  double var_angle = 0.0;    // rad^2
  Vec2 direction() const { return Vec2(-n.y(), n.x()); }
  // The variance of the line's position along n at the foot of p (mm^2).
  double across_var(const Vec2& p) const {
    const double u = (p - mean).dot(direction());
    return var_offset + u * u * var_angle;
  }
};
// The covariance of `line`, fitted to the points of moments m whose
// distances from it have variance sigma2 (infinite var_angle when they
// have no spread along it).
LineCov line_cov(const Line& line, const Moments& m, double sigma2);
// The variance of the points of moments m across `line`, from their
// residuals, pooled with a prior variance worth prior_dof degrees of
// freedom: (sum r^2 + prior_dof prior_var) / (N - 2 + prior_dof). With few
// points the residuals alone say little (two points have none).
double residual_variance(const Line& line, const Moments& m, double prior_var, double prior_dof);
// The covariance (mm^2) of the intersection x of two lines known to a and b.
// Infinite when they are parallel.
Eigen::Matrix2d intersection_cov(const LineCov& a, const LineCov& b, const Vec2& x);
// P(|e| > r) for e ~ N(0, cov) in the plane: the chance that a point
// located with covariance cov lies more than r from where it is read.
// Exact for any cov to about 1e-6 (a one-dimensional integral).
double prob_outside_circle(const Eigen::Matrix2d& cov, double r);

// Acute angle between the lines, 0..90 degrees.
double acute_angle_deg(const Line& a, const Line& b);

// Angle between two directions, 0..180 degrees (any lengths, not zero).
double angle_between_deg(const Vec2& u, const Vec2& v);

}  // namespace vts::tracker
