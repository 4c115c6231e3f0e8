#pragma once
// Ground truth per profile as JSON Lines, for scoring the tracker
// (tracker/score.h, `vts score`, docs/JOINTS.md "Scores"): one object per
// profile with at least "profile" (its index) and "track_point" {"y", "z"}
// (sensor frame, mm); optionally "joint", "gap_mm", "mismatch_mm",
// "angle_deg", "step_mm", "depth_mm" (null where unknown), "noise_mm" (the
// profile's noise level, its table row; 0 noise-free), "tags" (a list of
// strings: "joint_hidden" or "notch_unseen" mark a joint that cannot be read)
// and "ideal" (true: a noise-free profile without imperfections, table row
// "ideal"). tests/corpus' vts-corpus writes this format.
#include <cstdint>
#include <istream>
#include <string>

#include "trackio/result_json.h"
#include "tracker/score.h"

namespace vts::trackio {

// One truth object; *profile receives its index. Throws JsonError naming the
// key that is missing or of the wrong type.
tracker::Truth truth_from_json(const Json& j, std::int64_t* profile = nullptr);

}  // namespace vts::trackio
