#pragma once
// A multi-pass weld of a groove cell (issue 18): the beads are laid one pass
// after the other (the cell's geometry rebuilt with one more pass each time),
// and between the passes the sensor is asked where the groove is, how much
// depth and area are left to fill and where the next bead goes; each answer
// against the cell's analytic truth. `vts sim --cell vgroove-thick` runs it,
// and `vts static` gives one row per built-in groove cell from it.
#include <cstdint>
#include <string>
#include <vector>

#include "pipeline/scan_session.h"
#include "sensor/cell.h"
#include "trackio/result_json.h"

namespace vts {

struct GroovePassSpec {
  Cell cell;              // one groove workpiece (vgroove, bevel, ugroove, jgroove)
  int first_pass = 0;     // beads laid before the first scan
  int last_pass = -1;     // ... before the last (-1: the cell's own passes)
  int profiles = 10;      // per pass, along the cell's path
  SourceKind source = SourceKind::Raster;
  std::uint64_t seed = 1;  // the error model's draws (seed + pass)
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
};

struct GroovePassRun {
  std::string cell;
  std::string conditions;  // "raster emulator, error model on, seed 1, 10 profiles per pass"
  std::vector<GroovePass> passes;
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
