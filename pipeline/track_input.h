#pragma once
// Profiles for the tracker from a recording: a vts profile EXR or a CSV file
// (docs/CLI.md, `vts track`), with what an EXR's scene says about the joint.
#include <filesystem>
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

struct TrackInput {
  std::vector<Profile> profiles;
  bool csv = false;          // read from CSV (no scene, no ground truth)
  bool has_truth = false;    // an EXR recorded with the error model: true.* holds the ideal points
  // The joint of the EXR's scene, if it names one (a mesh workpiece only
  // when its scene gives `joint:`; its mesh file is not read), and its plate
  // thickness (0 for a mesh).
  std::optional<tracker::JointType> scene_joint;
  double scene_thickness_mm = 0.0;
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

}  // namespace vts
