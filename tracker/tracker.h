#pragma once
// The seam tracker: one profile in, the joint's break points, track point and
// process values out, after the paper's Figure 4: (1) outlier elimination,
// (2) recursive split, (3) merge, (4) a least-squares line per segment with
// break points at the intersections of adjacent lines, (5) template matching
// against the configured joint with accept ranges. Break point meanings per
// joint: docs/JOINTS.md and break_point_name().
#include <array>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "tracker/geometry.h"
#include "tracker/params.h"
#include "tracker/segmentation.h"
#include "tracker/types.h"

namespace vts::tracker {

enum class TrackStatus {
  Ok,        // the joint was found and every process value is inside its accept range
  Rejected,  // not accepted: TrackResult::reason says why
  NoData,    // too few usable points to look for a joint (or malformed input)
};
std::string_view to_string(TrackStatus status);

inline constexpr int kMaxBreakPoints = 8;
inline constexpr double kNotMeasured = std::numeric_limits<double>::quiet_NaN();

// Everything the tracker reports for one profile. Points are in the sensor
// frame (y, z), mm. A process value that does not apply to the joint, or that
// this profile does not show, is NaN.
struct TrackResult {
  TrackStatus status = TrackStatus::NoData;
  std::string reason;  // empty when Ok
  JointType joint = JointType::Fillet;

  // B0..B7; which exist and what each means depends on the joint.
  std::array<std::optional<Vec2>, kMaxBreakPoints> break_points;
  std::optional<Vec2> track_point;  // the point to weld: the joint's root

  double gap_mm = kNotMeasured;        // true gap between the plates
  double gap_paper_mm = kNotMeasured;  // fillet: the paper's gap (3.2.3), web line's end point to the flange line
  double angle_deg = kNotMeasured;     // joint angle (docs/JOINTS.md per joint)
  double mismatch_mm = kNotMeasured;   // butt, v-groove: height difference of the plates
  double step_mm = kNotMeasured;       // lap: upper plate's top edge above the lower plate
  // Grooves (v-groove, bevel, U, J): from the plate tops' line (B1-B5) to
  // the lowest point of the groove's bottom (the root, or the last bead's
  // surface: the fill), and the cross-section still open between that line
  // and the groove's surface (the remaining depth and area to fill).
  double depth_mm = kNotMeasured;
  double area_mm2 = kNotMeasured;
  // Grooves: each wall's straight part against its plate top (90: square;
  // a: the wall of the first plate in scan order), and the top width B1-B5.
  // angle_deg is the included angle, 180 - both.
  double wall_angle_a_deg = kNotMeasured;
  double wall_angle_b_deg = kNotMeasured;
  double top_width_mm = kNotMeasured;
  std::optional<Vec2> fill_lowest;  // grooves: the lowest point of the bottom (fill) surface
  // Half the interval, along the plate, in which the plate edges that define
  // the gap can lie given the column rays (0 where lines meet or an edge face
  // was seen). Ideal profiles cannot pin an edge better than this.
  double edge_uncertainty_mm = 0.0;
  // The same for the track point: half the interval it can lie in, where
  // plate edges place it (a butt's or corner's edges, a lap's top edge, a
  // v-groove's root edges); 0 where lines meet.
  double track_uncertainty_mm = 0.0;
  // How precisely the reading locates the track point (docs/JOINTS.md
  // "Localization"): the root mean square of its error (mm; the square root
  // of the trace of its covariance, worked out from the residuals and
  // spread of the lines that place it, the end points' noise,
  // track_uncertainty_mm's interval, what the model cannot see: face points
  // spread along a plate, a hidden face's tilt (hidden_face_deg), a groove
  // bottom's scatter, and the readings of the same joint within
  // distinct_mm), and the chance (0..1) that it lies more than
  // ConfidenceParams::track_interval_mm from where it is read, which the
  // confidence includes. NaN where the template does not work it out or
  // there is no reading.
  double track_sigma_mm = kNotMeasured;
  double track_off_probability = kNotMeasured;
  // The profile's noise across the surface (1 sigma, mm) the tolerances were
  // scaled with: NoiseParams::sigma_mm, or estimated from the profile (the
  // larger of the second differences' estimate, estimate_noise_mm, and the
  // long segments' median rms about their lines: waviness).
  double noise_mm = 0.0;
  // How sure the reading is, 0..1 (docs/JOINTS.md, "Confidence"): its
  // posterior probability against the distinct rival readings and "the joint
  // is not in view" (ConfidenceParams). Readings below
  // ConfidenceParams::min_confidence are rejected. 0 when there is none.
  double confidence = 0.0;
  double strength = 0.0;  // the reading's evidence (ConfidenceParams), log-likelihood ratio
  // The strongest accepted reading farther than ConfidenceParams::distinct_mm
  // away, and its evidence (a competing joint: a reflection, a scratch, a
  // second feature); empty if none.
  std::optional<Vec2> rival_track_point;
  double rival_strength = 0.0;
  // Every accepted reading (at most 32, the strongest), the chosen one among
  // them, and those the model check left `uncertain` (a butt's edges: the
  // joint is there but not placed to 1 mm; they stay rivals of the others):
  // where the template saw the joint and how strongly.
  struct Reading {
    Vec2 track_point = Vec2::Zero();
    double strength = 0.0;
  };
  std::vector<Reading> readings;

  // Step 4's segments in scan order (first/last are profile columns).
  struct SegmentInfo {
    int first_col = 0;
    int last_col = 0;
    int points = 0;
    Line line;  // normal towards the sensor; meaningless when points < 2
    double rms_mm = 0.0;
  };
  std::vector<SegmentInfo> segments;
  int valid_points = 0;  // usable input points
  int outliers = 0;      // removed by step 1
};

// What break point `index` (0..7) means for `joint`; empty if unused.
std::string_view break_point_name(JointType joint, int index);

// Holds the parameters and all scratch memory: after the first few profiles
// track() allocates nothing (unless a reject reason outgrows its buffer).
// Not thread-safe; use one Tracker per thread.
class Tracker {
 public:
  explicit Tracker(const TrackerParams& params = {});

  const TrackerParams& params() const { return params_; }
  void set_params(const TrackerParams& params) { params_ = params; }

  // Tracks one profile into `out` (its buffers are reused). With a prior,
  // only readings within its radius of its point count.
  void track(const ProfileView& profile, TrackResult& out, const TrackPrior* prior = nullptr);
  // Tracks one profile into the tracker's own result.
  const TrackResult& track(const ProfileView& profile, const TrackPrior* prior = nullptr);

  // Steps 1 to 4 of the last profile tracked.
  const Segmentation& segmentation() const { return seg_; }

 private:
  TrackerParams params_;
  Segmentation seg_;
  TrackResult result_;
  std::vector<int> long_;  // indices of segments with at least s_min points
  std::vector<Vec2> scratch_;
  std::vector<int> bevels_;
  std::vector<std::uint8_t> off_plates_;
  std::vector<int> next_long_;
  std::vector<int> closed_;
  std::vector<std::pair<double, int>> rms_;
};

}  // namespace vts::tracker
