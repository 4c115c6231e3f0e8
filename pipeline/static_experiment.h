#pragma once
// The paper's static experiment (docs/STATIC.md): the built-in setups
// static-A .. static-F scanned along their paths, every profile tracked with
// the fillet template, and medians of the break points, gap and angle against
// the analytic truth: the paper's Table 3 and Figure 7. `vts static` prints
// and writes these; a front-end can call them as they are.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "pipeline/scan_session.h"
#include "plot/plot.h"
#include "sensor/profile.h"
#include "tracker/tracker.h"

namespace vts {

struct StaticSpec {
  int profiles = 10;       // per setup, 0.5 mm apart along the seam
  std::uint64_t seed = 1;  // the error model's draws
  SourceKind source = SourceKind::Raster;
  bool ideal = false;      // error model off
};

inline constexpr int kStaticBreaks = 5;  // the fillet's B0..B4

// The analytic truth of one setup at one sensor pose, sensor frame (y, z) mm.
struct StaticTruth {
  std::array<Vec2, kStaticBreaks> bp;
  double gap_mm = 0.0;
  double angle_deg = 0.0;
};

// One setup's result: medians over the accepted profiles, in the paper's
// physical frame (docs/STATIC.md; NaN where nothing was accepted).
struct StaticRow {
  char label = 'A';
  double distance_mm = 0.0;
  int profiles = 0, ok = 0;
  std::array<Vec2, kStaticBreaks> bp, bp_true;
  double gap = NAN, gap_paper = NAN, angle = NAN;
  StaticTruth truth;
  std::string first_reason;  // of the first profile not accepted
  // Drawn in the figure: the first profile and its result (sensor frame).
  Profile drawn;
  tracker::TrackResult drawn_result;
  StaticTruth drawn_truth;
};

struct StaticResult {
  std::vector<StaticRow> rows;  // static-A .. static-F
  std::string conditions;       // "raster emulator, error model on, seed 1, 10 profiles"
};

// Scans and tracks every setup (scan jobs, pipeline/scan_job.h). Throws as
// run_scan_job.
StaticResult run_static_experiment(const StaticSpec& spec);

// Table 3 as CSV (table3.csv) and as Markdown (two tables: values and
// deviations from the truth), and Figure 7 of one setup.
std::string static_table_csv(const StaticResult& result);
std::string static_table_markdown(const StaticResult& result);
plot::Canvas static_figure(const StaticRow& row, const std::string& conditions);

}  // namespace vts
