// How precisely the tracker's fits locate the track point (docs/JOINTS.md
// "Localization"): the covariance of a least-squares line, of two lines'
// intersection, the chance of a point lying outside a circle, and the track
// point's stated rms error against its spread over seeded noise.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <numbers>
#include <vector>

#include "synthetic.h"
#include "tracker/geometry.h"
#include "tracker/tracker.h"

namespace tk = vts::tracker;
using tk::Vec2;

namespace {

// Standard normal deviates from a fixed LCG and Box-Muller (the same on
// every platform).
struct Normal {
  std::uint64_t x;
  explicit Normal(std::uint64_t seed) : x(seed * 6364136223846793005ull + 1442695040888963407ull) {}
  double uniform() {
    x = x * 6364136223846793005ull + 1442695040888963407ull;
    return ((x >> 11) + 0.5) * (1.0 / 9007199254740992.0);
  }
  double operator()() { return std::sqrt(-2.0 * std::log(uniform())) * std::cos(2.0 * std::numbers::pi * uniform()); }
};

}  // namespace

TEST_CASE("line_cov: offset and slope variance of N evenly spaced points", "[tracker][geometry][localization]") {
  // 11 points 0.5 mm apart on z = 40: sum (x - mean)^2 = h^2 N (N^2 - 1) / 12
  // = 0.25 * 11 * 120 / 12 = 27.5 mm^2. With sigma = 0.1 mm across the line:
  // offset variance 0.01 / 11, angle variance 0.01 / 27.5.
  std::vector<Vec2> pts;
  for (int i = 0; i < 11; ++i) pts.emplace_back(0.5 * i, 40.0);
  const auto f = tk::fit_line(pts);
  REQUIRE(f);
  const tk::LineCov lc = tk::line_cov(f->line, tk::moments_of(pts), 0.01);
  CHECK(lc.var_offset == Approx(0.01 / 11.0).epsilon(1e-12));
  CHECK(lc.var_angle == Approx(0.01 / 27.5).epsilon(1e-12));
  CHECK(lc.mean.x() == Approx(2.5));
  // 2 mm past the mean: 0.01 / 11 + 4 * 0.01 / 27.5.
  CHECK(lc.across_var(Vec2(4.5, 40.0)) == Approx(0.01 / 11.0 + 0.04 / 27.5).epsilon(1e-12));
  // Tilted by 30 degrees: the same along the line.
  const Vec2 d(std::cos(std::numbers::pi / 6), std::sin(std::numbers::pi / 6));
  std::vector<Vec2> tilted;
  for (int i = 0; i < 11; ++i) tilted.push_back(Vec2(1.0, 2.0) + 0.5 * i * d);
  const auto g = tk::fit_line(tilted);
  REQUIRE(g);
  const tk::LineCov lt = tk::line_cov(g->line, tk::moments_of(tilted), 0.01);
  CHECK(lt.var_angle == Approx(0.01 / 27.5).epsilon(1e-9));
}

TEST_CASE("residual_variance: residuals pooled with a prior", "[tracker][geometry][localization]") {
  // 20 points alternately 0.1 mm above and below z = 50: residual sum of
  // squares 20 * 0.01 = 0.2 mm^2 over 18 degrees of freedom; with a prior of
  // 0.04 mm^2 worth 2: (0.2 + 0.08) / 20 = 0.014.
  std::vector<Vec2> pts;
  for (int i = 0; i < 20; ++i) pts.emplace_back(0.3 * i, i % 2 ? 50.1 : 49.9);
  const tk::Line line{Vec2(0.0, -1.0), -50.0};
  const tk::Moments m = tk::moments_of(pts);
  CHECK(tk::residual_variance(line, m, 0.04, 2.0) == Approx(0.014).epsilon(1e-9));
  CHECK(tk::residual_variance(line, m, 0.04, 0.0) == Approx(0.2 / 18.0).epsilon(1e-9));
  // Two points have no residual of their own: the prior alone.
  const std::vector<Vec2> two{Vec2(0, 50), Vec2(1, 50)};
  CHECK(tk::residual_variance(line, tk::moments_of(two), 0.04, 2.0) == Approx(0.04).epsilon(1e-12));
}

TEST_CASE("line_cov: the fitted slope's spread over seeded noise is sigma^2 / sum (x - mean)^2",
          "[tracker][geometry][localization]") {
  // 21 points 0.25 mm apart, Gaussian noise sigma = 0.05 mm across the line,
  // 4000 seeds. The sample variance of the slope (and of the offset at the
  // mean) has a relative standard error of sqrt(2 / 3999) = 2.2 %: within
  // 10 % (4.5 standard errors) of sigma^2 / S and sigma^2 / N.
  const int n = 21, seeds = 4000;
  const double h = 0.25, sigma = 0.05;
  const double s = h * h * n * (n * n - 1) / 12.0;
  double sum_a = 0.0, sum_a2 = 0.0, sum_c = 0.0, sum_c2 = 0.0;
  for (int k = 0; k < seeds; ++k) {
    Normal g(static_cast<std::uint64_t>(k) + 1);
    std::vector<Vec2> pts;
    for (int i = 0; i < n; ++i) pts.emplace_back(h * i, 30.0 + sigma * g());
    const auto f = tk::fit_line(pts);
    REQUIRE(f);
    const double slope = -f->line.n.x() / f->line.n.y();  // z = slope y + b
    const double at_mean = (f->line.c - f->line.n.x() * (0.5 * h * (n - 1))) / f->line.n.y();
    sum_a += slope, sum_a2 += slope * slope;
    sum_c += at_mean, sum_c2 += at_mean * at_mean;
  }
  const double var_a = (sum_a2 - sum_a * sum_a / seeds) / (seeds - 1);
  const double var_c = (sum_c2 - sum_c * sum_c / seeds) / (seeds - 1);
  std::vector<Vec2> grid;
  for (int i = 0; i < n; ++i) grid.emplace_back(h * i, 30.0);
  const tk::LineCov lc = tk::line_cov(tk::Line{Vec2(0.0, -1.0), -30.0}, tk::moments_of(grid), sigma * sigma);
  CHECK(lc.var_angle == Approx(sigma * sigma / s).epsilon(1e-12));
  CHECK(var_a == Approx(lc.var_angle).epsilon(0.10));
  CHECK(var_c == Approx(lc.var_offset).epsilon(0.10));
}

TEST_CASE("intersection_cov: two lines' shifts move their intersection", "[tracker][geometry][localization]") {
  // Square lines (normals y and z) through the origin: each line's shift
  // across itself is the intersection's shift along its normal.
  tk::LineCov a, b;
  a.n = Vec2(1.0, 0.0), a.var_offset = 0.04;
  b.n = Vec2(0.0, 1.0), b.var_offset = 0.01;
  const Eigen::Matrix2d c = tk::intersection_cov(a, b, Vec2::Zero());
  CHECK(c(0, 0) == Approx(0.04));
  CHECK(c(1, 1) == Approx(0.01));
  CHECK(c(0, 1) == Approx(0.0).margin(1e-15));
  // Lines at t = 60 degrees, both known to 0.01 mm^2 across, p along y and q
  // along (cos t, sin t): shifts dp, dq move x by dz = dp and dy = (cos t dp
  // - dq) / sin t, so var y = 0.01 (1 + cos^2 t) / sin^2 t = 0.01 * 1.25 /
  // 0.75, var z = 0.01, and the trace (va + vb) / sin^2 t = 0.02 / 0.75.
  tk::LineCov p, q;
  p.n = Vec2(0.0, 1.0), p.var_offset = 0.01;  // the line z = 0, along y
  const double t = std::numbers::pi / 3;
  q.n = Vec2(-std::sin(t), std::cos(t)), q.var_offset = 0.01;  // along (cos t, sin t)
  const Eigen::Matrix2d cx = tk::intersection_cov(p, q, Vec2::Zero());
  CHECK(cx(0, 0) == Approx(0.01 * 1.25 / 0.75));
  CHECK(cx(1, 1) == Approx(0.01));
  CHECK(cx.trace() == Approx(2.0 * 0.01 / 0.75));
  // Parallel lines: not located.
  q.n = p.n;
  CHECK_FALSE(tk::intersection_cov(p, q, Vec2::Zero()).allFinite());
}

TEST_CASE("prob_outside_circle: circular, one-dimensional and none", "[tracker][geometry][localization]") {
  // Circular: |e|^2 / sigma^2 is chi-square with 2 degrees of freedom, so
  // P(|e| > r) = exp(-r^2 / 2 sigma^2).
  for (const double sigma : {0.1, 0.3, 0.5, 1.0, 3.0}) {
    const Eigen::Matrix2d c = sigma * sigma * Eigen::Matrix2d::Identity();
    CHECK(tk::prob_outside_circle(c, 1.0) == Approx(std::exp(-0.5 / (sigma * sigma))).margin(1e-6));
  }
  // All along one direction (tilted): the two tails of a normal,
  // erfc(r / (sigma sqrt 2)).
  const Vec2 u = Vec2(3.0, 4.0) / 5.0;
  for (const double sigma : {0.2, 0.5, 1.0}) {
    const Eigen::Matrix2d c = sigma * sigma * u * u.transpose();
    CHECK(tk::prob_outside_circle(c, 1.0) == Approx(std::erfc(1.0 / (sigma * std::sqrt(2.0)))).margin(1e-6));
  }
  CHECK(tk::prob_outside_circle(Eigen::Matrix2d::Zero(), 1.0) == 0.0);
  CHECK(tk::prob_outside_circle(Eigen::Matrix2d::Constant(std::numeric_limits<double>::infinity()), 1.0) == 1.0);
  // Elongated, against a direct sum over a fine grid of the density:
  // sigma 0.6 and 0.2 along the axes, r = 1.
  {
    const double s1 = 0.6, s2 = 0.2, step = 0.002;
    double inside = 0.0;
    for (double y = -1.0 + 0.5 * step; y < 1.0; y += step)
      for (double z = -1.0 + 0.5 * step; z < 1.0; z += step)
        if (y * y + z * z <= 1.0)
          inside += std::exp(-0.5 * (y * y / (s1 * s1) + z * z / (s2 * s2))) * step * step / (2.0 * std::numbers::pi * s1 * s2);
    const Eigen::Matrix2d c = Eigen::Vector2d(s1 * s1, s2 * s2).asDiagonal();
    CHECK(tk::prob_outside_circle(c, 1.0) == Approx(1.0 - inside).margin(1e-4));
  }
}

namespace {
// The track point's stated rms error (TrackResult::track_sigma_mm) against
// its root mean square distance from the truth over `seeds` seeds of range
// noise sigma: the ratio of the empirical mean square to the stated one.
struct Spread {
  double stated_ms = 0.0, empirical_ms = 0.0;
  int read = 0;
};
// closed_only: only the readings of a closed root (gap 0: the bevels' lines'
// intersection).
Spread spread(const tk::TrackerParams& params, const std::vector<synth::Piece>& pieces, const Vec2& truth,
              double sigma, int seeds, int columns, bool closed_only = false) {
  Spread s;
  tk::Tracker tracker(params);
  for (int k = 0; k < seeds; ++k) {
    auto p = synth::sample(pieces, columns);
    synth::add_noise(p, sigma, static_cast<std::uint32_t>(k + 1));
    const tk::TrackResult& r = tracker.track(p.view());
    if (!r.track_point || !std::isfinite(r.track_sigma_mm)) continue;
    if (closed_only && !(r.gap_mm == 0.0)) continue;
    ++s.read;
    s.stated_ms += r.track_sigma_mm * r.track_sigma_mm;
    s.empirical_ms += (*r.track_point - truth).squaredNorm();
  }
  if (s.read) s.stated_ms /= s.read, s.empirical_ms /= s.read;
  return s;
}
// The same for a v-groove (with beads laid: fill).
Spread spread(const std::vector<synth::Piece>& pieces, const Vec2& truth, double sigma, int seeds, int columns,
              bool closed_only = false, bool fill = false) {
  tk::TrackerParams params;
  params.joint = tk::JointType::VGroove;
  params.groove.vgroove_fill = fill;
  return spread(params, pieces, truth, sigma, seeds, columns, closed_only);
}
}  // namespace

TEST_CASE("v-groove: the stated rms error of a closed root is its spread over seeded noise",
          "[tracker][vgroove][localization]") {
  // A closed 60-degree root at 120 mm (the bevels' lines meet there), 512
  // columns, range noise 0.05 and 0.2 mm, 400 seeds each, the readings of a
  // closed root (gap 0: the bevels' intersection; 342 and 195 of them). The
  // empirical mean square error has a relative standard error of about
  // sqrt(2 / 195) = 10 % (a chi-square's with two degrees of freedom per
  // reading); the track point of an ideal profile is exact (within 1e-3 mm),
  // so its mean square is the variance the bevels' fits give. Within 30 %
  // (3 standard errors). (The other readings take the root for open, its
  // edges a point or two short of the apex: at 0.05 mm noise 57 of 400,
  // 0.21 mm rms off where 0.10 mm is stated, a bias the fits do not see;
  // at 0.2 mm 0.29 mm where 0.33 mm is stated.)
  const synth::ClosedVGroove g;
  for (const double sigma : {0.05, 0.2}) {
    const Spread s = spread(g.pieces, g.root, sigma, 400, 512, true);
    INFO("noise " << sigma << ": stated rms " << std::sqrt(s.stated_ms) << " mm, empirical "
                  << std::sqrt(s.empirical_ms) << " mm over " << s.read << " readings");
    REQUIRE(s.read >= 150);
    CHECK(s.empirical_ms == Approx(s.stated_ms).epsilon(0.30));
  }
}

TEST_CASE("v-groove: the stated rms error of an open root is not overconfident", "[tracker][vgroove][localization]") {
  // The 60-degree groove with a 1.2 mm root opening and 1.5 mm root faces
  // (tracker_test.cpp's), 512 columns, range noise 0.05 mm, 400 seeds. Each
  // root edge lies between a bevel's last point and the next ray (a uniform
  // interval, which the stated error counts as its variance h^2 / 3), and
  // may lie a few points up the bevel (its last points could be the root
  // face): the stated error covers both, so the empirical mean square
  // error, about the truth (an edge's interval is no noise: the same on
  // every seed), must not exceed it by more than its standard error allows
  // (25 %).
  const double half = 30.0, depth = 8.0, gap = 1.2;
  const double run = depth * std::tan(half * std::numbers::pi / 180.0);
  const Vec2 lr{-0.5 * gap, 100}, rr{0.5 * gap, 100};
  const Vec2 lt = lr + Vec2(-run, -depth), rt = rr + Vec2(run, -depth);
  const std::vector<synth::Piece> v{{Vec2(-80, 92), lt}, {lt, lr}, {lr, Vec2(lr.x(), 101.5)},
                                    {rr, Vec2(rr.x(), 101.5)}, {rr, rt}, {rt, Vec2(80, 92)}};
  const Spread s = spread(v, Vec2(0, 100), 0.05, 400, 512);
  INFO("stated rms " << std::sqrt(s.stated_ms) << " mm, empirical " << std::sqrt(s.empirical_ms) << " mm over "
                     << s.read << " readings");
  REQUIRE(s.read >= 380);
  CHECK(s.empirical_ms <= 1.25 * s.stated_ms);
}

TEST_CASE("v-groove: a bevel whose foot is unseen may go on to the other edge's level",
          "[tracker][vgroove][localization]") {
  // The closed 60-degree root at (0.4, 120), tops at 110 on both sides
  // (no mismatch), its right bevel's last 2.5 mm of depth in a shadow (the
  // columns whose rays hit it below z = 117.5 return nothing). Read as an
  // open root, the right edge is where the bevel's last point is, 2.5 mm
  // above the left: the track point, halfway across, lies 0.5 * 2.5 tan 30
  // = 0.72 mm from the root. The bevel could go on down to the left edge's
  // level, 2.5 / cos 30 = 2.89 mm along it, and nothing seen between the
  // edges says otherwise: taken as uniform over that extension (variance
  // L^2 / 3), the track point moves half of its run across: 0.5 * 0.5 *
  // 2.89 / sqrt(3) = 0.42 mm rms, less for the part of the excess the
  // edges' own spread across the plates explains (twice their rms, about
  // 0.2 mm here: the grazing ray's interval at the shadowed edge). So at
  // least 0.3 mm, and the error (the extension's far end) within twice
  // it. Without it, the stated error is the fits' and the edge's interval
  // (0.09-0.16 mm, under a quarter of the error).
  const synth::ClosedVGroove g;
  const Vec2 &root = g.root, &lt = g.lt, &rt = g.rt;
  auto shadowed = [](synth::Profile p) {
    for (int i = 0; i < p.size(); ++i)
      if (p.valid[i] && p.y[i] > 0.45f && p.z[i] > 117.5f) p.invalidate(i, i);
    return p;
  };
  tk::TrackerParams params;
  params.joint = tk::JointType::VGroove;
  for (const double sigma : {0.0, 0.05}) {
    auto p = shadowed(synth::sample(g.pieces, 512));
    if (sigma > 0.0) synth::add_noise(p, sigma, 3);
    for (const bool on : {true, false}) {
      params.vgroove.unseen_root_extension = on;
      tk::Tracker tracker(params);
      const tk::TrackResult& r = tracker.track(p.view());
      REQUIRE(r.track_point);
      const double error = (*r.track_point - root).norm();
      INFO("noise " << sigma << ", extension " << on << ": " << tk::to_string(r.status) << ", error " << error
                    << " mm, stated " << r.track_sigma_mm << " mm, gap " << r.gap_mm << ", mismatch "
                    << r.mismatch_mm);
      CHECK(r.gap_mm > 0.0);
      CHECK(r.mismatch_mm == Approx(2.5).margin(0.15));
      CHECK(error == Approx(0.72).margin(0.1));
      if (on) {
        CHECK(r.track_sigma_mm >= 0.3);
        CHECK(error <= 2.0 * r.track_sigma_mm);
      } else {
        CHECK(r.track_sigma_mm < 0.25 * error);
      }
    }
  }
  // The same edges where the right plate's root face goes down to a
  // backing bar 1 mm under the left edge (a root opening 1.44 mm wide, the
  // right edge 2.5 mm higher: unequal root faces). The rays between the
  // edges reach the bar through where the extension would be: the right
  // edge is where it is read, and the stated error is the fits'.
  const Vec2 re = root + Vec2(2.5 * std::tan(std::numbers::pi / 6), -2.5);
  const std::vector<synth::Piece> open{{Vec2(-80, 110), lt},         {lt, root},  {root, Vec2(root.x(), 121)},
                                       {Vec2(-1, 121), Vec2(3, 121)}, {re, Vec2(re.x(), 121)},
                                       {re, rt},                       {rt, Vec2(80, 110)}};
  const auto p = synth::sample(open, 512);
  double stated[2] = {0, 0};
  for (const bool on : {true, false}) {
    params.vgroove.unseen_root_extension = on;
    tk::Tracker tracker(params);
    const tk::TrackResult& r = tracker.track(p.view());
    REQUIRE(r.track_point);
    INFO("backing bar, extension " << on << ": " << tk::to_string(r.status) << ", track (" << r.track_point->x()
                                   << ", " << r.track_point->y() << "), stated " << r.track_sigma_mm);
    CHECK(r.mismatch_mm == Approx(2.5).margin(0.15));
    stated[on] = r.track_sigma_mm;
  }
  CHECK(stated[1] == stated[0]);
}

TEST_CASE("groove model: the stated rms error of B3 on a flat bottom is its spread over seeded noise",
          "[tracker][groove][localization]") {
  // A groove read by the groove model (a v-groove with beads laid,
  // GrooveParams::vgroove_fill): tops at 100 mm, walls 60 degrees to them
  // down to a flat bottom 7 mm deep and 6 mm wide (the last bead's cap),
  // 512 columns, range noise 0.05 and 0.2 mm, 400 seeds. B3 is the bottom
  // midway between the toes, each toe the wall's and the bottom's fitted
  // lines' intersection: along the tops it moves with the toes' mean (a
  // quarter of their variances' sum along the tops, from the two lines'
  // covariances), across them with the two bottom points it lies between
  // ((1 - t)^2 + t^2 times the noise variance). The empirical mean square
  // error has a relative standard error of about sqrt(2 / 400) = 7 %;
  // within 30 %. Only at 0.05 mm: at 0.2 mm noise the stated rms is 0.24 mm
  // where 0.31 mm is found (docs/JOINTS.md "Localization": not resolved).
  const Vec2 b2(-3.0, 107.0), b4(3.0, 107.0), b1(-7.0, 100.0), b5(7.0, 100.0);
  const std::vector<synth::Piece> g{{Vec2(-60, 100), b1}, {b1, b2}, {b2, b4}, {b4, b5}, {b5, Vec2(60, 100)}};
  for (const double sigma : {0.05}) {
    const Spread s = spread(g, Vec2(0.0, 107.0), sigma, 400, 512, false, true);
    INFO("noise " << sigma << ": stated rms " << std::sqrt(s.stated_ms) << " mm, empirical "
                  << std::sqrt(s.empirical_ms) << " mm over " << s.read << " readings");
    REQUIRE(s.read >= 380);
    CHECK(s.empirical_ms == Approx(s.stated_ms).epsilon(0.30));
  }
}

TEST_CASE("groove model: B3 on a step of the bottom is stated no better than the step allows",
          "[tracker][groove][localization]") {
  // The flat-bottomed groove above with the plates' mismatch at a closed
  // root: the bottom's right half 0.6 mm deeper than its left, the step
  // under the toes' midpoint. B3 (midway between the toes along the tops)
  // lands on either level or on the step, where the truth (the corpus'
  // convention: the step's middle, between the two plates' root edges)
  // lies 0.3 mm from each level. The bottom's points within 1.5 mm of B3
  // scatter about their line by more than the noise, which the stated
  // error counts across the tops. Range noise 0.05 mm, 400 seeds: stated
  // 0.195 mm rms, found 0.291 mm (0.158 mm stated without the scatter, as
  // for the flat bottom); within 2.5 times in mean square. A step is still
  // understated: its points' scatter about a line fitted across it is
  // about half its half height (at 0.02 mm noise 0.107 mm is stated where
  // 0.253 mm is found). B3's own distance from that line counted too made
  // it 0.256 mm, but stated a closed U root's B3 on the lower plate's
  // radius beside a 1.9 mm mismatch (right, 0.007 mm off) to 0.74 mm.
  const Vec2 b2(-3.0, 107.0), b4(3.0, 107.6), b1(-7.0, 100.0), b5(7.0, 100.0);
  const std::vector<synth::Piece> g{{Vec2(-60, 100), b1}, {b1, b2},         {b2, Vec2(0.0, 107.0)},
                                    {Vec2(0.0, 107.0), Vec2(0.0, 107.6)}, {Vec2(0.0, 107.6), b4},
                                    {b4, b5},           {b5, Vec2(60, 100)}};
  const Spread s = spread(g, Vec2(0.0, 107.3), 0.05, 400, 512, false, true);
  INFO("stated rms " << std::sqrt(s.stated_ms) << " mm, empirical " << std::sqrt(s.empirical_ms) << " mm over "
                     << s.read << " readings");
  REQUIRE(s.read >= 380);
  CHECK(s.empirical_ms <= 2.5 * s.stated_ms);
}

TEST_CASE("lap: the stated rms error of a hidden face's foot is its spread over edge positions and noise",
          "[tracker][lap][localization]") {
  // A lap, the upper plate 4 mm thick at 106 mm on the right, its edge face
  // square to the plates and facing away from the sensor (hidden): the track
  // point is the face's foot on the lower plate, placed along it where the
  // upper plate's edge is read, between its last point and the next ray's
  // hit on its line (a uniform interval of half width h: variance h^2 / 3),
  // and across it on the lower plate's line. The edge is moved by a uniform
  // fraction of a column's spacing on each of 400 seeds (about 0.15 mm at
  // 106 mm, 512 columns), with range noise 0.05 mm, so that the interval's
  // share of the error is uniform as stated; the empirical mean square error
  // has a relative standard error of about 10 % (the interval's uniform
  // error has a kurtosis of 1.8). Within 30 %.
  // The face is drawn exactly square: no allowance for a sheared one.
  tk::TrackerParams params;
  params.joint = tk::JointType::Lap;
  params.hidden_face_deg = 0.0;
  tk::Tracker tracker(params);
  const double spacing = 2.0 * 106.0 * std::tan(20.0 * std::numbers::pi / 180.0) / 512;
  Normal g(7);
  double stated_ms = 0.0, empirical_ms = 0.0;
  int read = 0;
  for (int k = 0; k < 400; ++k) {
    const double e = 0.3 + spacing * g.uniform();
    const std::vector<synth::Piece> lap{{Vec2(-60, 110), Vec2(e, 110)}, {Vec2(e, 106), Vec2(60, 106)},
                                        {Vec2(e, 106), Vec2(e, 110)}};
    auto p = synth::sample(lap, 512);
    synth::add_noise(p, 0.05, static_cast<std::uint32_t>(k + 1));
    const tk::TrackResult& r = tracker.track(p.view());
    if (!r.track_point || !std::isfinite(r.track_sigma_mm)) continue;
    ++read;
    stated_ms += r.track_sigma_mm * r.track_sigma_mm;
    empirical_ms += (*r.track_point - Vec2(e, 110)).squaredNorm();
  }
  REQUIRE(read >= 380);
  stated_ms /= read, empirical_ms /= read;
  INFO("stated rms " << std::sqrt(stated_ms) << " mm, empirical " << std::sqrt(empirical_ms) << " mm over " << read
                     << " readings");
  CHECK(empirical_ms == Approx(stated_ms).epsilon(0.30));
}

TEST_CASE("lap: a hidden face sheared by the sensor's lead and side angles is within the stated error",
          "[tracker][lap][localization]") {
  // The section of a square edge face, seen by a sensor whose laser plane
  // has the unit normal n = (cos s cos p, sin s cos p, sin p) in the seam's
  // frame (seam along x, plates in x-y, the face the plane y = 0; lead angle
  // p, side angle s): the face's trace t = y x n and the plate's s = z x n
  // meet at cos a = -n_z n_y / sqrt((n_x^2 + n_z^2)(n_x^2 + n_y^2)), off
  // square by 1.56 degrees at p = 15, s = 6 degrees (worked out below). The
  // upper plate 6 mm thick, its face hidden and leaning that way, range
  // noise 0.05 mm, 200 seeds: the foot lies 6 tan(1.56 deg) = 0.163 mm from
  // where a square face puts it, which the fits alone state to about 0.04
  // mm; with TrackerParams::hidden_face_deg (1.5) the stated rms covers it
  // (the empirical mean square no more than 1.25 times the stated one), and
  // with 0 it does not (more than 4 times).
  const double deg = std::numbers::pi / 180.0, p = 15.0 * deg, side = 6.0 * deg;
  const double nx = std::cos(side) * std::cos(p), ny = std::sin(side) * std::cos(p), nz = std::sin(p);
  const double shear = std::acos(-nz * ny / std::sqrt((nx * nx + nz * nz) * (nx * nx + ny * ny))) - 0.5 * std::numbers::pi;
  REQUIRE(std::abs(shear) / deg == Approx(1.56).margin(0.005));
  const double e = 0.3, top = 104.0, bottom = 110.0;
  const Vec2 foot(e + (bottom - top) * std::tan(std::abs(shear)), bottom);  // the face leans away from the sensor
  const std::vector<synth::Piece> lap{{Vec2(-60, bottom), foot}, {Vec2(e, top), Vec2(60, top)}, {Vec2(e, top), foot}};
  for (const double allowance : {1.5, 0.0}) {
    tk::TrackerParams params;
    params.joint = tk::JointType::Lap;
    params.hidden_face_deg = allowance;
    const Spread s = spread(params, lap, foot, 0.05, 200, 512);
    INFO("hidden_face_deg " << allowance << ": stated rms " << std::sqrt(s.stated_ms) << " mm, empirical "
                            << std::sqrt(s.empirical_ms) << " mm over " << s.read << " readings");
    REQUIRE(s.read >= 190);
    if (allowance > 0.0)
      CHECK(s.empirical_ms <= 1.25 * s.stated_ms);
    else
      CHECK(s.empirical_ms > 4.0 * s.stated_ms);
  }
}

TEST_CASE("butt: a chamfered edge's points are no face, and the stated error counts their spread",
          "[tracker][butt][localization]") {
  // A butt joint at 100 mm, gap 1 mm (edges at y = -0.5 and 0.5), the left
  // plate's edge chamfered 1 mm at 45 degrees, its square edge face below
  // the chamfer, the right plate's edge sharp. The left edge (where the top
  // and the face would meet) is (-0.5, 100), the track point the gap's
  // centre (0, 100). The points behind the left plate between the plates
  // (about 7 at 512 columns: the chamfer's and the face's) are taken for
  // face points; their feet on the plate's line spread over the chamfer's
  // 1 mm, which noise does not do. The edge is their mean, about 0.45 mm
  // short of the truth, which lies at the end of the spread: the stated
  // error counts the feet's variance (about 0.08 mm^2, a uniform spread's
  // 1/12 mm^2 with the face's points), about half of that error, where the
  // fits alone stated 0.01-0.02 mm. Range noise 0.05 mm, 200 seeds: the
  // empirical mean square error within 5 times the stated one (a truth at
  // the end of a uniform spread is 3 times its variance off its centre),
  // and with the track point's error, 0.25 mm, over 2 stated rms.
  // (Placing the edge at the outermost foot instead: on the corpus'
  // development seeds the butt's right readings went 77.0 -> 72.8 %, the
  // corner's 66.8 -> 67.9 %; docs/JOINTS.md "Localization".)
  const double z = 100.0, depth = 6.0;
  const Vec2 l_top(-1.5, z), l_cham(-0.5, z + 1.0), r_edge(0.5, z);
  const std::vector<synth::Piece> butt{{Vec2(-60, z), l_top},          {l_top, l_cham},
                                       {l_cham, Vec2(-0.5, z + depth)}, {r_edge, Vec2(0.5, z + depth)},
                                       {r_edge, Vec2(60, z)}};
  tk::TrackerParams params;
  params.joint = tk::JointType::Butt;
  const Spread s = spread(params, butt, Vec2(0.0, z), 0.05, 200, 512);
  INFO("stated rms " << std::sqrt(s.stated_ms) << " mm, empirical " << std::sqrt(s.empirical_ms) << " mm over "
                     << s.read << " readings");
  REQUIRE(s.read >= 190);
  CHECK(s.empirical_ms <= 5.0 * s.stated_ms);
  CHECK(std::sqrt(s.empirical_ms) >= 0.2);
}

TEST_CASE("tracker: the confidence includes the chance that the track point is off", "[tracker][localization]") {
  // Any reading: confidence <= 1 - track_off_probability, and an exact
  // closed root of an ideal profile is located to well within 1 mm.
  const std::vector<synth::Piece> v = synth::ClosedVGroove{}.pieces;
  tk::TrackerParams params;
  params.joint = tk::JointType::VGroove;
  tk::Tracker tracker(params);
  const tk::TrackResult& ideal = tracker.track(synth::sample(v).view());
  REQUIRE(ideal.status == tk::TrackStatus::Ok);
  CHECK(ideal.track_sigma_mm < 0.01);
  CHECK(ideal.track_off_probability < 1e-12);
  for (const double sigma : {0.05, 0.2, 0.5}) {
    for (std::uint32_t seed = 1; seed <= 20; ++seed) {
      auto p = synth::sample(v, 256);
      synth::add_noise(p, sigma, seed);
      const tk::TrackResult& r = tracker.track(p.view());
      if (r.status != tk::TrackStatus::Ok) continue;
      INFO("noise " << sigma << " seed " << seed);
      CHECK(std::isfinite(r.track_sigma_mm));
      CHECK(r.confidence <= 1.0 - r.track_off_probability + 1e-12);
      CHECK(r.confidence >= params.confidence.min_confidence);
    }
  }
}
