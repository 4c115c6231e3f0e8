#pragma once
// Profiles for the tracker from a recording: a vts profile EXR or a CSV file
// (docs/CLI.md, `vts track`), with what an EXR's scene says about the joint.
#include <filesystem>
#include <memory>
#include <optional>
#include <stdexcept>
#include <vector>

#include "sensor/profile.h"
#include "sensor/workpiece.h"
#include "tracker/types.h"

namespace vts {

struct TrackInputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// What a recording says besides its profiles.
struct TrackInputInfo {
  bool csv = false;          // read from CSV (no scene, no ground truth)
  bool has_truth = false;    // an EXR recorded with the error model: true.* holds the ideal points
  // The joint of the EXR's scene, if it names one (a mesh workpiece only
  // when its scene gives `joint:`; its mesh file is not read), and its plate
  // thickness (0 for a mesh).
  std::optional<tracker::JointType> scene_joint;
  double scene_thickness_mm = 0.0;
};

struct TrackInput : TrackInputInfo {
  std::vector<Profile> profiles;
};

// By the file's extension, any case: .exr, .csv.
enum class RecordingFormat { Exr, Csv, Unknown };
RecordingFormat recording_format(const std::filesystem::path& file);

// Reads `file` by its extension (.exr or .csv, any case). Throws
// TrackInputError naming the file (and line, field) for a missing,
// malformed or unknown file.
TrackInput read_track_input(const std::filesystem::path& file);

// The ideal points instead of the measured ones (requires has_truth).
void use_truth(TrackInput& input);
void use_truth(std::vector<Profile>& profiles);

// A recording read a batch of profiles at a time, in order (sensor/
// profile_exr.h ProfileExrReader, sensor/profile_csv.h ProfileCsvReader):
// memory is one batch whatever the recording's length. Messages as
// read_track_input's; an error in the profiles further on is thrown by the
// next() that reaches it.
class TrackInputReader {
 public:
  // Opens `file` (by its extension, as read_track_input) and reads its
  // header. Throws TrackInputError.
  explicit TrackInputReader(const std::filesystem::path& file);
  ~TrackInputReader();
  TrackInputReader(const TrackInputReader&) = delete;
  TrackInputReader& operator=(const TrackInputReader&) = delete;

  const TrackInputInfo& info() const { return info_; }
  // From the next batch on, the ideal points (requires info().has_truth).
  void use_truth() { truth_ = true; }
  // The next profiles, at most max_profiles (>= 1), into `batch` (replacing
  // its content; storage reused); false, `batch` empty, at the end. Throws
  // TrackInputError.
  bool next(std::vector<Profile>& batch, int max_profiles);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  TrackInputInfo info_;
  bool truth_ = false;
};

}  // namespace vts
