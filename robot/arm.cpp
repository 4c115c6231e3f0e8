#include "robot/arm.h"

#include <cmath>
#include <random>
#include <sstream>

namespace vts::robot {
namespace {

constexpr double kDeg = M_PI / 180.0;

Axis axis(double a, double alpha_deg, double d, double offset_deg, double lo_deg, double hi_deg, double vel_deg_s,
          double acc_deg_s2) {
  Axis x;
  x.a_mm = a;
  x.alpha_rad = alpha_deg * kDeg;
  x.d_mm = d;
  x.offset_rad = offset_deg * kDeg;
  x.min_rad = lo_deg * kDeg;
  x.max_rad = hi_deg * kDeg;
  x.max_vel_rad_s = vel_deg_s * kDeg;
  x.max_acc_rad_s2 = acc_deg_s2 * kDeg;
  return x;
}

Eigen::Matrix4d dh(const Axis& x, double q) {
  const double t = q + x.offset_rad, ct = std::cos(t), st = std::sin(t);
  const double ca = std::cos(x.alpha_rad), sa = std::sin(x.alpha_rad);
  Eigen::Matrix4d m;
  m << ct, -st * ca, st * sa, x.a_mm * ct,  //
      st, ct * ca, -ct * sa, x.a_mm * st,   //
      0.0, sa, ca, x.d_mm,                  //
      0.0, 0.0, 0.0, 1.0;
  return m;
}

Eigen::Matrix4d chain(const ArmModel& m, const Joints& q, int n) {
  Eigen::Matrix4d t = Eigen::Matrix4d::Identity();
  for (int i = 0; i < n; ++i) t = t * dh(m.axes[static_cast<std::size_t>(i)], q[i]);
  return t;
}

double wrap(double a) { return std::remainder(a, 2.0 * M_PI); }

bool near_deg(double rad, double deg) { return std::abs(rad - deg * kDeg) < 1e-9; }

}  // namespace

std::vector<std::string> arm_preset_names() { return {"irb2400", "kr16"}; }

double limited_value(const ArmModel& m, const Joints& q, int i) {
  return i == 2 && m.axis3_coupled ? q[1] + q[2] : q[i];
}

std::optional<ArmModel> arm_preset(std::string_view name) {
  ArmModel m;
  if (name == "irb2400") {
    m.name = "irb2400";
    m.source =
        "ABB IRB 2400/16 product specification: axis 2 615 mm above the base and 100 mm ahead of axis 1, upper arm "
        "705 mm, forearm offset 135 mm and length 755 mm, wrist to flange 85 mm; axis ranges and speeds from the "
        "same specification; accelerations assumed";
    m.axes = {axis(100, -90, 615, 0, -180, 180, 150, 600),   //
              axis(705, 0, 0, -90, -100, 110, 150, 600),     //
              axis(135, -90, 0, 0, -60, 65, 150, 600),       //
              axis(0, 90, 755, 0, -200, 200, 360, 1800),     //
              axis(0, -90, 0, 0, -120, 120, 360, 1800),      //
              axis(0, 0, 85, 0, -400, 400, 450, 2400)};
    m.axis3_coupled = true;
    return m;
  }
  if (name == "kr16") {
    m.name = "kr16";
    m.source =
        "KUKA KR 16-2 specification: axis 2 675 mm above the base and 260 mm ahead of axis 1, upper arm 680 mm, "
        "forearm offset 35 mm and length 670 mm, wrist to flange 115 mm; axis ranges and speeds from the same "
        "specification, in this model's axis directions; accelerations assumed";
    m.axes = {axis(260, -90, 675, 0, -185, 185, 156, 600),  //
              axis(680, 0, 0, -90, -35, 155, 156, 600),     //
              axis(35, -90, 0, 0, -154, 130, 156, 600),     //
              axis(0, 90, 670, 0, -350, 350, 330, 1800),    //
              axis(0, -90, 0, 0, -130, 130, 330, 1800),     //
              axis(0, 0, 115, 0, -350, 350, 615, 2400)};
    return m;
  }
  return std::nullopt;
}

std::string validate(const ArmModel& m) {
  const auto& x = m.axes;
  const double alpha[6] = {-90, 0, -90, 90, -90, 0};
  for (int i = 0; i < 6; ++i) {
    const Axis& a = x[static_cast<std::size_t>(i)];
    const std::string ax = "axis " + std::to_string(i + 1);
    if (!near_deg(a.alpha_rad, alpha[i])) return ax + ": alpha must be " + std::to_string(int(alpha[i])) + " degrees";
    if (!(a.min_rad < a.max_rad)) return ax + ": the lower limit must be below the upper";
    if (!(a.max_vel_rad_s > 0.0) || !(a.max_acc_rad_s2 > 0.0)) return ax + ": velocity and acceleration limits must be > 0";
  }
  if (x[3].a_mm != 0.0 || x[4].a_mm != 0.0 || x[5].a_mm != 0.0 || x[1].d_mm != 0.0 || x[2].d_mm != 0.0 ||
      x[4].d_mm != 0.0)
    return "not a spherical wrist: a4, a5, a6, d2, d3 and d5 must be 0";
  if (!(x[1].a_mm > 0.0) || !(x[3].d_mm > 0.0)) return "a2 and d4 must be > 0";
  return {};
}

Pose3 forward(const ArmModel& m, const Joints& q) { return Pose3(chain(m, q, 6)); }

std::array<Pose3, 7> frames(const ArmModel& m, const Joints& q) {
  std::array<Pose3, 7> f;
  Eigen::Matrix4d t = Eigen::Matrix4d::Identity();
  f[0] = Pose3(t);
  for (int i = 0; i < 6; ++i) {
    t = t * dh(m.axes[static_cast<std::size_t>(i)], q[i]);
    f[static_cast<std::size_t>(i) + 1] = Pose3(t);
  }
  return f;
}

Eigen::Vector3d wrist_centre(const ArmModel& m, const Joints& q) { return chain(m, q, 4).block<3, 1>(0, 3); }

namespace {

// The planar geometry of axes 2-3 for a wrist centre w and base angle q1.
struct Plane {
  double R, S;       // wrist centre from axis 2: along the arm's reach, up
  double L3, gamma;  // forearm to the wrist centre: length, angle of (a3, d4)
};

Plane plane(const ArmModel& m, const Eigen::Vector3d& w, double q1) {
  Plane p;
  const double reach = std::cos(q1) * w.x() + std::sin(q1) * w.y();
  p.R = reach - m.axes[0].a_mm;
  p.S = w.z() - m.axes[0].d_mm;
  p.L3 = std::hypot(m.axes[2].a_mm, m.axes[3].d_mm);
  p.gamma = std::atan2(m.axes[3].d_mm, m.axes[2].a_mm);
  return p;
}

// q4..q6 from the wrist's rotation R36 = Rz(q4) Ry(-q5) Rz(q6) (alpha4 = 90,
// alpha5 = -90), the branch q5 >= 0 or (flip) q5 <= 0.
void wrist(const Eigen::Matrix3d& r, bool flip, double& q4, double& q5, double& q6) {
  const double s5 = std::hypot(r(0, 2), r(1, 2));
  q5 = std::atan2(s5, r(2, 2));
  if (s5 < 1e-12) {  // singular: only q4 + q6 (or q6 - q4) is fixed
    q4 = 0.0;
    q6 = std::atan2(r(1, 0), r(0, 0));
    if (r(2, 2) < 0.0) q6 = std::atan2(r(1, 0), -r(0, 0));  // q5 = 180: R = Rz(q4) diag(-1, 1, -1) Rz(q6)
  } else {
    q4 = std::atan2(-r(1, 2), -r(0, 2));
    q6 = std::atan2(-r(2, 1), r(2, 0));
  }
  if (flip) {
    q4 = wrap(q4 + M_PI);
    q5 = -q5;
    q6 = wrap(q6 + M_PI);
  }
}

}  // namespace

Config config_of(const ArmModel& m, const Joints& q) {
  Config c;
  const Eigen::Vector3d w = wrist_centre(m, q);
  c.front = std::cos(q[0]) * w.x() + std::sin(q[0]) * w.y() >= 0.0;
  const double psi = q[2] + std::atan2(m.axes[3].d_mm, m.axes[2].a_mm);
  c.elbow_up = std::sin(psi) >= 0.0;
  c.flip = q[4] < 0.0;
  return c;
}

std::string to_string(const Config& c) {
  return std::string(c.front ? "front" : "back") + "/" + (c.elbow_up ? "up" : "down") + "/" +
         (c.flip ? "flip" : "noflip");
}

Singularity singularity(const ArmModel& m, const Joints& q) {
  Singularity s;
  s.wrist = std::abs(std::sin(q[4]));
  s.elbow = std::abs(std::sin(q[2] + std::atan2(m.axes[3].d_mm, m.axes[2].a_mm)));
  const Eigen::Vector3d w = wrist_centre(m, q);
  s.shoulder_mm = std::hypot(w.x(), w.y());
  return s;
}

namespace {

// The solution of one branch (q1 facing the wrist centre or away, elbow up
// or down, wrist flipped or not); false when the wrist centre is out of reach.
bool solve_branch(const ArmModel& m, const Pose3& t, bool front, bool up, bool flip, Solution& s) {
  const Eigen::Vector3d w = t.translation() - m.axes[5].d_mm * t.linear().col(2);
  const double q1 = wrap(front ? std::atan2(w.y(), w.x()) : std::atan2(w.y(), w.x()) + M_PI);
  const Plane p = plane(m, w, q1);
  const double a2 = m.axes[1].a_mm;
  const double D = (p.R * p.R + p.S * p.S - a2 * a2 - p.L3 * p.L3) / (2.0 * a2 * p.L3);
  if (std::abs(D) > 1.0 + 1e-12) return false;
  const double psi0 = std::acos(std::clamp(D, -1.0, 1.0));
  const double psi = up ? psi0 : -psi0;  // q3 + gamma
  // The upper arm's angle from vertical: the direction to the wrist centre
  // less the forearm's share of it.
  const double q2 = std::atan2(p.R, p.S) - std::atan2(p.L3 * std::sin(psi), a2 + p.L3 * std::cos(psi));
  const double q3 = psi - p.gamma;
  Joints q;
  q << q1, wrap(q2), wrap(q3), 0.0, 0.0, 0.0;
  const Eigen::Matrix3d r03 = chain(m, q, 3).block<3, 3>(0, 0);
  const Eigen::Matrix3d r36 = r03.transpose() * t.linear();
  double q4, q5, q6;
  wrist(r36, flip, q4, q5, q6);
  s.q = q;
  s.q[3] = q4;
  s.q[4] = q5;
  s.q[5] = q6;
  s.config = config_of(m, s.q);
  return true;
}

}  // namespace

std::vector<Solution> inverse_all(const ArmModel& m, const Pose3& t) {
  std::vector<Solution> out;
  for (bool front : {true, false})
    for (bool up : {true, false})
      for (bool flip : {false, true}) {
        Solution s;
        if (solve_branch(m, t, front, up, flip, s)) out.push_back(s);
      }
  return out;
}

std::string_view to_string(IkStatus s) {
  switch (s) {
    case IkStatus::Ok: return "ok";
    case IkStatus::Unreachable: return "unreachable";
    case IkStatus::JointLimit: return "joint-limit";
    case IkStatus::Singular: return "singular";
  }
  return "?";
}

IkResult inverse(const ArmModel& m, const Pose3& t, const Config& config, const Joints& near, const Limits& limits,
                 bool continuous) {
  IkResult r;
  // The branch of the configuration is the one that has it, but at its
  // boundaries (singular poses) the flags are told by the joints: then
  // search all.
  Solution own;
  const Solution* pick = nullptr;
  std::vector<Solution> all;
  if (solve_branch(m, t, config.front, config.elbow_up, config.flip, own) && own.config == config) {
    pick = &own;
  } else {
    all = inverse_all(m, t);
    for (const Solution& s : all)
      if (s.config == config) pick = &s;
  }
  if (!pick) {
    r.status = IkStatus::Unreachable;
    std::ostringstream o;
    o << "the flange pose at (" << t.translation().x() << ", " << t.translation().y() << ", " << t.translation().z()
      << ") mm is out of reach in configuration " << to_string(config);
    r.message = o.str();
    return r;
  }
  r.q = pick->q;
  // Each angle as the representative nearest `near`, within the limits if one is.
  for (int i = 0; i < 6; ++i) {
    const Axis& a = m.axes[static_cast<std::size_t>(i)];
    double best = r.q[i], best_d = 1e300;
    const double shift = limited_value(m, r.q, i) - r.q[i];  // q2 for a coupled axis 3
    for (int k = -2; k <= 2; ++k) {
      const double v = r.q[i] + 2.0 * M_PI * k;
      const bool inside = continuous || (v + shift >= a.min_rad && v + shift <= a.max_rad);
      const double dist = std::abs(v - near[i]) + (inside ? 0.0 : 1e6);
      if (dist < best_d) {
        best_d = dist;
        best = v;
      }
    }
    r.q[i] = best;
    const double v = limited_value(m, r.q, i);
    if (v < a.min_rad || v > a.max_rad) {
      r.status = IkStatus::JointLimit;
      std::ostringstream o;
      o << "axis " << i + 1 << " would be at " << v / kDeg << " degrees" << (v != best ? " (q2 + q3)" : "")
        << ", outside " << a.min_rad / kDeg << " .. " << a.max_rad / kDeg;
      r.message = o.str();
      return r;
    }
  }
  const Singularity s = singularity(m, r.q);
  std::ostringstream o;
  if (s.wrist < limits.wrist)
    o << "wrist singularity: axis 5 at " << r.q[4] / kDeg << " degrees (axes 4 and 6 aligned)";
  else if (s.elbow < limits.elbow)
    o << "elbow singularity: the arm is stretched or folded (axis 3 at " << r.q[2] / kDeg << " degrees)";
  else if (s.shoulder_mm < limits.shoulder_mm)
    o << "shoulder singularity: the wrist centre is " << s.shoulder_mm << " mm from axis 1";
  if (!o.str().empty()) {
    r.status = IkStatus::Singular;
    r.message = o.str();
  }
  return r;
}

ArmModel perturbed(const ArmModel& nominal, std::uint64_t seed, double sigma_length_mm, double sigma_zero_rad) {
  ArmModel m = nominal;
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> len(0.0, sigma_length_mm), zero(0.0, sigma_zero_rad);
  for (Axis& a : m.axes) {
    if (a.a_mm != 0.0) a.a_mm += len(rng);
    if (a.d_mm != 0.0) a.d_mm += len(rng);
    a.offset_rad += zero(rng);
  }
  m.name = nominal.name + " (as built, seed " + std::to_string(seed) + ")";
  return m;
}

}  // namespace vts::robot
