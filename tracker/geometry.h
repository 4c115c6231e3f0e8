#pragma once
// Lines in the laser plane, in normal form so that vertical walls need no
// special case, and their total least-squares fit.
#include <cmath>
#include <optional>
#include <span>

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

// Acute angle between the lines, 0..90 degrees.
double acute_angle_deg(const Line& a, const Line& b);

// Angle between two directions, 0..180 degrees (any lengths, not zero).
double angle_between_deg(const Vec2& u, const Vec2& v);

}  // namespace vts::tracker
