// The tracker on the independent corpus (tests/corpus), held-out seeds
// (from 1,000,001; the rules were developed on seeds 1-300): the figures of
// docs/JOINTS.md "Scores" may not get worse. Issue 17's targets (no false
// read in 10,000 profiles per joint, right >= 98 % ideal and >= 95 % noisy)
// are not met yet; the limits below are today's figures with a little room,
// to be tightened as the tracker improves.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <initializer_list>
#include <map>
#include <string>
#include <tuple>

#include "corpus_score.h"

using namespace vts_score;

namespace {

struct Limit {
  int max_false;       // of 2,100 profiles (300 per level)
  double min_right;    // share of the profiles whose joint is in view
};

// Each of the corpus profiles (seed, noise level) of `joint` has a tack
// weld over the joint (hidden: any `ok` is false) and must be rejected.
template <std::size_t N>
void check_tack_rejected(vc::Joint joint, const std::pair<std::uint64_t, double> (&cases)[N]) {
  for (const auto& [seed, level] : cases) {
    const ReadOne one = read_one(joint, seed, level);
    INFO(vc::joint_name(joint) << " seed " << seed << " level " << level << ": " << tk::to_string(one.result.status)
                               << " " << one.result.reason << ", error " << one.scored.track_error_mm);
    CHECK(one.profile.truth.has_tag("tack_weld"));
    CHECK(one.profile.truth.has_tag("joint_hidden"));
    CHECK(one.result.status == tk::TrackStatus::Rejected);
  }
}

// Each development profile (seed, geometry only) of `joint` reads right,
// within `max_error_mm`, with the default parameters, and with the option
// under test off (`off`) reads as `outcome_off`.
void check_right_with_option(vc::Joint joint, std::initializer_list<std::uint64_t> seeds, double max_error_mm,
                             const tk::TrackerParams& off, tk::Outcome outcome_off) {
  for (const std::uint64_t seed : seeds) {
    const ReadOne one = read_one(joint, seed, kIdealLevel);
    INFO(vc::joint_name(joint) << " seed " << seed << ": " << tk::to_string(one.result.status) << " "
                               << one.result.reason << ", error " << one.scored.track_error_mm);
    CHECK(one.scored.outcome == tk::Outcome::Right);
    CHECK(one.scored.track_error_mm < max_error_mm);
    CHECK(read_one(joint, seed, kIdealLevel, off).scored.outcome == outcome_off);
  }
}

}  // namespace

TEST_CASE("corpus: the tracker's scores do not get worse", "[tracker][corpus]") {
  RunOptions o;
  o.first_seed = 1000001;
  o.profiles = 300;
  const tk::ScoreTable table = run(o);
  WARN("\n" << table.markdown());
  const std::map<tk::JointType, Limit> limits = {
      {tk::JointType::Fillet, {0, 0.96}},   {tk::JointType::Corner, {5, 0.59}},
      {tk::JointType::Lap, {0, 0.65}},      {tk::JointType::Butt, {13, 0.73}},
      {tk::JointType::VGroove, {37, 0.74}},
  };
  for (const auto& [joint, limit] : limits) {
    const tk::Tally t = table.total(joint);
    INFO(tk::to_string(joint) << ": " << t.false_reads << " false reads, " << t.right << " right of " << t.visible());
    REQUIRE(t.profiles == 2100);
    CHECK(t.false_reads <= limit.max_false);
    CHECK(static_cast<double>(t.right) / t.visible() >= limit.min_right);
  }
}

TEST_CASE("corpus: the stated track error is not overconfident", "[tracker][corpus][localization]") {
  // TrackResult::track_sigma_mm against the corpus' truth: of the readings
  // `ok` with the joint in view, all seven levels, development seeds 1-150,
  // the share more than 3 stated rms off the truth (a Gaussian's: 0.3 %
  // along one line, 1.1 % circular; the corpus' parts do what no fit sees,
  // so more). Session 30's figures with a little room; before it (the fits
  // alone) corner 22 %, lap 34 %, butt 43 %, bevel 23 %, U 30 %, J 18 %,
  // thick v-groove 16 % on seeds 1-300 (docs/JOINTS.md "Localization").
  RunOptions o;
  o.first_seed = 1;
  o.profiles = 150;
  const std::pair<vc::Joint, double> limits[] = {
      {vc::Joint::Fillet, 0.06}, {vc::Joint::Corner, 0.12}, {vc::Joint::Lap, 0.06},
      {vc::Joint::Butt, 0.10},   {vc::Joint::VGroove, 0.12}, {vc::Joint::Bevel, 0.10},
      {vc::Joint::UGroove, 0.22}, {vc::Joint::JGroove, 0.13}, {vc::Joint::VGrooveThick, 0.07},
  };
  for (const auto& [joint, limit] : limits) {
    o.joints = {joint};
    int read = 0, over = 0;
    run(o, {}, [&](const vc::Profile& p, const tk::TrackResult& r, const tk::Scored& s) {
      if (r.status != tk::TrackStatus::Ok || p.truth.has_tag("joint_hidden") || p.truth.has_tag("notch_unseen") ||
          !std::isfinite(r.track_sigma_mm))
        return;
      ++read;
      over += s.track_error_mm > 3.0 * r.track_sigma_mm;
    });
    INFO(vc::joint_name(joint) << ": " << over << " of " << read << " readings more than 3 stated rms off");
    REQUIRE(read >= 200);
    CHECK(over <= limit * read);
  }
}

TEST_CASE("corpus: the groove model's scores do not get worse", "[tracker][corpus][groove]") {
  // Issue 18's grooves in the corpus (tests/corpus/grooves.cpp: bevel, U, J
  // and v-grooves in thick plate, most with beads laid), held-out seeds, 100
  // profiles per level (the corpus' thick parts are slow to cast). The
  // thick v-groove is read with --fill; its rows are the v-groove's.
  RunOptions o;
  o.first_seed = 1000001;
  o.profiles = 100;
  const std::pair<vc::Joint, Limit> limits[] = {
      {vc::Joint::Bevel, {4, 0.68}},
      {vc::Joint::UGroove, {0, 0.47}},
      {vc::Joint::JGroove, {3, 0.63}},
      {vc::Joint::VGrooveThick, {2, 0.759}},
  };
  for (const auto& [joint, limit] : limits) {
    o.joints = {joint};
    const tk::Tally t = run(o).total(joint_of(joint));
    INFO(vc::joint_name(joint) << ": " << t.false_reads << " false reads, " << t.right << " right of " << t.visible());
    REQUIRE(t.profiles == 700);
    CHECK(t.false_reads <= limit.max_false);
    CHECK(static_cast<double>(t.right) / t.visible() >= limit.min_right);
  }
}

TEST_CASE("corpus: fillets up to 0.1 mm noise: 2 false reads in 6,000", "[tracker][corpus]") {
  // Both are one profile (seed 2000922 at 0.05 and 0.1 mm): a tack weld in
  // the root, most of the profile out of range, the tack's 9 points read as
  // the flange. Any other false read fails.
  RunOptions o;
  o.joints = {vc::Joint::Fillet};
  o.levels = {kIdealLevel, 0.0, 0.005, 0.02, 0.05, 0.1};
  o.first_seed = 2000001;
  o.profiles = 1000;
  const tk::Tally t = run(o).total(tk::JointType::Fillet);
  CHECK(t.false_reads <= 2);
}

TEST_CASE("corpus: butt profiles whose true joint was never a candidate", "[tracker][corpus]") {
  // Development seeds with the corpus' imperfections that were false reads
  // 23-60 mm off: a reflection in front of the gap ruled the true joint out
  // (176, 267), or a dropout run on one plate was read while the other
  // plate, 0.6-1.9 mm off its line, was left unexplained (137, 250). None
  // may be a false read now.
  // And a gap whose rays found the backing bar and also missing columns,
  // priced as one dropout run where a dropout shows no points behind the
  // plates, so a dropout run 8-39 mm away outranked it (62, 270).
  const std::pair<std::uint64_t, double> cases[] = {{137, 0.0}, {176, 0.05}, {250, 0.0}, {267, 0.0},
                                                    {62, 0.0},  {270, 0.0}};
  for (const auto& [seed, noise] : cases) {
    const ReadOne one = read_one(vc::Joint::Butt, seed, noise);
    const tk::TrackResult& r = one.result;
    INFO("seed " << seed << ": " << tk::to_string(r.status) << " " << r.reason << ", error "
                 << one.scored.track_error_mm);
    CHECK(one.scored.outcome != tk::Outcome::False);
  }
}

TEST_CASE("corpus: butt gaps between rounded edges", "[tracker][corpus]") {
  // Development seeds, each a false read 1.4-105 mm off: the points of a
  // rounded edge, between a plate's last point and its edge, were weighed as
  // a reflection cluster under either reading, so a 5-column dropout run 105
  // mm away (179) or a reading 1.4 mm off (188) outranked the true gap. They
  // are the joint's, as its walls are: the true gap is now as strong as the
  // other reading, and the profile is rejected as ambiguous, never read at
  // the wrong place.
  const std::pair<std::uint64_t, double> cases[] = {{179, 0.0}, {188, 0.0}, {188, 0.02}, {270, 0.02}};
  for (const auto& [seed, noise] : cases) {
    const ReadOne one = read_one(vc::Joint::Butt, seed, noise);
    const tk::TrackResult& r = one.result;
    INFO("seed " << seed << " noise " << noise << ": " << tk::to_string(r.status) << " " << r.reason << ", error "
                 << one.scored.track_error_mm);
    CHECK(one.scored.outcome != tk::Outcome::False);
  }
}

TEST_CASE("corpus: laps whose upper edge is chamfered and whose face shows below it", "[tracker][corpus]") {
  // Development seeds, geometry only: a few face points show below the
  // chamfer. The wall was fitted to chamfer and face points together, and
  // its foot lay 1-1.25 mm off; the chamfer's points (they drop no more than
  // they run on from the plate's end) are no part of the face.
  for (const std::uint64_t seed : {80u, 112u, 162u}) {
    const ReadOne one = read_one(vc::Joint::Lap, seed, kIdealLevel);
    INFO("seed " << seed << ": " << tk::to_string(one.result.status) << " " << one.result.reason);
    REQUIRE(one.result.status == tk::TrackStatus::Ok);
    CHECK(one.scored.track_error_mm < 0.1);
  }
}

TEST_CASE("corpus: a lap whose upper edge is chamfered and whose face is hidden", "[tracker][corpus]") {
  // Development seed 18, geometry only: the upper plate's top edge is
  // chamfered, its edge face hidden from the camera, the plates tilted about
  // 8 degrees. The chamfer's points are no face points: the face passes the
  // chamfer's last point, so the top edge is where the plate's line meets
  // the face there (not the chamfer points' mean, which put the foot 1.1 mm
  // off).
  const ReadOne one = read_one(vc::Joint::Lap, 18, kIdealLevel);
  INFO(tk::to_string(one.result.status) << " " << one.result.reason);
  REQUIRE(one.result.status == tk::TrackStatus::Ok);
  CHECK(one.scored.track_error_mm < 0.3);
}

TEST_CASE("corpus: closed corners with rounded or chamfered edges are not read below the apex", "[tracker][corpus]") {
  // Development seeds, geometry only and noise 0: both outer edges rounded
  // (31, 64) or chamfered (55) at a closed apex leave a shallow notch there,
  // which was read as a gap 1.2-1.4 mm below the apex. A closed corner with
  // such edges looks like that notch: ambiguous (rejected) or right, never
  // a false read.
  for (const std::uint64_t seed : {31u, 55u, 64u}) {
    for (const double level : {kIdealLevel, 0.0}) {
      const ReadOne one = read_one(vc::Joint::Corner, seed, level);
      INFO("seed " << seed << " level " << level << ": " << tk::to_string(one.result.status) << " "
                   << one.result.reason << ", error " << one.scored.track_error_mm);
      CHECK(one.scored.outcome != tk::Outcome::False);
    }
  }
}

TEST_CASE("corpus: a shallow notch closed at its bottom is read at the apex", "[tracker][corpus]") {
  // Development seeds, geometry only: closed corners whose outer edges are
  // chamfered (2, 14, 30) or rounded (69, 80), every ray between the faces
  // on the surface and the notch's flanks meeting at a bottom. The open
  // reading put the track point between the notch's edges, 0.14-0.82 mm
  // below the apex, at confidence 1 (imprecise); the closed reading is the
  // truth (JointTruth: B1 = B3 = the apex) within 0.001 mm, gap 0. (With
  // the end faces fitted, CornerParams::fit_end_faces, the open reading of
  // seed 69 is right too: its arcs' ends fit the faces; "off" is the tracker
  // before both.)
  tk::TrackerParams off;
  off.corner.closed_notch = false;
  off.corner.fit_end_faces = false;
  check_right_with_option(vc::Joint::Corner, {2, 14, 30, 69, 80}, 0.001, off, tk::Outcome::Imprecise);
  for (const std::uint64_t seed : {2u, 14u, 30u, 69u, 80u}) {
    INFO("seed " << seed);
    CHECK(read_one(vc::Joint::Corner, seed, kIdealLevel).result.gap_mm == 0.0);
  }
}

TEST_CASE("corpus: a closed corner's wide or finely cut notch is read at the apex", "[tracker][corpus]") {
  // Development seeds, geometry only, rejected as "unexplained" before: a
  // flat corner's chamfers leaving a notch 3.2 mm wide, wider than a gap's
  // accept range (10); rounded edges whose arcs the segmentation cut in
  // more than two pieces (9, 13). The closed reading explains its notch
  // (the edges' rounding or chamfer) and is right within 0.002 mm; with
  // CornerParams::closed_notch off they are rejected again.
  tk::TrackerParams off;
  off.corner.closed_notch = false;
  check_right_with_option(vc::Joint::Corner, {9, 10, 13}, 0.002, off, tk::Outcome::Rejected);
}

TEST_CASE("corpus: an open corner's edges from its mitred end faces (session 27)", "[tracker][corpus]") {
  // Seeds never read before (5,000,001 on), geometry only: corners with a
  // gap between mitred ends. With the end faces taken square to the outer
  // faces, the points seen on a mitred end face were projected square onto
  // the outer face and the edges read off (imprecise, 0.12 mm off), or the
  // reading explained too few points (rejected). Fitted as seen, or placed
  // in the interval a rounding or chamfer leaves (CornerParams::
  // fit_end_faces), they read right.
  tk::TrackerParams off;
  off.corner.fit_end_faces = false;
  for (const std::uint64_t seed : {5000538u, 5001037u, 5001357u}) {
    const ReadOne one = read_one(vc::Joint::Corner, seed, kIdealLevel);
    INFO("seed " << seed << ": " << tk::to_string(one.result.status) << " " << one.result.reason << ", error "
                 << one.scored.track_error_mm);
    CHECK(one.profile.truth.has_tag("gap"));
    CHECK(one.scored.outcome == tk::Outcome::Right);
    CHECK(one.scored.track_error_mm < 0.03);
    CHECK(read_one(vc::Joint::Corner, seed, kIdealLevel, off).scored.outcome != tk::Outcome::Right);
  }
}

TEST_CASE("corpus: a U's or J's radius beside a closed root's mismatch is no notch (session 28)",
          "[tracker][corpus][groove]") {
  // Seeds never read before (5,000,001 on), geometry only. U grooves closed
  // at the root with the plates' mismatch (1.9 mm), a J with a mismatch
  // over a backing bar: the lower plate's half of the bottom, a radius
  // 1-2 mm deep and 3-4 mm wide, was closed at its shoulders as a root
  // gap's notch, and B3 lay on the closing line, 1.4-1.9 mm from the root
  // (false reads). Kept as seen (GrooveParams::radius_not_notch), the line
  // midway between the toes meets the radius: right.
  tk::TrackerParams off;
  off.groove.radius_not_notch = false;
  const std::pair<vc::Joint, std::uint64_t> cases[] = {
      {vc::Joint::UGroove, 5000197}, {vc::Joint::UGroove, 5001214}, {vc::Joint::JGroove, 5000878}};
  for (const auto& [joint, seed] : cases) {
    const ReadOne one = read_one(joint, seed, kIdealLevel);
    INFO(vc::joint_name(joint) << " seed " << seed << ": " << tk::to_string(one.result.status) << " "
                               << one.result.reason << ", error " << one.scored.track_error_mm);
    CHECK(one.profile.truth.has_tag("mismatch"));
    CHECK(one.scored.outcome == tk::Outcome::Right);
    CHECK(one.scored.track_error_mm < 0.02);
    CHECK(read_one(joint, seed, kIdealLevel, off).scored.outcome == tk::Outcome::False);
  }
}

TEST_CASE("corpus: a U's track point at its closed root's step is uncertain (session 28)",
          "[tracker][corpus][groove]") {
  // Seeds never read before, geometry only: U grooves closed at the root
  // with the plates' mismatch, the step between the two halves' bottoms
  // (1.15 and 1.26 mm) within 3 standard deviations of B3's place along
  // the tops (midway between the toes): the line from there meets one level
  // or the other as the toes move by less than their uncertainty. With the lower
  // half closed as a notch (both options off) they were false reads 1.1-1.3
  // mm off. At the step B3's depth is not known (GrooveParams::
  // bottom_steps): rejected as uncertain.
  tk::TrackerParams neither;
  neither.groove.bottom_steps = false;
  neither.groove.radius_not_notch = false;
  for (const std::uint64_t seed : {5000296u, 5000427u}) {
    const ReadOne one = read_one(vc::Joint::UGroove, seed, kIdealLevel);
    INFO("seed " << seed << ": " << tk::to_string(one.result.status) << " " << one.result.reason);
    CHECK(one.profile.truth.has_tag("mismatch"));
    CHECK(one.result.status == tk::TrackStatus::Rejected);
    CHECK(one.result.reason.find("at a step") != std::string::npos);
    CHECK(read_one(vc::Joint::UGroove, seed, kIdealLevel, neither).scored.outcome == tk::Outcome::False);
  }
}

TEST_CASE("corpus: a lap's upper plate resting on its edge, off parallel", "[tracker][corpus]") {
  // Development seeds, geometry only, the upper plate tilted 0.5-3 degrees
  // (the corpus' `tilt`), read within 0.1 mm, were rejected as
  // "unexplained" (its points 0.02-0.04 mm off the line parallel to the
  // lower plate's, over the surface tolerance's floor of 0.02 mm). Weighed on
  // the plates' own lines (LapParams::tilted_upper) they are right; held
  // parallel, rejected.
  for (const std::uint64_t seed : {8u, 11u, 17u})
    CHECK(read_one(vc::Joint::Lap, seed, kIdealLevel).profile.truth.has_tag("tilt"));
  tk::TrackerParams parallel;
  parallel.lap.tilted_upper = false;
  check_right_with_option(vc::Joint::Lap, {8, 11, 17}, 0.1, parallel, tk::Outcome::Rejected);
}

TEST_CASE("corpus: a fillet's web with a rounded or chamfered bottom edge", "[tracker][corpus]") {
  // Development seeds, geometry only, rejected as "unexplained" before:
  // the web's rounded (52, 56) or chamfered (63, 225) bottom edge is a short
  // segment of its own between the web and the flange, and only
  // neighbouring segments were paired (the edge's arc with the flange, the
  // web's points then unexplained). Paired across it
  // (FilletParams::across_edge) the root is read within 0.005 mm of the
  // truth (flange line x the web's open face line); with it off, rejected.
  tk::TrackerParams off;
  off.fillet.across_edge = false;
  check_right_with_option(vc::Joint::Fillet, {52, 56, 63, 225}, 0.005, off, tk::Outcome::Rejected);
}

TEST_CASE("corpus: a v-groove's lower bevel reaches past the crossing of the bevels' lines", "[tracker][corpus]") {
  // Development seeds, geometry only, a mismatch with a root face: the lower
  // plate's bevel goes on below where the two bevels' lines cross (the
  // other plate's root face stands there). Its points past the crossing
  // were trimmed off as another surface's, and its root edge put up to
  // 0.5 mm up the bevel (imprecise, 0.26-0.48 mm). Kept
  // (VGrooveParams::keep_past_crossing), the track point is within 0.06 mm.
  tk::TrackerParams off;
  off.vgroove.keep_past_crossing = false;
  check_right_with_option(vc::Joint::VGroove, {13, 18, 19, 30, 78}, 0.06, off, tk::Outcome::Imprecise);
}

TEST_CASE("corpus: grooves whose track point was read off the bottom", "[tracker][corpus][groove]") {
  // Development seeds, each a false read 1.5-20 mm off: B3 on a line from a
  // bevel's seen end to a hidden toe (bevel 272, geometry only), on a
  // reflection cluster over the bottom (bevel 3, thick V 265), or a bead's
  // crest or flat cap taken for a plate top (bevel 39; J 96 at 0.05 mm).
  // Bevel 4 and 7 at 0.2 mm (8.7-10.5 mm off): a bump of a plate top read
  // as a wall 0.1-0.4 mm high put the real wall into the "bottom", and B3
  // halfway up it (GrooveParams::min_track_depth_share).
  const std::tuple<vc::Joint, std::uint64_t, double> cases[] = {
      {vc::Joint::Bevel, 272, kIdealLevel}, {vc::Joint::Bevel, 3, 0.0},     {vc::Joint::Bevel, 39, 0.0},
      {vc::Joint::VGrooveThick, 265, 0.0}, {vc::Joint::JGroove, 96, 0.05}, {vc::Joint::Bevel, 4, 0.2},
      {vc::Joint::Bevel, 7, 0.2}};
  for (const auto& [joint, seed, level] : cases) {
    const ReadOne one = read_one(joint, seed, level);
    INFO(vc::joint_name(joint) << " seed " << seed << ": " << tk::to_string(one.result.status) << " "
                               << one.result.reason << ", error " << one.scored.track_error_mm);
    CHECK(one.scored.outcome != tk::Outcome::False);
  }
}

TEST_CASE("corpus: a groove wall going on below its toe", "[tracker][corpus][groove]") {
  // Development seeds, each a false read 1.9-15.7 mm off before: a piece of
  // a wall (its bent top, or one of the pieces noise cut it into) was read
  // as the whole wall, and the wall going on below it as the bottom, so the
  // toe lay high on the wall and the track point midway between the toes
  // on the wall or beside the root (bevel 101 and 147, J 204 and 162 at 0.2
  // mm noise, J 234 ideal). The bottom beside a toe running straight down
  // at the wall's angle, deeper than the wall read, says so: none may be a
  // false read.
  const std::tuple<vc::Joint, std::uint64_t, double> cases[] = {
      {vc::Joint::Bevel, 101, 0.2}, {vc::Joint::Bevel, 147, 0.2}, {vc::Joint::JGroove, 204, 0.2},
      {vc::Joint::JGroove, 162, 0.2}, {vc::Joint::JGroove, 234, 0.0}};
  for (const auto& [joint, seed, level] : cases) {
    const ReadOne one = read_one(joint, seed, level);
    INFO(vc::joint_name(joint) << " seed " << seed << " level " << level << ": " << tk::to_string(one.result.status)
                               << " " << one.result.reason << ", error " << one.scored.track_error_mm);
    CHECK(one.scored.outcome != tk::Outcome::False);
  }
}

TEST_CASE("corpus: a groove's track point on a step in its bottom", "[tracker][corpus][groove]") {
  // Development seeds, bevels with a root gap, each a false read 1.1-2.0 mm
  // off before: B3 lay between two neighbours on the bottom 1.6-3.1 mm apart
  // in depth with nothing seen between them (256 at 0.05 and 0.1 mm: the
  // square wall's seen end, 3 mm above the other toe, with the root between
  // unseen; 78 at 0.2 mm: a dropout run over the bottom). Its depth there
  // is not known: none may be a false read.
  const std::pair<std::uint64_t, double> cases[] = {{256, 0.05}, {256, 0.1}, {78, 0.2}};
  for (const auto& [seed, level] : cases) {
    const ReadOne one = read_one(vc::Joint::Bevel, seed, level);
    INFO("seed " << seed << " level " << level << ": " << tk::to_string(one.result.status) << " "
                 << one.result.reason << ", error " << one.scored.track_error_mm);
    CHECK(one.scored.outcome != tk::Outcome::False);
  }
}

TEST_CASE("corpus: a thick groove's bead cap is no plate top for the v-groove template", "[tracker][corpus][groove]") {
  // Development seeds, thick v-grooves with beads laid (--fill), each a
  // false read 2.9-24 mm off: the groove model had no reading, and the
  // v-groove template paired a bead's flat cap deep in the groove with the
  // real plate top as its tops (parallel, 20-70 mm apart), its V in the
  // fill. The tops must be one plane within the mismatch: without them the
  // template's reading does not stand with beads laid.
  const std::pair<std::uint64_t, double> cases[] = {{47, 0.02}, {130, 0.05}, {132, 0.05}, {12, 0.1},
                                                    {239, 0.1}, {87, 0.2},   {140, 0.2}};
  for (const auto& [seed, level] : cases) {
    const ReadOne one = read_one(vc::Joint::VGrooveThick, seed, level);
    INFO("seed " << seed << " level " << level << ": " << tk::to_string(one.result.status) << " "
                 << one.result.reason << ", error " << one.scored.track_error_mm);
    CHECK(one.scored.outcome != tk::Outcome::False);
  }
}

TEST_CASE("corpus: a fill's cap beside an unseen wall is no plate top for the v-groove template", "[tracker][corpus][groove]") {
  // Development seed 165 (thick v-groove nearly filled, beads laid): the
  // left wall, nearly along the rays, shows no points, so the groove model
  // has no reading; the template took the fill's surface for the left plate
  // top (parallel to the right top, 0.4 mm off it) and read a V between the
  // fill and the right wall, 15 mm from the joint. The real left top stands
  // 3.7 mm in front of that "top" just beyond its outer end: the reading is
  // refused (VGrooveParams::check_tops_outside). With the check off it is a
  // false read at 0.1 mm, so the test can fail.
  for (const double level : {0.1, 0.2}) {
    const ReadOne one = read_one(vc::Joint::VGrooveThick, 165, level);
    INFO("level " << level << ": " << tk::to_string(one.result.status) << " " << one.result.reason << ", error "
                  << one.scored.track_error_mm);
    CHECK(one.result.status == tk::TrackStatus::Rejected);
    CHECK(std::string(one.result.reason).find("inside a wider groove") != std::string::npos);
    tk::TrackerParams off;
    off.vgroove.check_tops_outside = false;
    const ReadOne without = read_one(vc::Joint::VGrooveThick, 165, level, off);
    if (level == 0.1) CHECK(without.scored.outcome == tk::Outcome::False);
  }
}

TEST_CASE("corpus: far butt readings whose rival is nearly as strong are ambiguous once calibrated", "[tracker][corpus]") {
  // Development seeds (seed, noise level), each a false read 4.8-105 mm off
  // at the raw posterior (ConfidenceParams::temperature 1, confidence
  // 0.93-0.98): a dropout run or a reflection read as the joint, with the
  // true joint (or as strong a reading) its rival. At the calibrated
  // temperature (docs/JOINTS.md "Calibration") the profile comes back
  // ambiguous.
  struct Case {
    vc::Joint joint;
    std::uint64_t seed;
    double level;
  };
  const Case cases[] = {{vc::Joint::Butt, 179, 0.02}, {vc::Joint::Butt, 179, 0.2}, {vc::Joint::Butt, 251, 0.1},
                        {vc::Joint::Butt, 188, 0.2},  {vc::Joint::VGroove, 47, 0.05}};
  tk::TrackerParams raw;
  raw.confidence.temperature = 1.0;
  // (Butt 251 at 0.1 mm is a tack weld over the joint, which the bump
  // rival rejects at either temperature: left out at T = 1, as it was when
  // the temperature was chosen.)
  raw.confidence.bump_rival = false;
  for (const Case& c : cases) {
    const ReadOne one = read_one(c.joint, c.seed, c.level);
    const ReadOne before = read_one(c.joint, c.seed, c.level, raw);
    INFO(vc::joint_name(c.joint) << " seed " << c.seed << " level " << c.level << ": "
                                 << tk::to_string(one.result.status) << " " << one.result.reason << "; at T = 1: "
                                 << tk::to_string(before.result.status) << ", error " << before.scored.track_error_mm);
    CHECK(before.scored.outcome == tk::Outcome::False);
    CHECK(one.scored.outcome != tk::Outcome::False);
    CHECK(one.result.reason.rfind("ambiguous", 0) == 0);
    CHECK(one.result.confidence < before.result.confidence);
  }
}

TEST_CASE("corpus: a plate top going on inside a groove, and toes a dropout hid", "[tracker][corpus][groove]") {
  // Development seeds, each a false read 8-54 mm off before: a dent, a
  // dropout's edge or a noisy piece in a plate top was read as a wall, and
  // the groove's real wall and the plate top beyond it as its bottom
  // (bevel 190 and 289, J 170, 294 and 44: GrooveParams::plate_level_mm),
  // or a fill surface longer than window_mm was paired with a plate top as
  // the tops (bevel 149: nothing may stand in front of the tops beyond
  // their outer ends). None may be a false read. Thick V 1 (0.02 mm noise):
  // a dropout hid the first wall's foot, and the toe taken at the wall's
  // last seen point, 4 mm up the wall, put the track point 1.1 mm off; the
  // toe is where the wall meets the bottom's line, and the reading right.
  // Thick V 23 (0.2 mm noise): with beads laid and no reading of the groove
  // model, the v-groove template's V in the noise of a plate, without plate
  // tops, stood 120 mm off. J 128 (0.1 mm): 5 points of a reflection
  // cluster 3.5 mm behind a plate, at 256 columns, were read as a groove
  // 170 mm from the joint (fewer than two walls' and one bottom point).
  const std::tuple<vc::Joint, std::uint64_t, double> cases[] = {
      {vc::Joint::Bevel, 190, 0.02},   {vc::Joint::Bevel, 289, 0.2},   {vc::Joint::JGroove, 170, 0.2},
      {vc::Joint::JGroove, 294, 0.2},  {vc::Joint::JGroove, 44, 0.2},  {vc::Joint::Bevel, 149, 0.2},
      {vc::Joint::VGrooveThick, 1, 0.02}, {vc::Joint::VGrooveThick, 23, 0.2}, {vc::Joint::JGroove, 128, 0.1}};
  for (const auto& [joint, seed, level] : cases) {
    const ReadOne one = read_one(joint, seed, level);
    INFO(vc::joint_name(joint) << " seed " << seed << ": " << tk::to_string(one.result.status) << " "
                               << one.result.reason << ", error " << one.scored.track_error_mm);
    CHECK(one.scored.outcome != tk::Outcome::False);
    if (joint == vc::Joint::VGrooveThick && seed == 1) CHECK(one.scored.outcome == tk::Outcome::Right);
  }
}

TEST_CASE("corpus: a lap's upper plate reaches past reflection clusters to its edge", "[tracker][corpus]") {
  // Development seeds, noise 0: a reflection cluster behind the lower plate
  // (201) or in front of the upper one (252) beside the upper plate's
  // hidden edge ended the plate there, 2.4-2.5 mm short of its edge.
  for (const std::uint64_t seed : {201u, 252u}) {
    const ReadOne one = read_one(vc::Joint::Lap, seed, 0.0);
    INFO("seed " << seed << ": " << tk::to_string(one.result.status) << " " << one.result.reason << ", error "
                 << one.scored.track_error_mm);
    CHECK(one.scored.outcome != tk::Outcome::False);
  }
}

TEST_CASE("corpus: a tack weld in a v-groove's root is not read as an open root", "[tracker][corpus]") {
  // Development seeds (seed, noise level), each a false read before the
  // open root's model check (VGrooveParams::check_root_cover): a tack weld
  // fills the root (the joint hidden, truth from the corpus' section), the
  // bevels end at its toes 1.0-1.25 mm above the root, and its cap between
  // them was read as the root opening. Each must now be rejected (the
  // reason reported is the best reading left's: the check takes the
  // template's reading out, and what remains is "unexplained" points or
  // "inside a wider groove").
  const std::pair<std::uint64_t, double> cases[] = {{116, kIdealLevel}, {281, kIdealLevel}, {116, 0.005},
                                                    {239, 0.02},        {255, 0.05}};
  check_tack_rejected(vc::Joint::VGroove, cases);
}

TEST_CASE("corpus: a tack weld's crest over a butt joint is not read as a plate", "[tracker][corpus]") {
  // Development seeds (seed, noise level), each a false read before the
  // butt plates' model check (ButtParams::check_plate_caps): a tack weld
  // covers the joint (hidden, truth from the corpus' section), and its
  // crest was read as a plate beside a step at the tack's foot or its
  // flank, 3.2-5.5 mm from the joint. Each must now be rejected (the reason
  // reported is the best reading left's).
  const std::pair<std::uint64_t, double> cases[] = {{19, 0.02}, {63, 0.1}};
  check_tack_rejected(vc::Joint::Butt, cases);
}

TEST_CASE("corpus: rival readings are weighed over the same points", "[tracker][corpus]") {
  // Development seeds (seed, noise level; -1: ideal), each a false read
  // before: a reading 1-60 mm from the joint outranked the true one because
  // each was weighed over its own window (a dropout run taken for a gap
  // priced the true gap's rays nowhere; a v-groove reading that sees fewer
  // of the bevels' points lost none for them). Weighed over the union of
  // their windows in one noise model, the two are as strong: the profile is
  // rejected as ambiguous, with the true joint among its readings (truth
  // from the corpus' section). Since a v-groove's plate tops must be one
  // plane, the v-groove's 36 and 113 read right (their false reading took a
  // bevel for a plate top) and 243 is rejected by the groove model beside
  // the template; since a point beside the joint counts on its own side's
  // plate only, the butt's 194 at 0.1 mm reads right, and since a run of
  // invalid columns may be one shadow (ConfidenceParams::shadow_weight),
  // the butt's 201 at noise 0 too. None may be a false
  // read, and a profile rejected as ambiguous must have the true joint
  // among its readings.
  struct Case {
    vc::Joint joint;
    std::uint64_t seed;
    double level;
  };
  const Case cases[] = {{vc::Joint::Butt, 201, 0.0},     {vc::Joint::Butt, 251, 0.0},
                        {vc::Joint::Butt, 257, 0.05},    {vc::Joint::Butt, 194, 0.1},
                        {vc::Joint::Butt, 267, 0.1},     {vc::Joint::VGroove, 36, kIdealLevel},
                        {vc::Joint::VGroove, 113, kIdealLevel}, {vc::Joint::VGroove, 243, 0.05},
                        {vc::Joint::VGroove, 208, 0.1},  {vc::Joint::VGroove, 295, 0.2}};
  for (const Case& c : cases) {
    const ReadOne one = read_one(c.joint, c.seed, c.level);
    const tk::TrackResult& r = one.result;
    INFO(vc::joint_name(c.joint) << " seed " << c.seed << " level " << c.level << ": " << tk::to_string(r.status)
                                 << " " << r.reason << ", error " << one.scored.track_error_mm);
    CHECK(one.scored.outcome != tk::Outcome::False);
    if (c.joint == vc::Joint::Butt && (c.seed == 194 || c.seed == 201)) {
      CHECK(one.scored.outcome == tk::Outcome::Right);
      continue;
    }
    if (c.joint == vc::Joint::VGroove && r.reason.rfind("ambiguous", 0) != 0) {
      CHECK((one.scored.outcome == tk::Outcome::Right || r.status == tk::TrackStatus::Rejected));
      continue;
    }
    CHECK(r.status == tk::TrackStatus::Rejected);
    CHECK(r.reason.rfind("ambiguous", 0) == 0);
    const tk::Vec2 truth(one.profile.truth.track_y_mm, one.profile.truth.track_z_mm);
    bool seen = false;
    for (const auto& rd : r.readings) seen = seen || (rd.track_point - truth).norm() <= 1.0;
    CHECK(seen);
  }
}

TEST_CASE("corpus: a tack weld's top is no plate where the surface beyond it lies on the other plate's line",
          "[tracker][corpus]") {
  // Development seeds, each a false read while a point beside the joint
  // could be explained by either plate's line: a butt's or v-groove's
  // plate read on a tack weld's top a few mm long, the real plate beyond
  // it at the other plate's level (explained by that plate, though on this
  // one's side). Weighed on its own side's plate, the surface beyond the
  // tack is unexplained: rejected.
  struct Case {
    vc::Joint joint;
    std::uint64_t seed;
    double level;
  };
  const Case cases[] = {{vc::Joint::Butt, 19, 0.1}, {vc::Joint::Butt, 102, 0.2}, {vc::Joint::VGroove, 279, 0.2}};
  tk::TrackerParams either;
  either.confidence.own_side_only = false;
  for (const Case& c : cases) {
    const ReadOne one = read_one(c.joint, c.seed, c.level);
    const ReadOne before = read_one(c.joint, c.seed, c.level, either);
    INFO(vc::joint_name(c.joint) << " seed " << c.seed << " level " << c.level << ": "
                                 << tk::to_string(one.result.status) << " " << one.result.reason
                                 << "; either plate: " << tk::to_string(before.result.status) << ", error "
                                 << before.scored.track_error_mm);
    CHECK(before.scored.outcome == tk::Outcome::False);
    CHECK(one.result.status == tk::TrackStatus::Rejected);
    CHECK(one.result.reason.rfind("unexplained", 0) == 0);
  }
}

TEST_CASE("corpus: butt false reads far from the joint on seeds never read before (session 26)", "[tracker][corpus]") {
  // Unseen seeds (5,000,001 on), noise 0, each read 20-62 mm from the
  // joint before this session's rules and no longer read there; each
  // case's rule off, it is a false read again.
  struct Case {
    std::uint64_t seed;
    const char* what;
    tk::TrackerParams without;
    tk::Outcome outcome;  // with every rule
    const char* reason;   // its start, if rejected
  };
  std::vector<Case> cases;
  // A 0.28 mm mismatch 8 mm from the profile's end: one segment, a dropout
  // run 37 mm away read as a tight gap. Now split there: right.
  tk::TrackerParams p1;
  p1.segmentation.segments.rough_step_either_side = false;
  p1.segmentation.segments.rough_split_best_fit = false;
  cases.push_back({5000758, "step point on its own side", p1, tk::Outcome::Right, ""});
  // A 0.3 mm mismatch on a wavy surface, the farthest point from the
  // chord 1 mm from it: cut at the least-squares place, the step is a
  // rival of the dropout run read 20.8 mm away.
  tk::TrackerParams p2;
  p2.segmentation.segments.rough_split_best_fit = false;
  cases.push_back({5000047, "least-squares step", p2, tk::Outcome::Rejected, "ambiguous"});
  // The joint under a clamp's shadow over coplanar plates, a dropout run
  // 34.7 mm away read as a tight gap: the shadow's columns may hide it.
  tk::TrackerParams p3;
  p3.confidence.hidden_in_unseen = false;
  cases.push_back({5000798, "joint under a shadow", p3, tk::Outcome::Rejected, "weak"});
  // A clamp's 4.7 mm shadow read as a gap 61.9 mm from the true one (its
  // wall seen): priced as one shadow, no longer 40 nats of dropouts.
  tk::TrackerParams p4;
  p4.confidence.shadow_weight = 0.0;
  cases.push_back({5000983, "one shadow", p4, tk::Outcome::Rejected, "ambiguous"});
  for (const Case& c : cases) {
    const ReadOne one = read_one(vc::Joint::Butt, c.seed, 0.0);
    const ReadOne before = read_one(vc::Joint::Butt, c.seed, 0.0, c.without);
    INFO("seed " << c.seed << " (" << c.what << "): " << tk::to_string(one.result.status) << " "
                 << one.result.reason << ", error " << one.scored.track_error_mm << "; without: "
                 << tk::to_string(before.result.status) << ", error " << before.scored.track_error_mm);
    CHECK(before.scored.outcome == tk::Outcome::False);
    CHECK(before.scored.track_error_mm > 20.0);
    CHECK(one.scored.outcome == c.outcome);
    CHECK(one.result.reason.rfind(c.reason, 0) == 0);
  }
}

TEST_CASE("corpus: a bevel wall cut below its top edge is joined with the rest of it (session 26)",
          "[tracker][corpus]") {
  // Unseen bevel seed 5,000,456 at noise 0 (a 58 mm bevel wall at 390 mm,
  // waviness, a reflection cluster and two dropout points 3 mm below the
  // top edge): the 10 points above them fit a line 0.2 degrees off the
  // 131 below, which lay up to 0.2 mm off it, so the wall was read as the
  // 10 points and the 68 mm of wall below as the groove's bottom, its track
  // point halfway down the wall, 40 mm from the root. Joined as one line
  // (GrooveParams::wall_joins_one_line), the root is read within 0.35 mm.
  const ReadOne one = read_one(vc::Joint::Bevel, 5000456, 0.0);
  tk::TrackerParams off;
  off.groove.wall_joins_one_line = false;
  const ReadOne before = read_one(vc::Joint::Bevel, 5000456, 0.0, off);
  INFO(tk::to_string(one.result.status) << " " << one.result.reason << ", error " << one.scored.track_error_mm
                                        << "; without: error " << before.scored.track_error_mm);
  CHECK(before.scored.outcome == tk::Outcome::False);
  CHECK(before.scored.track_error_mm > 20.0);
  REQUIRE(one.result.status == tk::TrackStatus::Ok);
  CHECK(one.scored.track_error_mm < 0.35);
}

TEST_CASE("corpus: a groove wall seen edge-on beside its top edge's rounding (session 31)",
          "[tracker][corpus][groove]") {
  // Development seeds, geometry only. Bevel 26: the square wall seen
  // nearly edge-on, 7 points 1 mm apart down its 6.7 mm, beside the top
  // edge's rounding (a short arc of more points at 27 degrees): the
  // rounding was taken for the wall, which then fitted neither wall's
  // range, and the reading was rejected. The others, all with rounded top
  // edges, were rejected for a wall angle out of range (bevel 122 and 199,
  // U 10, J 76 and 293) or a wall going on below its toe (U 38). The wall
  // is now the run reaching farthest (GrooveParams::wall_by_reach).
  tk::TrackerParams off;
  off.groove.wall_by_reach = false;
  check_right_with_option(vc::Joint::Bevel, {26, 122, 199}, 0.1, off, tk::Outcome::Rejected);
  check_right_with_option(vc::Joint::UGroove, {10, 38}, 0.1, off, tk::Outcome::Rejected);
  check_right_with_option(vc::Joint::JGroove, {76, 293}, 0.1, off, tk::Outcome::Rejected);
}

TEST_CASE("corpus: a closed butt's rounded edges dipping within one segment are its joint (session 31)",
          "[tracker][corpus]") {
  // Development seed 111, geometry only: a closed joint with rounded edges
  // whose dip lies within the split threshold, the plates one segment with
  // no corner for the step test: "no gap or step" before; now the dip is
  // the joint (ButtParams::dip_in_segment), read 0.011 mm from the truth.
  tk::TrackerParams off;
  off.butt.dip_in_segment = false;
  check_right_with_option(vc::Joint::Butt, {111}, 0.02, off, tk::Outcome::Rejected);
  // Unseen seed 5,000,918 at noise level 0 (waviness, a dropout run 12 mm
  // away): the dropout run was read as a tight gap, the only reading. The
  // dip is now a reading too, 0.005 mm from the truth, the two close in
  // strength: ambiguous, no longer a false read.
  const ReadOne one = read_one(vc::Joint::Butt, 5000918, 0.0);
  const ReadOne before = read_one(vc::Joint::Butt, 5000918, 0.0, off);
  INFO(tk::to_string(one.result.status) << " " << one.result.reason << "; without: "
                                        << tk::to_string(before.result.status) << ", error "
                                        << before.scored.track_error_mm);
  CHECK(before.scored.outcome == tk::Outcome::False);
  CHECK(before.scored.track_error_mm > 10.0);
  CHECK(one.result.status == tk::TrackStatus::Rejected);
  CHECK(one.result.reason.rfind("ambiguous", 0) == 0);
}
