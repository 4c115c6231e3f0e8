#pragma once
// The tracker over a whole recording (pipeline/track_input.h), as `vts track`
// runs it: one JSON Lines object per profile (trackio/result_json.h), in the
// recording's order. Front-ends hand over a line sink; the tracker itself
// stays free of files.
#include <functional>
#include <string>

#include "pipeline/track_input.h"
#include "tracker/follower.h"
#include "tracker/params.h"

namespace vts {

struct TrackRecordingOptions {
  // Each profile alone (tracker::Tracker) instead of the sequence along one
  // seam (tracker::Follower, docs/JOINTS.md "Sequence tracking").
  bool independent = false;
  // The sequence's parameters; travel_per_profile_mm applies to CSV
  // recordings only (an EXR carries the sensor's pose per profile).
  tracker::FollowParams follow;
};

// Tracks every profile of `input` with `params` and calls `line` with each
// profile's JSON line ('\n' included): trackio::result_to_json_line when
// independent, else trackio::sequence_to_json_line.
// The same, the profiles read from `reader` a batch at a time while the
// previous batch is tracked: memory stays flat in the recording's length.
// `line` is called as each profile is tracked; an error reading the
// recording (TrackInputError) comes after the lines of the profiles before
// it.
void track_recording(TrackInputReader& reader, const tracker::TrackerParams& params,
                     const TrackRecordingOptions& options, const std::function<void(const std::string&)>& line);

void track_recording(const TrackInput& input, const tracker::TrackerParams& params,
                     const TrackRecordingOptions& options, const std::function<void(const std::string&)>& line);

}  // namespace vts
