// The corpus' joints: ideal points on the section, truth on the lines it is
// defined by, every variant for many seeds, visibility tags.
#include <catch2/catch.hpp>

#include "corpus.h"

#include <cmath>
#include <numbers>
#include <optional>
#include <string>

namespace vc = vts_corpus;
using vc::Vec2;

namespace {

struct Line {
  Vec2 p, d;  // d unit
};

// The line of a named face in the sensor frame, through its longest edge.
std::optional<Line> face_line(const vc::Debug& dbg, int face) {
  const vc::Edge* best = nullptr;
  for (const auto& e : dbg.scene.edges)
    if (e.face == face && (!best || (e.b - e.a).norm() > (best->b - best->a).norm())) best = &e;
  if (!best) return std::nullopt;
  return Line{best->a, (best->b - best->a).normalized()};
}

double dist(const Vec2& q, const Line& l) { return std::abs(vc::cross(l.d, q - l.p)); }

Vec2 bp(const vc::Truth& t, const char* name) {
  const auto* p = t.break_point(name);
  REQUIRE(p != nullptr);
  return Vec2((*p)[0], (*p)[1]);
}

double dist_to_segment(const Vec2& p, const vc::Edge& e) {
  const Vec2 d = e.b - e.a;
  const double s = std::clamp((p - e.a).dot(d) / d.squaredNorm(), 0.0, 1.0);
  return (p - (e.a + s * d)).norm();
}

// On the lines of both faces (a corner of the section, real or virtual).
bool on_lines(const vc::Debug& dbg, const Vec2& q, int face_a, int face_b, double tol = 1e-9) {
  const auto a = face_line(dbg, face_a), b = face_line(dbg, face_b);
  return a && b && dist(q, *a) < tol && dist(q, *b) < tol;
}

vc::Options ideal() {
  vc::Options o;
  o.imperfections = false;
  o.keep_debug = true;
  return o;
}

// The distance of a line from the sensor (larger: lower, farther into the work).
double depth_of(const Line& l) { return std::abs(vc::cross(l.d, -l.p)); }

}  // namespace

TEST_CASE("joints: ideal profiles put every point on the cross-section's edges", "[corpus][joints]") {
  for (vc::Joint joint : vc::kAllJoints) {
    for (std::uint64_t seed = 1; seed <= 150; ++seed) {
      vc::Options o = ideal();
      o.decoy = seed % 3 == 0;
      const vc::Profile p = vc::make_profile(joint, seed, o);
      const vc::Debug& d = *p.debug;
      int valid = 0;
      for (std::size_t i = 0; i < p.y.size(); ++i) {
        if (!p.valid[i]) {
          CHECK(std::isnan(p.y[i]));
          CHECK(std::isnan(p.z[i]));
          continue;
        }
        ++valid;
        const Vec2 q = d.ideal_range_mm[i] * d.ray_dir[i];
        double nearest = 1e300;
        for (const auto& e : d.scene.edges) nearest = std::min(nearest, dist_to_segment(q, e));
        INFO(vc::joint_name(joint) << " seed " << seed << " column " << i);
        CHECK(nearest < 1e-6);
        // The float output is the ideal point rounded.
        CHECK(std::abs(p.y[i] - q.x()) <= 2e-7 * q.norm());
        CHECK(std::abs(p.z[i] - q.y()) <= 2e-7 * q.norm());
        CHECK(d.hit_face[i] != vc::kFaceBody);
      }
      CHECK(valid > static_cast<int>(p.y.size()) / 4);
    }
  }
}

TEST_CASE("joints: truth points lie on the lines that define them", "[corpus][joints]") {
  for (vc::Joint joint : vc::kAllJoints) {
    for (std::uint64_t seed = 1; seed <= 300; ++seed) {
      vc::Options o = ideal();
      o.decoy = seed % 4 == 0;
      const vc::Profile p = vc::make_profile(joint, seed, o);
      const vc::Truth& t = p.truth;
      const vc::Debug& d = *p.debug;
      const Vec2 track(t.track_y_mm, t.track_z_mm);
      INFO(vc::joint_name(joint) << " seed " << seed);
      CHECK(t.standoff_mm == t.track_z_mm);
      switch (joint) {
        case vc::Joint::Fillet: {
          // Root: the flange's top line x the web's open-face line, also with a gap.
          CHECK(on_lines(d, bp(t, "B1"), vc::kFaceFlangeTop, vc::kFaceWebOpen));
          CHECK(on_lines(d, bp(t, "B3"), vc::kFaceWebOpen, vc::kFaceWebBottom));
          CHECK((bp(t, "B1") - track).norm() < 1e-12);
          CHECK(t.gap_mm == Approx(dist(bp(t, "B3"), *face_line(d, vc::kFaceFlangeTop))).margin(1e-9));
          CHECK(t.angle_deg > 50);
          CHECK(t.angle_deg < 130);
          break;
        }
        case vc::Joint::Corner: {
          const Vec2 b1 = bp(t, "B1"), b3 = bp(t, "B3");
          CHECK((on_lines(d, b1, vc::kFaceOuter1, vc::kFaceEnd1) || on_lines(d, b1, vc::kFaceOuter2, vc::kFaceEnd2)));
          CHECK((on_lines(d, b3, vc::kFaceOuter1, vc::kFaceEnd1) || on_lines(d, b3, vc::kFaceOuter2, vc::kFaceEnd2)));
          CHECK(on_lines(d, bp(t, "B2"), vc::kFaceOuter1, vc::kFaceOuter2, 1e-8));
          CHECK((0.5 * (b1 + b3) - track).norm() < 1e-9);
          CHECK(t.gap_mm == Approx((b3 - b1).norm()).margin(1e-12));
          CHECK(b1.x() / b1.y() <= b3.x() / b3.y() + 1e-12);  // scan order
          CHECK(t.angle_deg > 60);
          CHECK(t.angle_deg < 175);
          break;
        }
        case vc::Joint::Lap: {
          // Foot: the edge face's line x the lower plate's top line.
          CHECK(on_lines(d, bp(t, "B1"), vc::kFaceLowerTop, vc::kFaceUpperEdge));
          CHECK(on_lines(d, bp(t, "B2"), vc::kFaceUpperEdge, vc::kFaceUpperBottom));
          CHECK(on_lines(d, bp(t, "B3"), vc::kFaceUpperEdge, vc::kFaceUpperTop));
          CHECK((bp(t, "B1") - track).norm() < 1e-12);
          const Line lower = *face_line(d, vc::kFaceLowerTop);
          CHECK(t.step_mm == Approx(dist(bp(t, "B3"), lower)).margin(1e-9));
          CHECK(t.gap_mm == Approx(dist(bp(t, "B2"), lower)).margin(1e-9));
          CHECK(t.step_mm > 0.9);
          break;
        }
        case vc::Joint::Butt: {
          const Vec2 b1 = bp(t, "B1"), b3 = bp(t, "B3");
          CHECK((on_lines(d, b1, vc::kFaceTop1, vc::kFaceEdge1) || on_lines(d, b1, vc::kFaceTop2, vc::kFaceEdge2)));
          CHECK((on_lines(d, b3, vc::kFaceTop1, vc::kFaceEdge1) || on_lines(d, b3, vc::kFaceTop2, vc::kFaceEdge2)));
          // The gap centre on the lower plate's top line, midway between the edges along it.
          const Line top1 = *face_line(d, vc::kFaceTop1), top2 = *face_line(d, vc::kFaceTop2);
          const Line& lower = depth_of(top1) >= depth_of(top2) ? top1 : top2;
          const Line& higher = depth_of(top1) >= depth_of(top2) ? top2 : top1;
          CHECK(dist(track, lower) < 1e-9);
          CHECK(std::abs((track - 0.5 * (b1 + b3)).dot(lower.d)) < 1e-9);
          CHECK((bp(t, "B2") - track).norm() == 0);
          CHECK(t.gap_mm == Approx(std::abs((b3 - b1).dot(lower.d))).margin(1e-9));
          CHECK(t.mismatch_mm == Approx(dist(higher.p, lower)).margin(1e-9));
          CHECK((t.gap_mm > 0.05 || t.mismatch_mm > 0.05 || t.has_tag("rounded_edges") ||
                 t.has_tag("chamfered_edges")));  // never nothing to see
          break;
        }
        case vc::Joint::VGroove: {
          const Vec2 b2 = bp(t, "B2"), b4 = bp(t, "B4");
          CHECK((on_lines(d, bp(t, "B1"), vc::kFaceTop1, vc::kFaceBevel1) ||
                 on_lines(d, bp(t, "B1"), vc::kFaceTop2, vc::kFaceBevel2)));
          CHECK((on_lines(d, bp(t, "B5"), vc::kFaceTop1, vc::kFaceBevel1) ||
                 on_lines(d, bp(t, "B5"), vc::kFaceTop2, vc::kFaceBevel2)));
          const Line bevel1 = *face_line(d, vc::kFaceBevel1), bevel2 = *face_line(d, vc::kFaceBevel2);
          CHECK(std::min(dist(b2, bevel1), dist(b2, bevel2)) < 1e-9);
          CHECK(std::min(dist(b4, bevel1), dist(b4, bevel2)) < 1e-9);
          if (t.param("root_face_mm") > 0) {  // root edge: bevel x root face
            CHECK((on_lines(d, b2, vc::kFaceBevel1, vc::kFaceRoot1) || on_lines(d, b2, vc::kFaceBevel2, vc::kFaceRoot2)));
            CHECK((on_lines(d, b4, vc::kFaceBevel1, vc::kFaceRoot1) || on_lines(d, b4, vc::kFaceBevel2, vc::kFaceRoot2)));
          }
          // Track: on the level of the lower root edge, midway along the plates.
          const Line top = *face_line(d, vc::kFaceTop1);
          const double depth2 = std::abs(vc::cross(top.d, -b2)), depth4 = std::abs(vc::cross(top.d, -b4));
          const Vec2 lower = depth2 >= depth4 ? b2 : b4;
          CHECK(std::abs(vc::cross(top.d, track - lower)) < 1e-9);
          CHECK(std::abs((track - 0.5 * (b2 + b4)).dot(top.d)) < 1e-9);
          CHECK((bp(t, "B3") - track).norm() == 0);
          CHECK(t.depth_mm > 2.9);
          CHECK(t.angle_deg > 30);
          CHECK(t.angle_deg < 100);
          CHECK(t.area_mm2 > 0);
          break;
        }
        default: FAIL("not one of kAllJoints");  // the grooves: grooves_test.cpp
      }
    }
  }
}

TEST_CASE("joints: truth values stay within the oblique cut's stretch of the drawn ones", "[corpus][joints]") {
  // The laser plane cuts the prism obliquely (pitch and yaw up to 15 degrees):
  // lengths in the slice grow by a factor between 1 and 1 / cos^2(15 deg).
  const double k = 1.0 / (std::cos(15 * std::numbers::pi / 180) * std::cos(15 * std::numbers::pi / 180)) + 1e-9;
  for (std::uint64_t seed = 1; seed <= 500; ++seed) {
    const vc::Truth b = vc::make_profile(vc::Joint::Butt, seed, ideal()).truth;
    const double g = b.param("gap_joint_mm"), m = std::abs(b.param("mismatch_joint_mm"));
    CHECK(b.param("gap_faces_mm") >= g - 1e-9);
    CHECK(b.param("gap_faces_mm") <= g * k + 1e-9);
    CHECK(b.mismatch_mm >= m - 1e-9);
    CHECK(b.mismatch_mm <= m * k + 1e-9);
    const vc::Truth v = vc::make_profile(vc::Joint::VGroove, seed, ideal()).truth;
    const double depth = v.param("thickness_mm") - v.param("root_face_mm");
    CHECK(v.depth_mm >= depth - 1e-9);
    CHECK(v.depth_mm <= depth * k);
    const vc::Truth l = vc::make_profile(vc::Joint::Lap, seed, ideal()).truth;
    const double step =
        l.param("gap_joint_mm") + l.param("upper_thickness_mm") * std::cos(l.param("tilt_deg") * std::numbers::pi / 180);
    CHECK(l.step_mm >= step - 1e-9);
    CHECK(l.step_mm <= step * k);
  }
}

TEST_CASE("joints: every joint and variant for 1000 seeds gives finite truth and no exception", "[corpus][joints]") {
  for (vc::Joint joint : vc::kAllJoints) {
    std::vector<std::string> variants = vc::variant_names(joint);
    variants.push_back("decoy");
    variants.push_back("none");  // every probability 0
    for (const std::string& variant : variants) {
      vc::Options o;
      o.columns = 256;  // the column count is drawn apart from the rest: same scenes, faster
      o.noise_mm = -1;  // random levels
      if (variant == "decoy") {
        o.decoy = true;
      } else if (variant == "none") {
        for (const auto& n : vc::variant_names(joint)) o.probability[n] = 0.0;
      } else {
        o.probability[variant] = 1.0;
      }
      int tagged = 0;
      for (std::uint64_t seed = 1; seed <= 1000; ++seed) {
        INFO(vc::joint_name(joint) << " variant " << variant << " seed " << seed);
        vc::Profile p;
        REQUIRE_NOTHROW(p = vc::make_profile(joint, seed, o));
        const vc::Truth& t = p.truth;
        REQUIRE(std::isfinite(t.track_y_mm));
        REQUIRE(std::isfinite(t.track_z_mm));
        REQUIRE(std::isfinite(t.gap_mm));
        REQUIRE(t.gap_mm >= 0);
        REQUIRE(std::isfinite(t.angle_deg));
        REQUIRE(std::isfinite(t.standoff_mm));
        const bool has_mismatch = joint == vc::Joint::Butt || joint == vc::Joint::VGroove;
        REQUIRE(std::isfinite(t.mismatch_mm) == has_mismatch);
        REQUIRE(std::isfinite(t.step_mm) == (joint == vc::Joint::Lap));
        REQUIRE(std::isfinite(t.depth_mm) == (joint == vc::Joint::VGroove));
        REQUIRE(!t.break_points.empty());
        for (const auto& [name, q] : t.break_points) {
          REQUIRE(std::isfinite(q[0]));
          REQUIRE(std::isfinite(q[1]));
        }
        for (const auto& [name, v] : t.params) REQUIRE(std::isfinite(v));
        REQUIRE(t.columns == 256);
        REQUIRE(p.y.size() == 256u);
        REQUIRE(t.standoff_mm > 40);
        REQUIRE(t.standoff_mm < 280);
        for (std::size_t i = 0; i < p.y.size(); ++i) {
          if (p.valid[i]) {
            REQUIRE(std::isfinite(p.y[i]));
            REQUIRE(p.z[i] > 0);
          } else {
            REQUIRE(std::isnan(p.y[i]));
            REQUIRE(std::isnan(p.z[i]));
          }
        }
        if (variant == "decoy") {
          REQUIRE(std::isfinite(t.decoy_y_mm));
          REQUIRE(std::hypot(t.decoy_y_mm - t.track_y_mm, t.decoy_z_mm - t.track_z_mm) > 19);
        } else {
          REQUIRE(std::isnan(t.decoy_y_mm));
        }
        if (variant == "none") {
          for (const char* tag : {"waviness", "quantized", "dropout_runs", "single_dropouts", "shadow", "mirrored",
                                  "gap", "tack_weld", "backing_bar", "rounded_edges", "chamfered_edges"})
            if (!(joint == vc::Joint::Butt && std::string(tag) == "gap")) REQUIRE_FALSE(t.has_tag(tag));
        }
        // A forced variant shows in the tags: reflections by direction, mirror
        // as "mirrored", a body only when it blocked a column.
        if (variant == "reflections")
          tagged += t.has_tag("reflection_front") || t.has_tag("reflection_behind");
        else
          tagged += t.has_tag(variant == "mirror" ? "mirrored" : variant);
      }
      INFO(vc::joint_name(joint) << " variant " << variant << " tagged " << tagged);
      if (variant == "none") continue;
      // Chamfers yield to rounding (README: set rounded_edges to 0 to force them).
      const int expected = variant == "chamfered_edges" ? 600 : variant == "shadow" || variant == "reflections" ? 800 : 1000;
      CHECK(tagged >= expected);
    }
  }
}

TEST_CASE("joints: a tack weld over the root hides the joint", "[corpus][joints]") {
  for (vc::Joint joint : {vc::Joint::Fillet, vc::Joint::Butt, vc::Joint::VGroove}) {
    vc::Options o = ideal();
    o.probability["tack_weld"] = 1.0;
    for (std::uint64_t seed = 1; seed <= 100; ++seed) {
      const vc::Truth t = vc::make_profile(joint, seed, o).truth;
      INFO(vc::joint_name(joint) << " seed " << seed);
      CHECK(t.has_tag("tack_weld"));
      CHECK(t.has_tag("joint_hidden"));
      CHECK(t.has_tag("joint_covered"));
    }
  }
}

TEST_CASE("joints: a shadowing body hides the columns behind it", "[corpus][joints]") {
  int shadowed = 0;
  for (std::uint64_t seed = 1; seed <= 200; ++seed) {
    vc::Options o;
    o.keep_debug = true;
    o.probability["shadow"] = 1.0;
    const vc::Profile p = vc::make_profile(vc::Joint::Butt, seed, o);
    int body = 0, run = 0, longest = 0;
    for (std::size_t i = 0; i < p.y.size(); ++i) {
      const bool b = p.debug->status[i] == vc::kBodyShadow;
      body += b;
      run = b ? run + 1 : 0;
      longest = std::max(longest, run);
      if (b) CHECK(p.valid[i] == 0);
    }
    CHECK((body > 0) == p.truth.has_tag("shadow"));
    if (body > 0) {
      ++shadowed;
      CHECK(longest >= 3);  // a run, not single columns
    }
  }
  CHECK(shadowed > 150);
}

TEST_CASE("joints: ideal joints without variants are mostly visible", "[corpus][joints]") {
  // With the camera in the laser plane a groove's far bevel can be hidden (and
  // a steep corner's far face), but a plain joint seen from its natural side
  // mostly shows what a reading needs.
  for (vc::Joint joint : vc::kAllJoints) {
    vc::Options o = ideal();
    for (const auto& n : vc::variant_names(joint)) o.probability[n] = 0.0;
    int hidden = 0;
    for (std::uint64_t seed = 1; seed <= 200; ++seed) hidden += vc::make_profile(joint, seed, o).truth.has_tag("joint_hidden");
    INFO(vc::joint_name(joint) << " hidden " << hidden);
    CHECK(hidden < (joint == vc::Joint::VGroove ? 120 : joint == vc::Joint::Corner ? 25 : 10));
  }
}

TEST_CASE("joints: bad options are refused", "[corpus][joints]") {
  vc::Options o;
  o.probability["backing_bar"] = 1.0;
  CHECK_THROWS_AS(vc::make_profile(vc::Joint::Fillet, 1, o), std::invalid_argument);  // no backing bar on a fillet
  vc::Options p;
  p.probability["gap"] = 1.5;
  CHECK_THROWS_AS(vc::make_profile(vc::Joint::Butt, 1, p), std::invalid_argument);
  vc::Options c;
  c.columns = 5;
  CHECK_THROWS_AS(vc::make_profile(vc::Joint::Butt, 1, c), std::invalid_argument);
  vc::Options n;
  n.noise_mm = std::nan("");
  CHECK_THROWS_AS(vc::make_profile(vc::Joint::Butt, 1, n), std::invalid_argument);
  CHECK(vc::joint_from_name("v-groove") == vc::Joint::VGroove);
  CHECK_FALSE(vc::joint_from_name("tee").has_value());
}
