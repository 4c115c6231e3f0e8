// Steps 1 to 4 on synthetic profiles: outlier elimination, split, merge and
// the line fits, with the paper's Table 1 defaults.
#include <catch2/catch.hpp>

#include <cmath>

#include "synthetic.h"
#include "tracker/segmentation.h"

namespace tk = vts::tracker;
using tk::Vec2;

namespace {

tk::Segmentation segment(const synth::Profile& p, const tk::SegmentationParams& params = {}) {
  tk::Segmentation s;
  tk::segment_profile(p.view(), params, s);
  return s;
}

int long_segments(const tk::Segmentation& s, int min_points = 8) {
  int n = 0;
  for (const auto& sg : s.segments) n += sg.count() >= min_points;
  return n;
}

}  // namespace

TEST_CASE("segmentation: Table 1 defaults", "[tracker][segmentation]") {
  const tk::SegmentParams p;
  CHECK(p.split_threshold_mm == 0.4);
  CHECK(p.split_interval == 2);
  CHECK(p.min_segment_points == 8);
  CHECK(p.max_merge_gap_points == 10);
  CHECK(p.max_merge_angle_deg == 15.0);
}

TEST_CASE("segmentation: a straight plate is one segment", "[tracker][segmentation]") {
  const auto p = synth::sample({{Vec2(-80, 100), Vec2(80, 100)}});
  const auto s = segment(p);
  REQUIRE(s.segments.size() == 1);
  CHECK(s.segments[0].count() == 512);
  CHECK(s.segments[0].first_col == 0);
  CHECK(s.segments[0].last_col == 511);
  CHECK(s.segments[0].line.distance(Vec2(0, 100)) == Approx(0.0).margin(1e-4));
  CHECK(s.outliers == 0);
}

TEST_CASE("segmentation: a V splits at its corner, no point lost", "[tracker][segmentation]") {
  const auto p = synth::sample(synth::valley(Vec2(0.3, 100), 90.0));
  const auto s = segment(p);
  REQUIRE(s.segments.size() == 2);
  // Every kept point belongs to exactly one segment, in order.
  CHECK(s.segments[0].first == 0);
  CHECK(s.segments[1].first == s.segments[0].last + 1);
  CHECK(s.segments[1].last == static_cast<int>(s.points.size()) - 1);
  const auto x = tk::intersect(s.segments[0].line, s.segments[1].line);
  REQUIRE(x);
  CHECK((*x - Vec2(0.3, 100)).norm() < 1e-3);
  // Each point sits on its own segment's line.
  for (const auto& sg : s.segments)
    for (int k = sg.first; k <= sg.last; ++k) CHECK(sg.line.distance(s.points[k]) < 1e-3);
}

TEST_CASE("segmentation: a vertical wall is fitted in normal form", "[tracker][segmentation]") {
  // A wall at y = 5 (parallel to the optical axis) seen obliquely, z from 60
  // to 100, then a floor at z = 100.
  const auto p = synth::sample({{Vec2(5, 60), Vec2(5, 100)}, {Vec2(5, 100), Vec2(60, 100)}});
  const auto s = segment(p);
  bool wall = false;
  for (const auto& sg : s.segments)
    if (sg.count() >= 8 && std::abs(sg.line.n.x()) > 0.999999) {
      wall = true;
      CHECK(sg.line.distance(Vec2(5, 0)) == Approx(0.0).margin(1e-4));
    }
  CHECK(wall);
}

TEST_CASE("segmentation: regions smaller than s_min are not split", "[tracker][segmentation]") {
  // A 7-point profile with a sharp bend stays one segment.
  synth::Profile p = synth::sample(synth::valley(Vec2(0, 100), 90.0), 512);
  for (int i = 0; i < 512; ++i)
    if (i < 253 || i > 259) p.invalidate(i, i);
  tk::SegmentationParams params;
  params.outliers.enabled = false;
  const auto s = segment(p, params);
  REQUIRE(s.points.size() == 7);
  CHECK(s.segments.size() == 1);
}

TEST_CASE("segmentation: merge across a dropout shorter than g_max, not across a longer one",
          "[tracker][segmentation]") {
  for (int missing : {3, 9, 10, 25}) {
    auto p = synth::sample({{Vec2(-80, 100), Vec2(80, 100)}});
    p.invalidate(200, 200 + missing - 1);
    const auto s = segment(p);
    INFO(missing << " invalid columns");
    CHECK(static_cast<int>(s.segments.size()) == (missing < 10 ? 1 : 2));
  }
}

TEST_CASE("segmentation: collinear pieces offset by a step are not merged", "[tracker][segmentation]") {
  // Two parallel plates 0.5 mm apart with 4 invalid columns between them.
  auto p = synth::sample({{Vec2(-80, 100), Vec2(0, 100)}, {Vec2(0, 99.5), Vec2(80, 99.5)}});
  int cut = 0;
  while (p.y[cut] < 0.0f) ++cut;
  p.invalidate(cut, cut + 3);
  const auto s = segment(p);
  CHECK(long_segments(s) == 2);
}

TEST_CASE("segmentation: merge angle", "[tracker][segmentation]") {
  // Two plates meeting at a 10-degree kink with a dropout at the kink: the
  // angle is below 15 degrees but together they are not one line, so they
  // stay two; a 0.3-degree kink is one line.
  for (double kink : {10.0, 0.3}) {
    const Vec2 k(0, 100);
    auto p = synth::sample({{k - 80 * Vec2(1, 0), k}, {k, k + 80 * synth::dir_deg(-kink)}});
    int c = 0;
    while (p.y[c] < 0.0f) ++c;
    p.invalidate(c - 2, c + 2);
    const auto s = segment(p);
    INFO("kink " << kink);
    CHECK(long_segments(s) == (kink > 1.0 ? 2 : 1));
  }
}

TEST_CASE("outliers: single spikes and clusters of up to 4 points are removed", "[tracker][segmentation]") {
  for (int cluster : {1, 2, 3, 4}) {
    for (double height : {0.5, 3.0, -2.0}) {
      auto p = synth::sample({{Vec2(-80, 100), Vec2(80, 100)}});
      for (int k = 0; k < cluster; ++k) {
        p.z[300 + k] += static_cast<float>(height - 0.13 * k);
        p.y[300 + k] = p.y[300 + k] * p.z[300 + k] / 100.0f;  // still on its column's ray
      }
      const auto s = segment(p);
      INFO(cluster << " points " << height << " mm off the plate");
      CHECK(s.outliers == cluster);
      CHECK(s.segments.size() == 1);
      for (int k = 0; k < cluster; ++k) CHECK(s.column_state[300 + k] == tk::kColumnOutlier);
    }
  }
}

TEST_CASE("outliers: a cluster inside a shadow (an island) is removed", "[tracker][segmentation]") {
  auto p = synth::sample({{Vec2(-80, 100), Vec2(80, 100)}});
  p.invalidate(200, 240);
  p.valid[220] = p.valid[221] = 1;
  p.y[220] = -3.0f, p.z[220] = 70.0f;
  p.y[221] = -2.9f, p.z[221] = 70.1f;
  const auto s = segment(p);
  CHECK(s.outliers == 2);
  // 41 columns without a point: more than g_max, so two pieces of one line.
  REQUIRE(s.segments.size() == 2);
  CHECK(s.segments[0].last_col == 199);
  CHECK(s.segments[1].first_col == 241);
}

TEST_CASE("outliers: corners and short real faces are kept", "[tracker][segmentation]") {
  // A V: nothing is removed at the corner.
  {
    const auto s = segment(synth::sample(synth::valley(Vec2(0, 100), 90.0)));
    CHECK(s.outliers == 0);
  }
  {
    const auto s = segment(synth::sample(synth::ridge(Vec2(0, 100), 100.0)));
    CHECK(s.outliers == 0);
  }
  // A step 1.5 mm high whose face, seen obliquely, shows 3 points.
  {
    const auto p = synth::sample(
        {{Vec2(-80, 101.5), Vec2(30, 101.5)}, {Vec2(30, 100), Vec2(30, 101.5)}, {Vec2(30, 100), Vec2(80, 100)}});
    int on_face = 0;
    for (int i = 0; i < p.size(); ++i) on_face += p.valid[i] && std::abs(p.y[i] - 30.0f) < 1e-4f;
    REQUIRE(on_face >= 2);
    REQUIRE(on_face <= 4);
    const auto s = segment(p);
    CHECK(s.outliers == 0);
  }
}

TEST_CASE("segmentation: NaN, infinity and points behind the sensor are invalid", "[tracker][segmentation]") {
  auto p = synth::sample({{Vec2(-80, 100), Vec2(80, 100)}});
  p.y[10] = std::numeric_limits<float>::quiet_NaN();
  p.z[11] = std::numeric_limits<float>::infinity();
  p.y[12] = -std::numeric_limits<float>::infinity();
  p.z[13] = -5.0f;
  p.z[14] = std::numeric_limits<float>::quiet_NaN();
  const auto s = segment(p);
  CHECK(s.valid_points == 512 - 5);
  for (int i = 10; i <= 14; ++i) CHECK(s.column_state[i] == tk::kColumnInvalid);
  CHECK(s.segments.size() == 1);
}

TEST_CASE("segmentation: region of interest", "[tracker][segmentation]") {
  const auto p = synth::sample(synth::valley(Vec2(0, 100), 90.0));
  tk::SegmentationParams params;
  params.roi_first = 300;
  params.roi_last = 400;
  const auto s = segment(p, params);
  CHECK(s.valid_points == 101);
  REQUIRE(s.segments.size() == 1);
  CHECK(s.segments[0].first_col == 300);
  CHECK(s.segments[0].last_col == 400);
}

TEST_CASE("segmentation: column rays between kept points", "[tracker][segmentation]") {
  auto p = synth::sample({{Vec2(-80, 100), Vec2(80, 100)}});
  p.invalidate(100, 120);
  const auto s = segment(p);
  for (int col : {0, 99, 110, 121, 511}) CHECK(s.column_tan(col) == Approx(synth::column_tan(col, 512)).margin(1e-6));
}

TEST_CASE("segmentation: malformed input", "[tracker][segmentation]") {
  std::vector<float> y(10, 0.0f), z(9, 100.0f);
  tk::Segmentation s;
  tk::segment_profile({y, z, {}}, {}, s);
  CHECK_FALSE(s.error.empty());
  CHECK(s.points.empty());
}

// A noisy point displaced along its ray that makes a jump from the point
// before it starts a new run: with no kept neighbours before it in its run,
// the cluster test inside a run cannot remove it. It lies 0.27 mm off the
// plate (under threshold_mm) and the step back onto the plate is no jump, so
// it is the run's first point; the rule for clusters at a run's end removes it
// (seen on a fillet's flange at 50 mm: left in, it cut the flange in two).
TEST_CASE("outliers: a point that makes the jump starting its run is removed", "[tracker][segmentation]") {
  auto p = synth::sample({{Vec2(-15, 35), Vec2(15, 65)}});  // 45 degrees at 50 mm
  int c = 0;
  while (p.y[c] < 0.76f) ++c;
  p.z[c] += 0.38f;
  p.y[c] = static_cast<float>(p.y[c] * (p.z[c]) / (p.z[c] - 0.38f));  // still on its column's ray
  tk::SegmentationParams params;
  {
    const auto s = segment(p, params);
    CHECK(s.outliers == 1);
    CHECK(s.column_state[c] == tk::kColumnOutlier);
    CHECK(s.segments.size() == 1);
  }
  // Without the rule the point stays and the plate is cut at it.
  params.outliers.run_end_clusters = false;
  {
    const auto s = segment(p, params);
    CHECK(s.outliers == 0);
    CHECK(s.segments.size() > 1);
  }
}

// The same rule must keep a wall seen in a gap: the points on plate 1's end
// face join plate 1 with short steps and leave for plate 2 with a long one (a
// butt joint's gap seen obliquely, as the built-in butt at 150 mm, tilt 20).
TEST_CASE("outliers: a wall seen in a gap at a run's end is kept", "[tracker][segmentation]") {
  // Plates tilted 20 degrees, gap 1 mm, the first plate's end face square to it.
  const Vec2 u = synth::dir_deg(-20.0), nrm(-u.y(), u.x());  // along the plates, into the work (+z side)
  const Vec2 c0(0.0, 150.0);
  const Vec2 e1 = c0 - 0.5 * u, e2 = c0 + 0.5 * u;
  const auto p = synth::sample({{e1 - 80.0 * u, e1}, {e2, e2 + 80.0 * u}, {e1, e1 + 6.0 * nrm}});
  int wall = 0;
  for (int i = 0; i < p.size(); ++i) wall += p.valid[i] && std::abs((Vec2(p.y[i], p.z[i]) - e1).dot(u)) < 1e-3 &&
                                             (Vec2(p.y[i], p.z[i]) - e1).dot(nrm) > 0.05;
  INFO(wall << " wall points");
  REQUIRE(wall >= 2);
  REQUIRE(wall <= 4);
  const auto s = segment(p);
  CHECK(s.outliers == 0);
}

// An island of a root-face point and a noisy point at the corner (dropouts
// on both sides): the line through the two passes within threshold_mm of the
// root face's next point beyond the dropout, but beside the island, not past
// its end: no piece of a steep surface, so it is removed (seen on a
// v-groove at 50 mm: kept, it was read as a 2-point bevel).
TEST_CASE("outliers: an island is a piece only if the point beyond continues it past its end",
          "[tracker][segmentation]") {
  // Root face going away from the sensor's left (70 degrees), then the bevel.
  const Vec2 corner(0.72, 50.21), face = synth::dir_deg(-70.0), bevel = synth::dir_deg(-40.0);
  auto p = synth::sample({{corner - 2.0 * face, corner}, {corner, corner + 20.0 * bevel}});
  int c = 0;
  while (!p.valid[c] || p.y[c] < 0.66f) ++c;  // the last root-face point before the corner
  p.invalidate(c - 1, c - 1);
  // The next point 0.38 mm behind, along its ray: it makes a jump to the bevel.
  const float z0 = p.z[c + 1];
  p.z[c + 1] += 0.38f;
  p.y[c + 1] = p.y[c + 1] * p.z[c + 1] / z0;
  tk::SegmentationParams params;
  {
    const auto s = segment(p, params);
    CHECK(s.column_state[c + 1] == tk::kColumnOutlier);
  }
  params.outliers.islands_continue_ahead = false;
  {
    const auto s = segment(p, params);
    CHECK(s.column_state[c + 1] == tk::kColumnKept);
  }
}

TEST_CASE("segmentation: a step below t_split near a region's end is split, its point on its own side",
          "[tracker][segmentation]") {
  // Two parallel plates, the right one 0.28 mm nearer the sensor from
  // y = 30.74 (40 of the 512 columns, the first on the step's face, 0.13 mm
  // below the upper plate): the step leaves the chord by 0.26 mm, less than
  // t_split (0.4 mm), so only the rough split (rough_tol_mm, the tracker's
  // surface tolerance) cuts it. Its farthest point from the chord is the
  // lower plate's last: with it, the upper side fits a line with an rms of
  // 0.045 mm, more than half the whole's (0.066 mm / 2); on its own side,
  // the lower side fits exactly and the upper (with the face's point) to
  // 0.022 mm.
  const auto p = synth::sample(
      {{Vec2(-80, 100), Vec2(30.74, 100)}, {Vec2(30.74, 100), Vec2(30.74, 99.72)}, {Vec2(30.74, 99.72), Vec2(80, 99.72)}});
  int face = 0;
  while (!(p.z[face] < 99.99f)) ++face;
  REQUIRE(p.z[face] > 99.8f);  // on the face, not the upper plate
  REQUIRE(p.valid.size() - face == 40);
  tk::SegmentationParams params;
  tk::Segmentation s;
  tk::segment_profile(p.view(), params, s, 0.0, 0.02, 0.0);
  REQUIRE(long_segments(s) == 2);
  CHECK(s.segments.front().last_col == face - 1);
  CHECK(s.segments.back().first_col >= face);
  CHECK(s.segments.back().first_col <= face + 1);
  CHECK(s.segments.front().line.distance(Vec2(0, 100)) < 1e-4);
  CHECK(s.segments.back().line.distance(Vec2(50, 99.72)) < 0.01);  // (the face's point may be in its fit)
  // Either rule alone cuts it (the least-squares place of two parallel
  // lines is the step too); neither, and it stays one segment.
  params.segments.rough_split_best_fit = false;
  tk::segment_profile(p.view(), params, s, 0.0, 0.02, 0.0);
  CHECK(long_segments(s) == 2);
  params.segments.rough_split_best_fit = true;
  params.segments.rough_step_either_side = false;
  tk::segment_profile(p.view(), params, s, 0.0, 0.02, 0.0);
  CHECK(long_segments(s) == 2);
  params.segments.rough_split_best_fit = false;
  tk::segment_profile(p.view(), params, s, 0.0, 0.02, 0.0);
  CHECK(long_segments(s) == 1);
}

TEST_CASE("segmentation: a step below t_split on a wavy surface is split at the step", "[tracker][segmentation]") {
  // Plates at z = 100 and, from y = 20, 0.3 mm nearer the sensor (a butt's
  // mismatch, its face seen by one column), 1,024 columns, with waviness
  // 0.05 mm in amplitude and 8 mm in wavelength along the rays: the rough
  // split's test fails at the region's farthest point from the chord (one
  // segment without rough_split_best_fit); the least-squares place of two
  // lines is the step, each side then fitting its line to the waviness
  // (0.05 / sqrt(2) = 0.035 mm rms).
  const int n = 1024;
  auto p = synth::sample({{Vec2(-80, 100), Vec2(20, 100)}, {Vec2(20, 100), Vec2(20, 99.7)}, {Vec2(20, 99.7), Vec2(80, 99.7)}},
                         n);
  int step = 0;
  while (!(p.y[step] >= 20.0f)) ++step;
  for (int i = 0; i < n; ++i)
    synth::along_ray(p, i, 0.05 * std::sin(2.0 * std::numbers::pi * synth::column_tan(i, n) * 100.0 / 8.0));
  tk::SegmentationParams params;
  tk::Segmentation s;
  tk::segment_profile(p.view(), params, s, 0.0, 0.02, 0.0);
  REQUIRE(long_segments(s) == 2);
  CHECK(std::abs(s.segments.back().first_col - step) <= 1);
  CHECK(s.segments.front().rms_mm < 0.04);
  CHECK(s.segments.back().rms_mm < 0.04);
  params.segments.rough_split_best_fit = false;
  tk::segment_profile(p.view(), params, s, 0.0, 0.02, 0.0);
  CHECK(long_segments(s) == 1);
}
