#pragma once
// A multi-pass weld of a groove cell (issue 18): the beads are laid one pass
// after the other (the cell's geometry rebuilt with one more pass each time),
// and between the passes the sensor is asked where the groove is, how much
// depth and area are left to fill and where the next bead goes; each answer
// against the cell's analytic truth. `vts sim --cell vgroove-thick` runs it,
// and `vts static` gives one row per built-in groove cell from it.
#include <cmath>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "pipeline/scan_session.h"
#include "sensor/cell.h"
#include "trackio/result_json.h"

namespace vts {

// Where each bead goes (docs/SIM.md "Multi-pass"): Model lays it where the
// cell's model centres it (between the toes of the fill under it), whatever
// the sensor said; Adaptive lays it where the sensor said (the tracker's
// next-bead point, median over the pass's accepted profiles, taken into the
// part frame through the scan's poses), with the model's deposit per pass,
// and stops the run when a pass has no accepted profile.
enum class FillMode { Model, Adaptive };
std::string_view to_string(FillMode mode);

struct GroovePassSpec {
  Cell cell;              // one groove workpiece (vgroove, bevel, ugroove, jgroove)
  int first_pass = 0;     // beads laid before the first scan
  int last_pass = -1;     // ... before the last (-1: the cell's own passes)
  int profiles = 10;      // per pass, along the cell's path
  SourceKind source = SourceKind::Raster;
  std::uint64_t seed = 1;  // the error model's draws (seed + pass)
  // Adaptive: each bead laid where the sensor said (as `vts sim --cell`);
  // Model: centred between the walls, whatever the sensor said.
  FillMode fill = FillMode::Adaptive;
  // Adaptive: added to every reported next-bead point along the laser line
  // (sensor y, mm) before it is taken into the part frame, as a sensor
  // mounted that far off its calibrated place across the seam would report.
  double bias_mm = 0.0;
};

// One scan between passes: medians over the accepted profiles; NaN where
// nothing was accepted. Walls and top edges in scan order (the tracker's a
// and b).
struct GroovePass {
  int laid = 0;  // beads laid before this scan
  int profiles = 0, ok = 0;
  double depth_true = 0.0, depth = 0.0;  // what is left to fill, mm
  double area_true = 0.0, area = 0.0;    // mm^2
  double width_true = 0.0, width = 0.0;  // top width, mm
  double wall_a_true = 0.0, wall_a = 0.0, wall_b_true = 0.0, wall_b = 0.0;  // degrees to the plate top
  // The next bead's place (B3, the bottom midway between the toes): its
  // error across the seam (along the laser line) and in depth, mm.
  double next_dy = 0.0, next_dz = 0.0;
  std::string first_reason;  // of the first profile not accepted
  // The next bead's place across the seam, in the part (joint) frame, mm:
  // where the model centres it (the true B3 of the fill scanned), where the
  // sensor put it (NaN when no profile was accepted) and whether a bead was
  // laid from this scan (not after the last pass, nor when the run stopped);
  // laid_y is where it went: model_y with --fill model, reported_y adaptive.
  double model_y = NAN, reported_y = NAN, laid_y = NAN;
  bool bead_laid = false;
  // The fill scanned, true (joint frame, mm): its toes B2, B4 (the plate's
  // root edges when empty), and the plates' top edges B1, B5.
  Vec2 toe_a = Vec2::Zero(), toe_b = Vec2::Zero(), top_a = Vec2::Zero(), top_b = Vec2::Zero();
};

struct GroovePassRun {
  std::string cell;
  std::string conditions;  // "raster emulator, error model on, seed 1, 10 profiles per pass"
  FillMode fill = FillMode::Model;
  std::vector<GroovePass> passes;
  std::string stopped;  // adaptive: why the run stopped before its last pass (empty: it did not)
};

// Empty if the spec can run, else a message naming what is wrong.
std::string validate(const GroovePassSpec& spec);
// Scans and tracks each pass (the v-groove read with its fill). Throws
// std::invalid_argument with validate()'s message, and as run_scan_job.
GroovePassRun run_groove_passes(const GroovePassSpec& spec);
// The summary as a Markdown table and as JSON (docs/SIM.md, "Multi-pass").
std::string groove_passes_markdown(const GroovePassRun& run);
// One row per run (its last pass): the built-in groove cells as `vts static`
// tabulates them (grooves.md).
std::string groove_cells_markdown(const std::vector<GroovePassRun>& runs);
trackio::Json groove_passes_json(const GroovePassRun& run);

}  // namespace vts
