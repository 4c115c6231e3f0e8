#include "pipeline/track_recording.h"

#include "tracker/tracker.h"
#include "trackio/result_json.h"

namespace vts {

void track_recording(const TrackInput& input, const tracker::TrackerParams& params,
                     const TrackRecordingOptions& options, const std::function<void(const std::string&)>& line) {
  tracker::Tracker tracker(params);
  tracker::Follower follower(params, options.follow);
  tracker::TrackResult result;
  for (const Profile& p : input.profiles) {
    const tracker::ProfileView view{p.y_mm, p.z_mm, p.valid};
    if (options.independent) {
      tracker.track(view, result);
      line(trackio::result_to_json_line(p.index, result));
      continue;
    }
    const tracker::TrackResult& r = follower.track(view, input.csv ? nullptr : &p.world_from_sensor);
    line(trackio::sequence_to_json_line(p.index, r, follower));
  }
}

}  // namespace vts
