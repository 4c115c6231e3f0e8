#include "pipeline/track_input.h"

#include <cctype>
#include <string>

#include "sensor/profile_csv.h"
#include "sensor/profile_exr.h"
#include "sensor/scene_file.h"

namespace vts {
namespace {

namespace fs = std::filesystem;

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// The first workpiece's joint and thickness, if the recording's scene says.
void read_scene_joint(const ProfileRecording& rec, TrackInput& input) {
  if (rec.info.scene_text.empty()) return;
  try {
    const Cell cell = parse_scene(rec.info.scene_text, rec.info.scene_name, MeshFiles::Skip);
    if (cell.workpieces.empty()) return;
    const Workpiece& w = cell.workpieces.front();
    if (!w.has_joint()) return;
    input.scene_joint = tracker_joint(w.type);
    input.scene_thickness_mm = w.is_mesh() ? 0.0 : w.params.thickness_mm;
  } catch (const std::exception&) {
  }
}

}  // namespace

RecordingFormat recording_format(const fs::path& file) {
  const std::string ext = lower(file.extension().string());
  if (ext == ".exr") return RecordingFormat::Exr;
  if (ext == ".csv") return RecordingFormat::Csv;
  return RecordingFormat::Unknown;
}

TrackInput read_track_input(const fs::path& file) {
  const RecordingFormat format = recording_format(file);
  TrackInput input;
  if (format == RecordingFormat::Csv) {
    input.csv = true;
    try {
      input.profiles = read_profile_csv(file);
    } catch (const CsvError& e) {
      throw TrackInputError(e.what());
    }
  } else if (format == RecordingFormat::Exr) {
    ProfileRecording rec;
    try {
      rec = read_profile_exr(file);
    } catch (const ExrError& e) {
      throw TrackInputError(e.what());
    }
    input.has_truth = rec.info.error_model;
    read_scene_joint(rec, input);
    input.profiles = std::move(rec.profiles);
  } else {
    throw TrackInputError(file.string() + ": unknown file type '" + file.extension().string() +
                          "': expected .exr (vts profile EXR) or .csv");
  }
  return input;
}

void use_truth(TrackInput& input) {
  for (Profile& p : input.profiles) {
    p.y_mm = p.true_y_mm;
    p.z_mm = p.true_z_mm;
    p.valid = p.true_valid;
  }
}

}  // namespace vts
