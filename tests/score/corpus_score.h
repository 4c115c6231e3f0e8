#pragma once
// The tracker scored on the independent corpus (tests/corpus): the corpus'
// truth in the tracker's terms, and one run over seeds and noise levels.
// Shared by vts-score-corpus (the table in docs/JOINTS.md) and the tests.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "corpus.h"
#include "tracker/score.h"
#include "tracker/tracker.h"

namespace vts_score {

namespace tk = vts::tracker;
namespace vc = vts_corpus;

tk::JointType joint_of(vc::Joint j);
tk::Truth truth_of(const vc::Truth& t);

struct RunOptions {
  std::vector<vc::Joint> joints{vc::kAllJoints.begin(), vc::kAllJoints.end()};
  // Noise levels (rows); a negative level is "ideal": noise 0 and no
  // imperfections (geometry only).
  std::vector<double> levels{-1.0, 0.0, 0.005, 0.02, 0.05, 0.1, 0.2};
  std::uint64_t first_seed = 1;
  int profiles = 1000;  // per joint and level
  bool camera_in_laser_plane = false;
};

// The row key of an ideal profile's level.
inline constexpr double kIdealLevel = -1.0;

// The corpus' options for a noise level (a table row; negative: "ideal",
// noise 0 and no imperfections).
vc::Options options_for(double level, bool camera_in_laser_plane);

// One profile at a noise level (camera out of the laser plane, as run()
// draws them by default), read alone with the joint's default parameters.
struct ReadOne {
  vc::Profile profile;
  tk::TrackResult result;
  tk::Scored scored;
};
// One corpus profile read with `base` (its joint and --fill set as run() does).
ReadOne read_one(vc::Joint joint, std::uint64_t seed, double level, const tk::TrackerParams& base = {});

// Calls `each` (if set) with every profile, its result and score.
tk::ScoreTable run(const RunOptions& o, const tk::TrackerParams& base = {},
                   const std::function<void(const vc::Profile&, const tk::TrackResult&, const tk::Scored&)>& each = {});

}  // namespace vts_score
