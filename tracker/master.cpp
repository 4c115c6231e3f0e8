#include "tracker/master.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>

namespace vts::tracker {

std::string_view to_string(Phase p) {
  switch (p) {
    case Phase::Move: return "move";
    case Phase::Search: return "search";
    case Phase::Approach: return "approach";
    case Phase::Weld: return "weld";
    case Phase::Done: return "done";
  }
  return "?";
}

namespace {
// The distance of r from the line through the origin along the unit vector u.
double off_line(const Vec3& r, const Vec3& u) { return (r - r.dot(u) * u).norm(); }

// A length in messages: to 0.1 mm.
std::string mm_text(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f", v);
  return buf;
}
// The failure of a seam whose joint data lie `off` mm from its plan.
std::string not_the_seam_planned(double off, double tolerance) {
  return "the joint tracked lies " + mm_text(off) + " mm from the planned seam, more than the " + mm_text(tolerance) +
         " mm the part may be displaced: not the seam planned";
}
}  // namespace

double weave_unit(const MasterParams::Weave& w, double t) {
  if (w.amplitude_mm <= 0.0 || w.frequency_hz <= 0.0) return 0.0;
  const double period = 1.0 / w.frequency_hz;
  const double d = std::clamp(w.dwell_s, 0.0, 0.5 * period);
  const double q = 0.25 * (period - 2.0 * d);  // a quarter of the moving time
  double tau = std::fmod(t, period);
  if (tau < 0.0) tau += period;
  if (q <= 0.0) return tau < 0.5 * period ? 1.0 : -1.0;
  if (tau < q) return tau / q;
  tau -= q;
  if (tau < d) return 1.0;
  tau -= d;
  if (tau < 2.0 * q) return 1.0 - tau / q;
  tau -= 2.0 * q;
  if (tau < d) return -1.0;
  tau -= d;
  return -1.0 + tau / q;
}

void SeamObject::reset(const Vec3& origin, const Vec3& direction_guess) {
  origin_ = origin;
  guess_ = direction_guess.normalized();
  points_.clear();
  arcs_.clear();
  sum_.setZero();
  sum_outer_.setZero();
  span_ = 0.0;
}

Vec3 SeamObject::direction() const {
  if (points_.size() < 2 || span_ < 2.0) return guess_;
  const double n = static_cast<double>(points_.size());
  const Vec3 mean = sum_ / n;
  const Eigen::Matrix3d cov = sum_outer_ / n - mean * mean.transpose();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
  Vec3 d = eig.eigenvectors().col(2).normalized();
  return d.dot(guess_) < 0.0 ? Vec3(-d) : d;
}

Vec3 SeamObject::centroid() const {
  return points_.empty() ? origin_ : Vec3(origin_ + sum_ / static_cast<double>(points_.size()));
}

double SeamObject::max_arc() const {
  if (points_.empty()) return 0.0;
  const Vec3 d = direction();
  double m = -std::numeric_limits<double>::infinity();
  // Points arrive in order along the seam: the last few hold the maximum.
  const std::size_t from = points_.size() > 16 ? points_.size() - 16 : 0;
  for (std::size_t i = from; i < points_.size(); ++i) m = std::max(m, (points_[i] - origin_).dot(d));
  return m;
}

Vec3 SeamObject::at(double s, double window_mm) const {
  const Vec3 d = direction();
  // Arcs stored at insertion are nearly sorted and nearly the current ones:
  // find the window with slack, then test exactly.
  constexpr double kSlackMm = 2.0;
  const auto first = std::partition_point(arcs_.begin(), arcs_.end(),
                                          [&](double a) { return a < s - window_mm - kSlackMm; });
  double sw = 0.0, st = 0.0, stt = 0.0;
  Vec3 sp = Vec3::Zero(), stp = Vec3::Zero();
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (auto it = first; it != arcs_.end() && *it <= s + window_mm + kSlackMm; ++it) {
    const Vec3& p = points_[static_cast<std::size_t>(it - arcs_.begin())];
    const double t = (p - origin_).dot(d) - s;
    if (std::abs(t) > window_mm) continue;
    sw += 1.0;
    st += t;
    stt += t * t;
    sp += p;
    stp += t * p;
    lo = std::min(lo, t);
    hi = std::max(hi, t);
  }
  // p(t) = a + b t by least squares; the seam at s is a.
  const double det = sw * stt - st * st;
  if (sw >= 3.0 && hi - lo >= 1.0 && det > 1e-9) return (stt * sp - st * stp) / det;
  if (points_.size() >= 2) {
    const Vec3 c = centroid();
    return c + (s - (c - origin_).dot(d)) * d;
  }
  return origin_ + s * d;
}

bool SeamObject::add(const Vec3& p, double window_mm, double gate_mm, int gate_after) {
  if (size() >= gate_after) {
    const Vec3 predicted = at(arc(p), window_mm);
    if ((p - predicted).norm() > gate_mm) return false;
  } else {
    // Too few points for a fit: the point must lie near the line from the
    // start point along the current direction, allowing for a direction off
    // by up to about 11 degrees.
    const Vec3 d = direction();
    const Vec3 r = p - origin_;
    if (off_line(r, d) > gate_mm + 0.2 * std::abs(r.dot(d))) return false;
  }
  const Vec3 q = p - origin_;  // sums relative to the origin, for precision
  sum_ += q;
  sum_outer_ += q * q.transpose();
  span_ = std::max(span_, (p - origin_).norm());
  points_.push_back(p);
  arcs_.push_back(arc(p));  // with the sums and the count including p
  // Keep the stored arcs sorted (points come nearly in order).
  for (std::size_t i = arcs_.size() - 1; i > 0 && arcs_[i] < arcs_[i - 1]; --i) {
    std::swap(arcs_[i], arcs_[i - 1]);
    std::swap(points_[i], points_[i - 1]);
  }
  return true;
}

void CurveSeamObject::reset(const Vec3& direction_guess, double first_arc) {
  guess_ = direction_guess.normalized();
  first_arc_ = first_arc;
  points_.clear();
  arcs_.clear();
}

Vec3 CurveSeamObject::at(double s, double window_mm, Vec3* tangent) const {
  if (points_.empty()) {
    if (tangent) *tangent = guess_;
    return Vec3::Zero();
  }
  const auto first = std::lower_bound(arcs_.begin(), arcs_.end(), s - window_mm);
  const auto last = std::upper_bound(first, arcs_.end(), s + window_mm);
  const std::size_t i0 = static_cast<std::size_t>(first - arcs_.begin());
  const std::size_t i1 = static_cast<std::size_t>(last - arcs_.begin());
  const std::size_t n = i1 - i0;
  if (n >= 2 && arcs_[i1 - 1] - arcs_[i0] >= 1.0) {
    // p(u) = a + b u (+ c u^2), u = arc - s, by least squares per coordinate.
    const int m = n >= 5 && arcs_[i1 - 1] - arcs_[i0] >= 2.0 ? 3 : 2;
    Eigen::Matrix3d a = Eigen::Matrix3d::Zero(), b = Eigen::Matrix3d::Zero();
    for (std::size_t i = i0; i < i1; ++i) {
      const double u = arcs_[i] - s;
      const Vec3 phi(1.0, u, u * u);
      a.topLeftCorner(m, m) += phi.head(m) * phi.head(m).transpose();
      b.topRows(m) += phi.head(m) * points_[i].transpose();
    }
    const Eigen::MatrixXd x = a.topLeftCorner(m, m).ldlt().solve(b.topRows(m));
    if (tangent) {
      const Vec3 d = x.row(1).transpose();
      *tangent = d.norm() > 1e-12 ? Vec3(d.normalized()) : guess_;
    }
    return x.row(0).transpose();
  }
  // Too few points near s: the nearest one.
  std::size_t best = 0;
  for (std::size_t i = 1; i < arcs_.size(); ++i)
    if (std::abs(arcs_[i] - s) < std::abs(arcs_[best] - s)) best = i;
  if (tangent) {
    const Vec3 d = points_.size() >= 2 ? Vec3(points_.back() - points_.front()) : guess_;
    *tangent = d.norm() > 1e-9 ? Vec3(d.normalized()) : guess_;
  }
  return points_[best];
}

double CurveSeamObject::arc_of(const Vec3& p, double window_mm) const {
  if (points_.empty()) return first_arc_;
  if (points_.size() < 3 || arcs_.back() - arcs_.front() < 2.0)
    return arcs_.front() + (p - points_.front()).dot(guess_);
  // The step from the last point projected onto the fit's tangent there.
  // (From the fit's end value instead, the arcs would drift: a quadratic
  // fitted over one side of a circle's point misses it along the tangent by
  // about window^3 / (120 R^2), 3 um a point for R = 50 mm, 0.6 % of the arc.)
  Vec3 t;
  at(arcs_.back(), window_mm, &t);
  return arcs_.back() + (p - points_.back()).dot(t);
}

bool CurveSeamObject::add(const Vec3& p, double window_mm, double gate_mm, int gate_after) {
  const double arc = arc_of(p, window_mm);
  if (size() >= gate_after) {
    if ((p - at(arc, window_mm)).norm() > gate_mm) return false;
  } else if (!points_.empty()) {
    const Vec3 r = p - points_.front();
    if (off_line(r, guess_) > gate_mm + 0.2 * std::abs(r.dot(guess_))) return false;
  }
  points_.push_back(p);
  arcs_.push_back(arc);
  for (std::size_t i = arcs_.size() - 1; i > 0 && arcs_[i] < arcs_[i - 1]; --i) {
    std::swap(arcs_[i], arcs_[i - 1]);
    std::swap(points_[i], points_[i - 1]);
  }
  return true;
}

double CurveSeamObject::crossing(const Vec3& q, const Vec3& n, double window_mm, double from_arc) const {
  const auto first = std::lower_bound(arcs_.begin(), arcs_.end(), from_arc);
  for (auto it = first; it != arcs_.end(); ++it) {
    if (it == arcs_.begin()) continue;
    const std::size_t i = static_cast<std::size_t>(it - arcs_.begin());
    const double d0 = (points_[i - 1] - q).dot(n), d1 = (points_[i] - q).dot(n);
    if (!(d0 < 0.0 && d1 >= 0.0)) continue;
    // Between the two points, then on the fit (Newton: d/ds of the signed
    // distance is the tangent's part along n).
    double s = arcs_[i - 1] + (arcs_[i] - arcs_[i - 1]) * (-d0 / (d1 - d0));
    for (int k = 0; k < 4; ++k) {
      Vec3 t;
      const double f = (at(s, window_mm, &t) - q).dot(n);
      const double df = t.dot(n);
      if (std::abs(df) < 0.1) break;
      s -= f / df;
    }
    return s;
  }
  return std::numeric_limits<double>::quiet_NaN();
}

Eigen::Matrix3d tool_rotation(const Vec3& direction, const Vec3& plate_normal, const Vec3& wall_normal) {
  const Vec3 x = direction.normalized();
  Vec3 z = -(plate_normal + wall_normal).normalized();
  z = (z - z.dot(x) * x).normalized();
  Eigen::Matrix3d r;
  r.col(0) = x;
  r.col(1) = z.cross(x);
  r.col(2) = z;
  return r;
}

Pose3 recalibrate(const Pose3& believed, const SeamPlan& seam, const Vec3& start, const Vec3& end,
                  const Vec3& measured_plate_normal, const Vec3& measured_wall_normal) {
  const Eigen::Matrix3d rb = believed.linear();
  const Vec3 d_b = rb * (seam.end_mm - seam.start_mm).normalized();
  const Vec3 d_m = (end - start).normalized();
  // Rotation taking the believed directions onto the measured ones (Kabsch);
  // the seam direction has the longest baseline and weighs most.
  Eigen::Matrix3d h = 2.0 * d_m * d_b.transpose();
  const Vec3 np_b = rb * seam.plate_normal, nw_b = rb * seam.wall_normal;
  if (measured_plate_normal.norm() > 0.5) h += measured_plate_normal.normalized() * np_b.transpose();
  if (measured_wall_normal.norm() > 0.5) h += measured_wall_normal.normalized() * nw_b.transpose();
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(h, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d fix = Eigen::Matrix3d::Identity();
  fix(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0.0 ? -1.0 : 1.0;
  const Eigen::Matrix3d r = svd.matrixU() * fix * svd.matrixV().transpose();
  Pose3 out = Pose3::Identity();
  out.linear() = r * rb;
  out.translation() = 0.5 * (start + end) - out.linear() * (0.5 * (seam.start_mm + seam.end_mm));
  return out;
}

namespace {

bool has(const std::vector<Event>& events, Event e) {
  return std::find(events.begin(), events.end(), e) != events.end();
}

// Unit normal of the surface spanned by the seam direction d and the in-surface
// direction u, signed like `like`; zero if u is missing.
Vec3 surface_normal(const Vec3& d, const Vec3& u, const Vec3& like) {
  if (u.norm() < 1e-9) return Vec3::Zero();
  Vec3 n = d.cross(u.normalized());
  if (n.norm() < 1e-6) return Vec3::Zero();
  n.normalize();
  return n.dot(like) < 0.0 ? Vec3(-n) : n;
}

}  // namespace

MasterResult Master::run(SensorInterface& sensor, const Pose3& world_from_workpiece,
                         const std::vector<SeamPlan>& seams,
                         const std::function<void(const MasterSample&)>& on_cycle) {
  const MasterParams& P = params_;
  MasterResult res;
  Pose3 believed = world_from_workpiece;
  bool recalibrated = false;
  const double dt = 1.0 / P.control_rate_hz;
  const double step = P.speed_mm_s * dt;
  std::int64_t cycle = 0;
  Pose3 tool = Pose3::Identity();
  double now = 0.0;

  // The weave, added to the tool's position while welding (weave_t: the
  // weld's own clock).
  double weave_t = 0.0;
  auto tick = [&](int seam, Phase phase, double s) {
    ++cycle;
    now = static_cast<double>(cycle) * dt;
    Pose3 commanded = tool;
    Vec3 weave = Vec3::Zero();
    if (phase == Phase::Weld && P.weave.amplitude_mm > 0.0) {
      weave_t += dt;
      weave = P.weave.amplitude_mm * weave_unit(P.weave, weave_t) * tool.linear().col(1);
      commanded.translation() += weave;
    }
    std::vector<Event> events = sensor.advance(now, commanded);
    MasterSample smp;
    smp.time_s = now;
    smp.seam = seam;
    smp.phase = phase;
    smp.sensor = sensor.state();
    smp.world_from_tool = commanded;
    smp.s_mm = s;
    smp.weave_mm = weave;
    res.samples.push_back(smp);
    if (on_cycle) on_cycle(smp);
    return events;
  };
  // To `target`: at once, or at the move speed and then settled. The
  // first move starts there (the robot is where the program begins).
  bool first_move = true;
  auto move_to = [&](int seam, const Pose3& target) {
    if (first_move) tool = target;
    first_move = false;
    if (P.move_speed_mm_s <= 0.0) {
      tool = target;
      tick(seam, Phase::Move, 0.0);
      return;
    }
    const Pose3 from = tool;
    const Eigen::Quaterniond q0(from.linear()), q1(target.linear());
    const double dist = (target.translation() - from.translation()).norm();
    const double turn = q0.angularDistance(q1) * 180.0 / std::numbers::pi;
    // A smooth start and stop, as a controller's motion planner ramps a
    // move: the fraction 3 u^2 - 2 u^3 of the way at u of the duration,
    // whose peak speed, 1.5 times the mean, is the move speed.
    const double duration = 1.5 * std::max(dist / P.move_speed_mm_s, turn / MasterParams::kMaxTurnDegS);
    const int n = std::max(1, static_cast<int>(std::ceil(duration / dt - 1e-9)));
    for (int i = 1; i <= n; ++i) {
      const double u = static_cast<double>(i) / n;
      const double f = u * u * (3.0 - 2.0 * u);
      tool = interpolate(from, target, f);
      tick(seam, Phase::Move, 0.0);
    }
    tool = target;
    const int settle = static_cast<int>(std::ceil(P.settle_s / dt - 1e-9));
    for (int i = 0; i < settle; ++i) tick(seam, Phase::Move, 0.0);
  };

  // A curved seam (SeamPlan::path; see the class comment).
  auto weld_path = [&](int k, const SeamPlan& plan, SeamRun& run) {
    const std::size_t n = plan.path.size();
    std::vector<Vec3> pt(n), pn(n), wn(n);
    std::vector<double> arc(n, 0.0);
    for (std::size_t i = 0; i < n; ++i) {
      pt[i] = believed * plan.path[i].point;
      pn[i] = believed.linear() * plan.path[i].plate_normal;
      wn[i] = believed.linear() * plan.path[i].wall_normal;
      if (i > 0) arc[i] = arc[i - 1] + (pt[i] - pt[i - 1]).norm();
    }
    struct PlanAt {
      Vec3 p, t, np, nw;
    };
    // The plan at arc a (clamped to the path): linear between its points.
    auto plan_at = [&](double a) {
      const auto it = std::upper_bound(arc.begin(), arc.end(), a);
      const std::size_t i = std::clamp<std::size_t>(static_cast<std::size_t>(it - arc.begin()), 1, n - 1);
      const double l = arc[i] - arc[i - 1];
      const double f = l > 0.0 ? std::clamp((a - arc[i - 1]) / l, 0.0, 1.0) : 0.0;
      PlanAt r;
      r.p = pt[i - 1] + f * (pt[i] - pt[i - 1]);
      r.t = (pt[i] - pt[i - 1]).normalized();
      r.np = ((1.0 - f) * pn[i - 1] + f * pn[i]).normalized();
      r.nw = ((1.0 - f) * wn[i - 1] + f * wn[i]).normalized();
      return r;
    };
    // The arc of the plan's point nearest to p, the path extended along
    // its end tangents (arcs below 0 or beyond its end), and the distance.
    auto plan_nearest = [&](const Vec3& p) {
      constexpr double kInf = std::numeric_limits<double>::infinity();
      double best = kInf, a = 0.0;
      for (std::size_t i = 1; i < n; ++i) {
        const Vec3 ab = pt[i] - pt[i - 1];
        const double l2 = ab.squaredNorm();
        const double f = l2 > 0.0 ? std::clamp((p - pt[i - 1]).dot(ab) / l2, i == 1 ? -kInf : 0.0,
                                               i + 1 == n ? kInf : 1.0)
                                  : 0.0;
        const double d = (p - pt[i - 1] - f * ab).squaredNorm();
        if (d < best) {
          best = d;
          a = arc[i - 1] + f * (arc[i] - arc[i - 1]);
        }
      }
      return std::pair{a, std::sqrt(best)};
    };
    auto plan_arc_of = [&](const Vec3& p) { return plan_nearest(p).first; };
    auto pose_of = [](const PlanAt& x, const Vec3& tangent, const Vec3& position) {
      Pose3 pose = Pose3::Identity();
      pose.linear() = tool_rotation(tangent, x.np, x.nw);
      pose.translation() = position;
      return pose;
    };
    const double a_from = std::clamp(plan.weld_from_mm, 0.0, arc.back());
    const double a_end = arc.back();
    const PlanAt xs = plan_at(a_from), xe = plan_at(a_end);
    // The tool along the plan from arc `from` to `to`, a step a cycle (a weld
    // cycle's s counted from `from`), `after` called with each cycle's
    // events; stops early when it returns false. Returns the arc reached.
    auto along_plan = [&](double from, double to, Phase phase, const auto& after) {
      double a = from;
      while (a < to - 1e-9) {
        a = std::min(a + step, to);
        const PlanAt x = plan_at(a);
        tool = pose_of(x, x.t, x.p);
        if (!after(tick(k, phase, phase == Phase::Weld ? a - from : 0.0))) break;
      }
      return a;
    };
    auto go_on = [](const std::vector<Event>&) { return true; };

    if (P.open_loop) {
      // The same moves as with the sensor: to the lead-in, along it, then
      // the weld along the plan.
      const PlanAt x0 = plan_at(0.0);
      move_to(k, pose_of(x0, x0.t, x0.p));
      along_plan(0.0, a_from, Phase::Approach, go_on);
      run.weld_start = tool.translation();
      weave_t = 0.0;
      run.welded_mm = along_plan(a_from, a_end, Phase::Weld, go_on) - a_from;
      run.weld_end = tool.translation();
      run.start_found = run.end_found = true;
      run.start_point = xs.p;
      run.end_point = xe.p;
      return;
    }

    const PlanAt x0 = plan_at(0.0);
    move_to(k, pose_of(x0, x0.t, x0.p));
    if (!sensor.laser_on()) {
      run.failure = "the laser did not come on: " + sensor.error();
      return;
    }
    sensor.start_tracking();
    const double w = P.fit_window_mm;
    const double tolerance = P.plan_tolerance_mm > 0.0 ? P.plan_tolerance_mm : P.search_margin_mm;
    CurveSeamObject obj;
    obj.reset(x0.t);
    std::int64_t last_index = -1;
    bool stop = false;
    std::vector<Vec3> rejected;  // joint data rejected in a row
    auto poll = [&] {
      const auto j = sensor.latest_joint(now);
      if (!j || j->profile_index == last_index || stop) return;
      last_index = j->profile_index;
      const Vec3& p = j->track_point_world;
      const double off = plan_nearest(p).second;
      if (off > tolerance) {
        run.failure = not_the_seam_planned(off, tolerance);
        stop = true;
        sensor.laser_off();
        return;
      }
      // The first point: the guess is the plan's direction there (the
      // sensor measures ahead of the torch, where the seam has turned).
      if (obj.size() == 0) obj.reset(plan_at(plan_arc_of(p)).t);
      if (obj.add(p, w, P.gate_mm, P.gate_after)) {
        rejected.clear();
        ++run.points;
        run.track_points.push_back(p);
        if (j->gap_mm > run.max_gap_mm) run.max_gap_mm = j->gap_mm;  // false for NaN
        return;
      }
      ++run.rejected_points;
      rejected.push_back(p);
      if (static_cast<int>(rejected.size()) < P.refit_after_rejections) return;
      // As many points in a row off the seam object, each near the last:
      // the seam object went wrong, not the sensor. Start it again from
      // them, its arcs continuing the old ones.
      for (std::size_t i = 1; i < rejected.size(); ++i)
        if ((rejected[i] - rejected[i - 1]).norm() > P.gate_mm + 4.0 * step) {
          rejected.erase(rejected.begin(), rejected.begin() + static_cast<std::ptrdiff_t>(i));
          return;
        }
      const double a = obj.arc_of(rejected.front(), w);
      obj.reset((rejected.back() - rejected.front()).normalized(), a);
      constexpr double kNoGate = std::numeric_limits<double>::infinity();
      for (const Vec3& q : rejected) obj.add(q, w, kNoGate, P.gate_after);
      run.track_points.insert(run.track_points.end(), rejected.begin(), rejected.end());
      run.points += static_cast<int>(rejected.size());
      run.rejected_points -= static_cast<int>(rejected.size());
      ++run.refits;
      rejected.clear();
    };
    auto handle = [&](const std::vector<Event>& ev) {
      if (stop) return;
      if (has(ev, Event::SeamLost)) {
        run.lost = true;
      } else if (has(ev, Event::StreamEnded)) {
        run.failure = "the sensor stopped while tracking: " + sensor.error();
      } else {
        return;
      }
      stop = true;
      sensor.laser_off();
    };

    // Along the plan to the weld's start while the sensor measures ahead.
    along_plan(0.0, a_from, Phase::Approach, [&](const std::vector<Event>& ev) {
      poll();
      handle(ev);
      return run.failure.empty() && !stop;
    });
    if (!run.failure.empty() || stop) {
      if (run.failure.empty()) run.failure = "the sensor lost the seam before the weld's start";
      run.lost = false;
      return;
    }
    const double s0 = obj.crossing(xs.p, xs.t, w, -std::numeric_limits<double>::infinity());
    if (std::isnan(s0)) {
      run.failure = "the measured seam does not reach the plane of the planned start";
      return;
    }
    run.start_found = true;
    Vec3 t0;
    run.start_point = obj.at(s0, w, &t0);
    // To the measured start.
    for (int c = 0; run.failure.empty(); ++c) {
      const Vec3 to = run.start_point - tool.translation();
      tool.linear() = tool_rotation(t0, xs.np, xs.nw);
      const bool there = to.norm() <= step;
      tool.translation() = there ? run.start_point : Vec3(tool.translation() + step * to.normalized());
      const std::vector<Event> ev = tick(k, Phase::Approach, 0.0);
      poll();
      handle(ev);
      if (there) break;
      if (c > 10000) run.failure = "the approach to the start point did not converge";
    }

    // Weld along the measured seam to the plane of the planned end.
    run.weld_start = tool.translation();
    weave_t = 0.0;
    double s = s0, s_end = std::numeric_limits<double>::quiet_NaN();
    const double length = a_end - a_from;
    while (run.failure.empty()) {
      if (std::isnan(s_end)) s_end = obj.crossing(xe.p, xe.t, w, s);
      const double s_stop = !std::isnan(s_end) ? s_end : stop ? obj.max_arc() : std::numeric_limits<double>::infinity();
      if (s >= s_stop - 1e-9) break;
      const double s_next = std::min(s + step, s_stop);
      if (s_next > obj.max_arc() + 1e-9) {
        run.failure = "the torch caught up with the sensor data at s = " + mm_text(s - s0) + " mm";
        break;
      }
      if (s - s0 > 2.0 * length + 50.0) {
        run.failure = "no end of seam within twice the planned length";
        break;
      }
      s = s_next;
      Vec3 tangent;
      const Vec3 p = obj.at(s, w, &tangent);
      tool = pose_of(plan_at(plan_arc_of(p)), tangent, p);
      const std::vector<Event> ev = tick(k, Phase::Weld, s - s0);
      poll();
      handle(ev);
    }
    run.end_found = run.failure.empty() && !std::isnan(s_end) && s >= s_end - 1e-9;
    if (run.end_found) {
      run.end_point = obj.at(s_end, w);
      run.lost = false;
    }
    run.weld_end = tool.translation();
    run.welded_mm = s - s0;
    run.line_point = run.start_point;
    run.line_direction = t0;

    if (P.recalibrate && run.end_found && run.failure.empty() && !run.track_points.empty()) {
      // The mean offset of the joint points from the plan.
      Vec3 shift = Vec3::Zero();
      for (const Vec3& q : run.track_points) shift += q - plan_at(plan_arc_of(q)).p;
      believed.pretranslate(shift / static_cast<double>(run.track_points.size()));
      recalibrated = true;
    }
  };

  for (int k = 0; k < static_cast<int>(seams.size()); ++k) {
    res.world_from_workpiece.push_back(believed);
    SeamRun run;
    const SeamPlan& plan = seams[k];
    if (!plan.path.empty()) {
      weld_path(k, plan, run);
      if (sensor.state() != SensorState::Idle) sensor.laser_off();
      res.seams.push_back(run);
      continue;
    }
    const Vec3 s_plan = believed * plan.start_mm, e_plan = believed * plan.end_mm;
    const Vec3 d_plan = (e_plan - s_plan).normalized();
    const double length = (e_plan - s_plan).norm();
    const Vec3 np = believed.linear() * plan.plate_normal, nw = believed.linear() * plan.wall_normal;
    // After re-calibration the start is known to well under a profile step:
    // put it halfway between two profiles' laser planes, where the middle
    // of the bracketing planes (the sensor's estimate) hits it best.
    const double margin =
        recalibrated ? P.search_margin_recalibrated_mm + 0.5 * step : P.search_margin_mm;

    if (P.open_loop) {
      // No sensor: weld the plan.
      Pose3 start = Pose3::Identity();
      start.linear() = tool_rotation(d_plan, np, nw);
      start.translation() = s_plan;
      move_to(k, start);
      run.weld_start = tool.translation();
      weave_t = 0.0;
      double s = 0.0;
      while (s < length - 1e-9) {
        s = std::min(s + step, length);
        tool.translation() = s_plan + s * d_plan;
        tick(k, Phase::Weld, s);
      }
      run.weld_end = tool.translation();
      run.welded_mm = s;
      run.start_found = run.end_found = true;
      run.start_point = s_plan;
      run.end_point = e_plan;
      res.seams.push_back(run);
      continue;
    }

    // Move to the search pose: the laser plane `margin` before the planned start.
    Pose3 search = Pose3::Identity();
    search.linear() = tool_rotation(d_plan, np, nw);
    Vec3 begin = s_plan - (margin + P.lookahead_mm) * d_plan;
    search.translation() = begin;
    move_to(k, search);

    auto finish = [&] {
      if (sensor.state() != SensorState::Idle) sensor.laser_off();
      res.seams.push_back(run);
    };
    if (!sensor.laser_on()) {
      run.failure = "the laser did not come on: " + sensor.error();
      finish();
      continue;
    }

    // Search along the planned seam.
    bool found = false;
    for (int attempt = 0; attempt <= P.max_search_retries && !found && run.failure.empty(); ++attempt) {
      sensor.search_start();
      double travelled = 0.0;
      const double limit = 2.0 * margin + P.search_extra_mm;
      while (true) {
        tool.translation() += step * d_plan;
        travelled += step;
        run.search_mm += step;
        const std::vector<Event> ev = tick(k, Phase::Search, 0.0);
        if (has(ev, Event::StartFound)) {
          found = true;
          break;
        }
        if (has(ev, Event::StreamEnded)) {
          run.failure = "the sensor stopped during the search: " + sensor.error();
          break;
        }
        if (has(ev, Event::StartBehind)) {
          // The joint was there from the first profile: back off and search again.
          begin -= P.search_margin_mm * d_plan;
          Pose3 back = tool;
          back.translation() = begin;
          move_to(k, back);
          if (attempt == P.max_search_retries) run.failure = "the start point lies behind every search";
          break;
        }
        if (travelled > limit) {
          run.failure = "no start point within " + mm_text(limit) + " mm of search";
          break;
        }
      }
    }
    if (!found) {
      finish();
      continue;
    }
    run.start_found = true;
    run.start_point = *sensor.start_point();
    sensor.start_tracking();

    SeamObject obj;
    obj.reset(run.start_point, d_plan);
    std::int64_t last_index = -1;
    Vec3 plate_dir = Vec3::Zero(), wall_dir = Vec3::Zero();
    std::optional<Vec3> stop_point;
    Vec3 last_accepted = run.start_point;
    bool end_requested = false;

    std::vector<Vec3> rejected;  // joint data rejected in a row
    const double tolerance = P.plan_tolerance_mm > 0.0 ? P.plan_tolerance_mm : P.search_margin_mm;
    auto poll = [&] {
      const auto j = sensor.latest_joint(now);
      if (!j || j->profile_index == last_index || stop_point) return;
      last_index = j->profile_index;
      {
        const double off = off_line(j->track_point_world - s_plan, d_plan);
        if (off > tolerance) {
          run.failure = not_the_seam_planned(off, tolerance);
          stop_point = last_accepted;
          sensor.laser_off();
          return;
        }
      }
      if (!obj.add(j->track_point_world, P.fit_window_mm, P.gate_mm, P.gate_after)) {
        ++run.rejected_points;
        rejected.push_back(j->track_point_world);
        if (static_cast<int>(rejected.size()) < P.refit_after_rejections) return;
        // As many points in a row off the seam object, and consistent with
        // one another: the seam object went wrong (a false point early on),
        // not the sensor. Start it again from the rejected points.
        const Vec3 span = rejected.back() - rejected.front();
        bool consistent = span.norm() > 1e-6;
        for (const Vec3& p : rejected) {
          const Vec3 r = p - rejected.front();
          consistent = consistent && off_line(r, span.normalized()) <= P.gate_mm;
        }
        if (!consistent) {
          rejected.erase(rejected.begin());
          return;
        }
        // Its origin: the start point moved onto the rejected points' line.
        const Vec3 u = span.normalized().dot(obj.direction()) < 0.0 ? Vec3(-span.normalized()) : span.normalized();
        const Vec3 c = rejected.front();
        obj.reset(c + (run.start_point - c).dot(u) * u, u);
        constexpr double kNoGate = std::numeric_limits<double>::infinity();
        for (const Vec3& p : rejected) obj.add(p, P.fit_window_mm, kNoGate, P.gate_after);
        run.track_points.insert(run.track_points.end(), rejected.begin(), rejected.end() - 1);
        run.points += static_cast<int>(rejected.size()) - 1;
        run.rejected_points -= static_cast<int>(rejected.size());
        ++run.refits;
        rejected.clear();
      } else {
        rejected.clear();
      }
      ++run.points;
      run.track_points.push_back(j->track_point_world);
      if (j->gap_mm > run.max_gap_mm) run.max_gap_mm = j->gap_mm;  // false for NaN
      last_accepted = j->track_point_world;
      // The two surfaces' directions from the root (break points 0 and 4:
      // the two plates' outer ends), for re-calibration.
      for (int b : {0, 4}) {
        if (!j->break_points[b]) continue;
        const Vec2& yz = *j->break_points[b];
        const Vec3 u = j->world_from_sensor * Vec3(0.0, yz.x(), yz.y()) - j->track_point_world;
        if (u.norm() < 3.0) continue;
        const Vec3 un = u.normalized();
        if (std::abs(un.dot(nw)) > std::abs(un.dot(np)))
          plate_dir += un.dot(nw) < 0.0 ? Vec3(-un) : un;
        else
          wall_dir += un.dot(np) < 0.0 ? Vec3(-un) : un;
      }
      if (!end_requested && sensor.state() == SensorState::Tracking &&
          obj.arc(j->track_point_world) >= length - P.end_margin_mm) {
        sensor.look_for_end();
        end_requested = true;
      }
    };
    auto handle = [&](const std::vector<Event>& ev) {
      if (stop_point) return;
      if (has(ev, Event::EndFound)) {
        run.end_found = true;
        run.end_point = *sensor.end_point();
        stop_point = run.end_point;
      } else if (has(ev, Event::SeamLost)) {
        run.lost = true;
        stop_point = last_accepted;
      } else if (has(ev, Event::StreamEnded)) {
        run.failure = "the sensor stopped while tracking: " + sensor.error();
        stop_point = last_accepted;
      } else {
        return;
      }
      sensor.laser_off();
    };
    poll();
    // The torch turns to the measured seam once the seam object is long
    // enough for its direction to be better than the plan's.
    auto travel_direction = [&] { return obj.max_arc() >= P.direction_span_mm ? obj.direction() : d_plan; };

    // Approach the start while the sensor fills the buffer ahead.
    const int approach_limit = static_cast<int>(4.0 * (P.lookahead_mm + 2.0 * margin + 50.0) / step) + 100;
    for (int c = 0;; ++c) {
      if (c > approach_limit) {
        run.failure = "the approach to the start point did not converge";
        break;
      }
      const Vec3 w0 = obj.at(0.0, P.fit_window_mm);
      const Vec3 to = w0 - tool.translation();
      tool.linear() = tool_rotation(travel_direction(), np, nw);
      if (to.norm() <= step) {
        tool.translation() = w0;
      } else {
        tool.translation() += step * to.normalized();
      }
      const std::vector<Event> ev = tick(k, Phase::Approach, 0.0);
      poll();
      handle(ev);
      if (to.norm() <= step) break;
    }

    // Weld along the seam object.
    run.weld_start = tool.translation();
    weave_t = 0.0;
    double s = 0.0;
    while (run.failure.empty()) {
      const double s_stop = stop_point ? obj.arc(*stop_point) : std::numeric_limits<double>::infinity();
      if (stop_point && s >= s_stop - 1e-9) break;
      const double s_next = std::min(s + step, s_stop);
      if (!stop_point && s_next > obj.max_arc()) {
        run.failure = "the torch caught up with the sensor data at s = " + mm_text(s) + " mm";
        break;
      }
      if (s > 2.0 * length + 50.0) {
        run.failure = "no end of seam within twice the planned length";
        break;
      }
      s = s_next;
      tool.translation() = obj.at(s, P.fit_window_mm);
      tool.linear() = tool_rotation(travel_direction(), np, nw);
      const std::vector<Event> ev = tick(k, Phase::Weld, s);
      poll();
      handle(ev);
    }
    run.weld_end = tool.translation();
    run.welded_mm = s;
    run.line_direction = obj.direction();
    run.line_point = obj.centroid();
    finish();

    if (P.recalibrate && run.start_found && run.end_found && run.failure.empty()) {
      const Vec3 d = obj.direction();
      auto on_line = [&](const Vec3& p) { return run.line_point + (p - run.line_point).dot(d) * d; };
      believed = recalibrate(believed, plan, on_line(run.start_point), on_line(run.end_point),
                             surface_normal(d, plate_dir, np), surface_normal(d, wall_dir, nw));
      recalibrated = true;
    }
  }
  tick(-1, Phase::Done, 0.0);
  return res;
}

}  // namespace vts::tracker
