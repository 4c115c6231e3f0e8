#pragma once
// Scoring the tracker against ground truth (docs/JOINTS.md, "Scores"): each
// profile's result is right, imprecise, rejected or a false read, and a
// table of those shares per joint and noise level. Pure computation: the
// truth comes from whatever made the profiles (an independent corpus, a vts
// scan's analytic truth, a hand-measured recording).
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "tracker/tracker.h"

namespace vts::tracker {

// The truth of one profile, sensor frame (mm, degrees); NaN where unknown.
struct Truth {
  JointType joint = JointType::Fillet;
  Vec2 track_point = Vec2::Zero();
  double gap_mm = kNotMeasured;
  double mismatch_mm = kNotMeasured;
  double angle_deg = kNotMeasured;
  double step_mm = kNotMeasured;
  double depth_mm = kNotMeasured;
  // The profile's noise level (a table row; 0 and below: noise-free, held
  // to ScoreParams::right_ideal_mm; below 0 prints as "ideal").
  double noise_mm = 0.0;
  // The joint cannot be seen (under a tack weld, in a shadow): a reading is
  // not expected, and one more than ScoreParams::false_mm away is false.
  bool hidden = false;
};

enum class Outcome {
  Right,      // ok, track point within the tolerance
  Imprecise,  // ok, track point off by more than the tolerance, at most false_mm
  Rejected,   // not ok (rejected or no data), with a reason
  False,      // ok, track point more than false_mm from the truth
};
std::string_view to_string(Outcome o);

struct ScoreParams {
  double right_ideal_mm = 0.1;  // tolerance of a right track point on noise-free profiles
  double right_noisy_mm = 0.3;  // ...and on noisy ones (Truth::noise_mm > 0)
  double false_mm = 1.0;        // an ok reading farther off is a false read
};

// The outcome of one profile and its track point error (NaN if no track point).
struct Scored {
  Outcome outcome = Outcome::Rejected;
  double track_error_mm = kNotMeasured;
  double gap_error_mm = kNotMeasured;  // |gap - truth|, ok readings with both known
};
Scored score(const TrackResult& result, const Truth& truth, const ScoreParams& params = {});

// Counts per (joint, noise level). Right, imprecise and rejected count the
// profiles whose joint is in view; false reads count every profile (a
// reading where the joint is hidden is false unless right by chance).
struct Tally {
  int profiles = 0;
  int right = 0, imprecise = 0, rejected = 0, false_reads = 0;
  int hidden = 0;         // of the profiles, those whose joint is hidden
  int hidden_read = 0;    // ...and were read anyway (ok), right or not
  // Of the ok readings whose joint is in view, those stating how precisely
  // they place the track point (TrackResult::track_sigma_mm), and of them
  // the ones more than 3 stated rms from the truth: a calibrated stated
  // error puts about 1 % there (a Gaussian's 0.3 % along a line, 1.1 %
  // circular).
  int located = 0;
  int over_3_sigma = 0;
  int visible() const { return profiles - hidden; }
  std::vector<double> track_errors_mm;  // of the ok readings
  std::vector<double> gap_errors_mm;
  std::map<std::string, int> reject_reasons;  // reason's first words -> count
  void add(const Scored& s, const TrackResult& r, const Truth& t);
};

struct ScoreTable {
  std::map<std::pair<JointType, double>, Tally> rows;  // (joint, noise_mm)
  void add(const TrackResult& r, const Truth& t, const ScoreParams& params = {});
  Tally total(JointType joint) const;
  // A Markdown table: joint, noise, profiles (of them hidden), right %,
  // imprecise %, rejected % (of the visible ones), false reads, median and
  // 95th percentile track error and gap error of the ok readings, and the
  // share of the located ones more than 3 stated rms off ("-" if none).
  std::string markdown() const;
};

}  // namespace vts::tracker
