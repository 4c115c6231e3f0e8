// The tracker on the independent corpus (tests/corpus), held-out seeds
// (from 1,000,001; the rules were developed on seeds 1-300): the figures of
// docs/JOINTS.md "Scores" may not get worse. Issue 17's targets (no false
// read in 10,000 profiles per joint, right >= 98 % ideal and >= 95 % noisy)
// are not met yet; the limits below are today's figures with a little room,
// to be tightened as the tracker improves.
#include <catch2/catch.hpp>

#include <cstdio>
#include <map>

#include "corpus_score.h"

using namespace vts_score;

namespace {

struct Limit {
  int max_false;       // of 2,100 profiles (300 per level)
  double min_right;    // share of the profiles whose joint is in view
};

}  // namespace

TEST_CASE("corpus: the tracker's scores do not get worse", "[tracker][corpus]") {
  RunOptions o;
  o.first_seed = 1000001;
  o.profiles = 300;
  const tk::ScoreTable table = run(o);
  WARN("\n" << table.markdown());
  const std::map<tk::JointType, Limit> limits = {
      {tk::JointType::Fillet, {4, 0.93}},   {tk::JointType::Corner, {58, 0.49}},
      {tk::JointType::Lap, {125, 0.49}},    {tk::JointType::Butt, {158, 0.66}},
      {tk::JointType::VGroove, {110, 0.70}},
  };
  for (const auto& [joint, limit] : limits) {
    const tk::Tally t = table.total(joint);
    INFO(tk::to_string(joint) << ": " << t.false_reads << " false reads, " << t.right << " right of " << t.visible());
    REQUIRE(t.profiles == 2100);
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
