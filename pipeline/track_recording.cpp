#include "pipeline/track_recording.h"

#include <future>
#include <vector>

#include "tracker/tracker.h"
#include "trackio/result_json.h"

namespace vts {
namespace {

// Profiles read per batch by the streaming overload.
constexpr int kBatchProfiles = 256;

// The tracker's state along a recording, one profile at a time.
class RecordingTracker {
 public:
  RecordingTracker(const tracker::TrackerParams& params, const TrackRecordingOptions& options, bool csv)
      : options_(options), csv_(csv), tracker_(params), follower_(params, options.follow) {}

  std::string track(const Profile& p) {
    const tracker::ProfileView view{p.y_mm, p.z_mm, p.valid};
    if (options_.independent) {
      tracker_.track(view, result_);
      return trackio::result_to_json_line(p.index, result_);
    }
    const tracker::TrackResult& r = follower_.track(view, csv_ ? nullptr : &p.world_from_sensor);
    return trackio::sequence_to_json_line(p.index, r, follower_);
  }

 private:
  const TrackRecordingOptions& options_;
  bool csv_;
  tracker::Tracker tracker_;
  tracker::Follower follower_;
  tracker::TrackResult result_;
};

}  // namespace

void track_recording(const TrackInput& input, const tracker::TrackerParams& params,
                     const TrackRecordingOptions& options, const std::function<void(const std::string&)>& line) {
  RecordingTracker tracker(params, options, input.csv);
  for (const Profile& p : input.profiles) line(tracker.track(p));
}

void track_recording(TrackInputReader& reader, const tracker::TrackerParams& params,
                     const TrackRecordingOptions& options, const std::function<void(const std::string&)>& line) {
  RecordingTracker tracker(params, options, reader.info().csv);
  // Two batches: one tracked here while the reader fills the other.
  std::vector<Profile> batch, ahead;
  bool more = reader.next(batch, kBatchProfiles);
  while (more) {
    std::future<bool> next = std::async(std::launch::async, [&] { return reader.next(ahead, kBatchProfiles); });
    try {
      for (const Profile& p : batch) line(tracker.track(p));
    } catch (...) {
      next.wait();
      throw;
    }
    more = next.get();
    std::swap(batch, ahead);
  }
}

}  // namespace vts
