#pragma once
// tracker::TrackResult <-> JSON, as `vts track` writes it, one object per
// profile (docs/CLI.md "vts track", "Output"). Lengths in mm, angles in
// degrees, points in the sensor frame (y along the laser line, z the range);
// numbers rounded to 1e-6; a value that does not apply or was not measured
// is null.
#include <cstdint>
#include <stdexcept>
#include <string>

#include <nlohmann/json.hpp>

#include "tracker/follower.h"
#include "tracker/tracker.h"

namespace vts::trackio {

using Json = nlohmann::ordered_json;

struct JsonError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// The result of profile `profile` (its index in the recording).
Json result_to_json(std::int64_t profile, const tracker::TrackResult& result);
// The same as one line of JSON Lines, '\n' included (invalid UTF-8 in a
// reject reason is replaced, never thrown on).
std::string result_to_json_line(std::int64_t profile, const tracker::TrackResult& result);

// The same for a profile read in a sequence (tracker::Follower): the
// result, then "sequence": {"locked": whether the joint was followed,
// "region": the region of interest searched {"y", "z", "radius_mm"} or null,
// "filtered": the smoothed track point {"y", "z"} or null}.
std::string sequence_to_json_line(std::int64_t profile, const tracker::TrackResult& result,
                                  const tracker::Follower& follower);

// Back from such an object: the result, and its profile index in *profile
// when given. Values come back as written (rounded to 1e-6; `meaning` is not
// read, it follows from the joint). Throws JsonError naming the key that is
// missing or of the wrong type.
tracker::TrackResult result_from_json(const Json& j, std::int64_t* profile = nullptr);

}  // namespace vts::trackio
