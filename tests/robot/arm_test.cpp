// The arm's kinematics against hand-computed poses and independent
// geometry, inverse against forward over the workspace, limits and
// singularities, the servo's step response against its formula.
#include <catch2/catch.hpp>

#include <cmath>
#include <random>
#include <vector>

#include "robot/arm.h"
#include "robot/arm_robot.h"
#include "robot/robots.h"
#include "robot/servo.h"

using namespace vts::robot;
using Catch::Matchers::Contains;

namespace {

constexpr double kDeg = M_PI / 180.0;

Joints deg(double a, double b, double c, double d, double e, double f) {
  Joints q;
  q << a, b, c, d, e, f;
  return q * kDeg;
}

// A random joint vector inside the limits (axes 4 and 6 within +-180) and
// away from the singularities.
Joints random_q(const ArmModel& m, std::mt19937_64& rng) {
  while (true) {
    Joints q;
    for (int i = 0; i < 6; ++i) {
      const Axis& a = m.axes[static_cast<std::size_t>(i)];
      std::uniform_real_distribution<double> d(std::max(a.min_rad, -M_PI), std::min(a.max_rad, M_PI));
      q[i] = d(rng);
    }
    const Singularity s = singularity(m, q);
    const double v3 = limited_value(m, q, 2);
    if (v3 < m.axes[2].min_rad || v3 > m.axes[2].max_rad) continue;  // a coupled axis 3
    if (s.wrist > 0.1 && s.elbow > 0.1 && s.shoulder_mm > 100.0) return q;
  }
}

double angle_diff(double a, double b) { return std::abs(std::remainder(a - b, 2.0 * M_PI)); }

}  // namespace

TEST_CASE("Arm presets: the flange at zero joints where the data sheets put it", "[robot]") {
  // IRB 2400: axis 2 at 615 mm up and 100 mm ahead; upper arm 705 up, 135
  // more to the forearm's axis, forearm 755 and 85 to the flange, pointing
  // forward: (100 + 755 + 85, 0, 615 + 705 + 135).
  const ArmModel irb = *arm_preset("irb2400");
  REQUIRE(validate(irb).empty());
  const Pose3 f = forward(irb, Joints::Zero());
  CHECK(f.translation().isApprox(Eigen::Vector3d(940.0, 0.0, 1455.0), 1e-12));
  CHECK(f.linear().col(2).isApprox(Eigen::Vector3d::UnitX(), 1e-12));
  const ArmModel kr = *arm_preset("kr16");
  REQUIRE(validate(kr).empty());
  CHECK(forward(kr, Joints::Zero()).translation().isApprox(Eigen::Vector3d(1045.0, 0.0, 1390.0), 1e-12));
  CHECK_FALSE(arm_preset("nope"));
}

TEST_CASE("Arm: the wrist centre from plain planar geometry agrees with the DH chain", "[robot]") {
  // In the vertical plane of axis 1: the upper arm a2 from vertical by q2,
  // the forearm (a3, d4) turned by q2 + q3 more; then turned by q1 about z.
  const ArmModel m = *arm_preset("irb2400");
  for (const Joints& q : {deg(30, 10, -20, 40, 50, 60), deg(-120, -45, 30, 0, 90, 0), deg(170, 90, -55, -150, -100, 300)}) {
    const double L3 = std::hypot(135.0, 755.0), g = std::atan2(755.0, 135.0);
    const double reach = 100.0 + 705.0 * std::sin(q[1]) + L3 * std::sin(q[1] + q[2] + g);
    const double up = 615.0 + 705.0 * std::cos(q[1]) + L3 * std::cos(q[1] + q[2] + g);
    const Eigen::Vector3d w(reach * std::cos(q[0]), reach * std::sin(q[0]), up);
    CHECK((wrist_centre(m, q) - w).norm() < 1e-9);
    // The flange is d6 from the wrist centre along its own z.
    const Pose3 f = forward(m, q);
    CHECK((f.translation() - 85.0 * f.linear().col(2) - w).norm() < 1e-9);
  }
}

TEST_CASE("Arm: inverse gives eight solutions that all reach the pose, one of them the joints it came from", "[robot]") {
  for (const char* name : {"irb2400", "kr16"}) {
    INFO(name);
    const ArmModel m = *arm_preset(name);
    std::mt19937_64 rng(7);
    for (int n = 0; n < 500; ++n) {
      const Joints q = random_q(m, rng);
      const Pose3 t = forward(m, q);
      const std::vector<Solution> all = inverse_all(m, t);
      REQUIRE(all.size() >= 4);  // the backward reach may be out of range
      bool found = false;
      for (const Solution& s : all) {
        const Pose3 back = forward(m, s.q);
        CHECK((back.translation() - t.translation()).norm() < 1e-8);
        CHECK((back.linear() - t.linear()).cwiseAbs().maxCoeff() < 1e-10);
        CHECK(config_of(m, s.q) == s.config);
        bool same = true;
        for (int i = 0; i < 6; ++i) same = same && angle_diff(s.q[i], q[i]) < 1e-8;
        found = found || same;
      }
      CHECK(found);
      const IkResult r = inverse(m, t, config_of(m, q), q);
      REQUIRE(r.status == IkStatus::Ok);
      CHECK((r.q - q).cwiseAbs().maxCoeff() < 1e-8);  // nearest representative: the same angles
    }
  }
}

TEST_CASE("Arm: unreachable poses, joint limits and singularities are refused with the reason", "[robot]") {
  const ArmModel m = *arm_preset("irb2400");
  Pose3 far = Pose3::Identity();
  far.translation() = Eigen::Vector3d(3000.0, 0.0, 500.0);
  const IkResult r1 = inverse(m, far, Config{}, Joints::Zero());
  CHECK(r1.status == IkStatus::Unreachable);
  CHECK_THAT(r1.message, Contains("out of reach"));
  // Axis 5 at 0: axes 4 and 6 aligned.
  const Joints q0 = deg(10, 20, -10, 30, 0, 40);
  const IkResult r2 = inverse(m, forward(m, q0), Config{}, q0);
  CHECK(r2.status == IkStatus::Singular);
  CHECK_THAT(r2.message, Contains("wrist singularity"));
  // Axis 3 beyond its upper limit of 65 degrees.
  const Joints q3 = deg(0, 0, 80, 0, 45, 0);
  const IkResult r3 = inverse(m, forward(m, q3), config_of(m, q3), q3);
  CHECK(r3.status == IkStatus::JointLimit);
  CHECK_THAT(r3.message, Contains("axis 3"));
  // The wrist centre on axis 1.
  Joints qs = deg(0, 0, 0, 0, 45, 0);
  {
    // q2 such that the wrist centre is over axis 1: reach 0.
    const double L3 = std::hypot(135.0, 755.0), g = std::atan2(755.0, 135.0);
    // Solve 100 + 705 sin q2 + L3 sin(q2 + g) = 0 for q2 near -0.4 by bisection.
    double lo = -1.5, hi = 0.0;
    for (int i = 0; i < 200; ++i) {
      const double mid = 0.5 * (lo + hi);
      (100.0 + 705.0 * std::sin(mid) + L3 * std::sin(mid + g) > 0.0 ? hi : lo) = mid;
    }
    qs[1] = 0.5 * (lo + hi);
  }
  const IkResult r4 = inverse(m, forward(m, qs), config_of(m, qs), qs);
  CHECK(r4.status == IkStatus::Singular);
  CHECK_THAT(r4.message, Contains("shoulder"));
}

TEST_CASE("Arm: the absolute-accuracy model puts the flange 0.2-1 mm from where the controller thinks", "[robot]") {
  const ArmModel m = *arm_preset("irb2400");
  const ArmModel built = perturbed(m, 42);
  const ArmModel again = perturbed(m, 42);
  CHECK(built.axes[1].a_mm == again.axes[1].a_mm);  // a seed gives one arm
  std::mt19937_64 rng(3);
  std::vector<double> err;
  for (int n = 0; n < 400; ++n) {
    const Joints q = random_q(m, rng);
    err.push_back((forward(built, q).translation() - forward(m, q).translation()).norm());
  }
  std::sort(err.begin(), err.end());
  const double median = err[err.size() / 2];
  CHECK(median > 0.2);
  CHECK(median < 1.0);
}

TEST_CASE("Servo: a small step is followed as q(t) = u - h (1 + w t) exp(-w t)", "[robot]") {
  ArmModel m = *arm_preset("irb2400");
  for (Axis& a : m.axes) a.max_acc_rad_s2 = a.max_vel_rad_s = 1e9;  // the formula is for the unlimited servo
  ServoParams p;
  JointServo s(m, p, Joints::Zero());
  const Joints u = deg(1, -2, 0.5, 3, 1, -1);
  for (int k = 1; k <= 100; ++k) {
    s.step(u);
    const double t = k * p.cycle_s;
    const Joints expect = u - u * (1.0 + p.omega_rad_s * t) * std::exp(-p.omega_rad_s * t);
    CHECK((s.q() - expect).cwiseAbs().maxCoeff() < 1e-12);
  }
}

TEST_CASE("Servo: a ramp is followed without lag once settled, and the limits are never passed", "[robot]") {
  const ArmModel m = *arm_preset("irb2400");
  ServoParams p;
  JointServo s(m, p, Joints::Zero());
  const Joints speed = deg(10, -5, 8, 20, -15, 30);  // deg/s, within every limit
  for (int k = 1; k <= 500; ++k) s.step(speed * (k * p.cycle_s));
  CHECK((s.q() - speed * (500 * p.cycle_s)).cwiseAbs().maxCoeff() < 1e-9);
  CHECK((s.velocity() - speed).cwiseAbs().maxCoeff() < 1e-9);
  // A 90-degree step on every axis: velocity and acceleration stay inside.
  JointServo big(m, p, Joints::Zero());
  Joints v_prev = Joints::Zero();
  bool clipped = false;
  for (int k = 0; k < 2000; ++k) {
    big.step(deg(90, 90, 60, 90, 90, 90));
    clipped = clipped || big.clipped() != 0;
    for (int i = 0; i < 6; ++i) {
      const Axis& a = m.axes[static_cast<std::size_t>(i)];
      CHECK(std::abs(big.velocity()[i]) <= a.max_vel_rad_s * (1 + 1e-12));
      CHECK(std::abs(big.velocity()[i] - v_prev[i]) / p.cycle_s <= a.max_acc_rad_s2 * (1 + 1e-9));
    }
    v_prev = big.velocity();
  }
  CHECK(clipped);
  CHECK((big.q() - deg(90, 90, 60, 90, 90, 90)).cwiseAbs().maxCoeff() < 1e-6);
}

TEST_CASE("ArmRobot: targets streamed at 20 Hz and advanced cycle by cycle are followed along the line", "[robot]") {
  // A master streams one target every 50 ms along a straight line at
  // 10 mm/s; the caller advances the arm one 4 ms cycle at a time (as vts
  // sim and vts serve do to sample the sensor). Each target is reached as a
  // ramp over the 50 ms, so once settled the TCP stays on the line (a step
  // each 50 ms, the axes' accelerations clipped unequally, had left it 0.03
  // mm off at right angles to the arm's reach).
  for (const double heading_deg : {30.0, 120.0}) {
    // The arm stands across the start's x (make_robot), which points at 30
    // degrees; the TCP travels along x or at right angles to it.
    Pose3 home = Pose3::Identity();
    const Eigen::Vector3d x(std::cos(M_PI / 6.0), std::sin(M_PI / 6.0), 0.0);
    const Eigen::Vector3d dir(std::cos(heading_deg * M_PI / 180.0), std::sin(heading_deg * M_PI / 180.0), 0.0);
    home.linear() << x, Eigen::Vector3d::UnitZ().cross(x), Eigen::Vector3d::UnitZ();
    home.linear() = home.linear() * Eigen::AngleAxisd(M_PI - 0.25 * M_PI, Eigen::Vector3d::UnitX()).toRotationMatrix();
    home.translation() = Eigen::Vector3d(600.0, 200.0, 0.0);
    const auto robot = make_robot("kr16", 0, home);
    Pose3 target = home;
    double worst_across = 0.0, worst_along = 0.0;
    for (int k = 1; k <= 60; ++k) {  // 3 s
      target.translation() += 0.5 * dir;
      robot->servo(target);
      const double t = 0.05 * k;
      for (double b : robot->breaks_before(t)) robot->advance(b);
      robot->advance(t);
      REQUIRE(robot->fault().empty());
      if (k < 20) continue;  // settling from rest
      const Eigen::Vector3d e = robot->tcp().translation() - target.translation();
      worst_across = std::max(worst_across, (e - e.dot(dir) * dir).norm());
      worst_along = std::max(worst_along, std::abs(e.dot(dir)));
    }
    INFO("heading " << heading_deg << " deg");
    CHECK(worst_across < 0.002);
    CHECK(worst_along < 0.05);  // 0.02 mm behind its command (0.06-0.23 mm with steps)
  }
}

TEST_CASE("Arm: a servo command never turns an axis a full turn back into its range", "[robot]") {
  // KR 16, axis 4 in -350 .. 350: at 349 degrees, a pose needing 351 is
  // reached at rest by -9 (the same pose). A start may take that
  // representative; a servo's next command must not (the wrist would spin
  // a full turn between two 4 ms cycles): it is a joint-limit fault.
  const ArmModel m = *arm_preset("kr16");
  const Joints here = deg(10.0, 30.0, 60.0, 349.0, 40.0, 20.0);
  const Joints next = deg(10.0, 30.0, 60.0, 351.0, 40.0, 20.0);
  const Pose3 target = forward(m, next);
  const Solution own = [&] {
    for (const Solution& s : inverse_all(m, target))
      if (angle_diff(s.q[3], next[3]) < 1e-6 && angle_diff(s.q[4], next[4]) < 1e-6) return s;
    FAIL("no solution of the pose has the joints it came from");
    return Solution{};
  }();
  const IkResult at_rest = inverse(m, target, own.config, here, {}, false);
  INFO(at_rest.message);
  REQUIRE(at_rest.status == IkStatus::Ok);
  CHECK(at_rest.q[3] / kDeg == Approx(-9.0).margin(1e-6));
  const IkResult servo = inverse(m, target, own.config, here, {}, true);
  CHECK(servo.status == IkStatus::JointLimit);
  CHECK_THAT(servo.message, Contains("axis 4 would be at 351"));
}

TEST_CASE("ArmRobot: starts with every axis as far inside its range as the pose allows", "[robot]") {
  // The KR 16's first pose on the saddle (vts sim --scenario saddle): the
  // first configuration in inverse_all's order has axis 4 at -177 degrees,
  // 3 % of its range from the limit the torch winds it into round the
  // branch. The start takes, of every configuration and turn of axes 4 and
  // 6, the one whose axis nearest a limit (as a share of its range) is
  // farthest from it: here the wrist flipped, axis 4 near 3 degrees.
  const ArmModel m = *arm_preset("kr16");
  auto room_of = [&](const Joints& q) {
    double room = 1.0;
    for (int i = 0; i < 6; ++i) {
      const Axis& a = m.axes[static_cast<std::size_t>(i)];
      const double v = limited_value(m, q, i);
      room = std::min(room, std::min(v - a.min_rad, a.max_rad - v) / (a.max_rad - a.min_rad));
    }
    return room;
  };
  const Joints first = deg(0.7, 23.3, 52.1, -177.1, 30.9, -93.0);
  ArmSetup setup;
  setup.nominal = m;
  setup.flange_from_tool.translation() = Eigen::Vector3d(0.0, 0.0, kTorchMm);
  const Pose3 home = forward(m, first) * setup.flange_from_tool;
  REQUIRE(inverse_all(m, forward(m, first)).front().q.isApprox(first, 1e-9));
  const ArmRobot robot(setup, home);
  const Joints q = *robot.joints();
  CHECK(robot.tcp().isApprox(home, 1e-9));
  CHECK(q[3] / kDeg == Approx(-177.1 + 180.0).margin(0.01));
  CHECK(q[4] / kDeg == Approx(-30.9).margin(0.01));
  CHECK(room_of(q) > room_of(first));
  // No solution or turn has more room.
  for (const Solution& s : inverse_all(m, forward(m, first)))
    for (int t4 = -1; t4 <= 1; ++t4)
      for (int t6 = -1; t6 <= 1; ++t6) {
        Joints v = s.q;
        v[3] += 2.0 * M_PI * t4;
        v[5] += 2.0 * M_PI * t6;
        CHECK(room_of(v) <= room_of(q) + 1e-9);
      }
}
