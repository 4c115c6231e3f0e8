#pragma once
// The groove joints (vgroove, bevel, ugroove, jgroove) with their beads: the
// walls, the plates under them, the fill and the analytic truth, following
// docs/design/grooves.md (formulas: docs/CELLS.md). Used by workpiece.cpp.
#include <string>

#include "sensor/workpiece.h"

namespace vts::groove {

// Checks that only the grooves need (angle, root face, radius, width, the
// fill and its cap), after validate()'s checks of single fields; empty if
// usable, else "field = value: why".
std::string validate(JointType type, const JointParams& params);

// The plates of both sides (not for the v-groove: build_vgroove keeps its
// own), then those of the fill when passes > 0.
void add_plates(JointType type, const JointParams& params, Workpiece& w, bool sides);

// The groove truth: track_yz (B3), top and toe points, wall angles, top
// width, fill_lowest, angle, gap, mismatch, the named features, and depth and
// area (what is left to fill) unless keep_depth_area (the empty v-groove).
void set_truth(JointType type, const JointParams& params, Workpiece& w, bool keep_depth_area);

}  // namespace vts::groove
