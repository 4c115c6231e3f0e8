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
void read_scene_joint(const ProfileFileInfo& info, TrackInputInfo& input) {
  if (info.scene_text.empty()) return;
  try {
    const Cell cell = parse_scene(info.scene_text, info.scene_name, MeshFiles::Skip);
    if (cell.workpieces.empty()) return;
    const Workpiece& w = cell.workpieces.front();
    if (!w.has_joint()) return;
    input.scene_joint = tracker_joint(w.type);
    input.scene_thickness_mm = w.is_mesh() ? 0.0 : w.params.thickness_mm;
  } catch (const std::exception&) {
  }
}

[[noreturn]] void unknown_type(const fs::path& file) {
  throw TrackInputError(file.string() + ": unknown file type '" + file.extension().string() +
                        "': expected .exr (vts profile EXR) or .csv");
}

// Runs f, turning the readers' errors into TrackInputError.
template <class F>
auto as_input_error(F&& f) {
  try {
    return f();
  } catch (const CsvError& e) {
    throw TrackInputError(e.what());
  } catch (const ExrError& e) {
    throw TrackInputError(e.what());
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
    input.profiles = as_input_error([&] { return read_profile_csv(file); });
  } else if (format == RecordingFormat::Exr) {
    ProfileRecording rec = as_input_error([&] { return read_profile_exr(file); });
    input.has_truth = rec.info.error_model;
    read_scene_joint(rec.info, input);
    input.profiles = std::move(rec.profiles);
  } else {
    unknown_type(file);
  }
  return input;
}

void use_truth(std::vector<Profile>& profiles) {
  for (Profile& p : profiles) {
    p.y_mm = p.true_y_mm;
    p.z_mm = p.true_z_mm;
    p.valid = p.true_valid;
  }
}

void use_truth(TrackInput& input) { use_truth(input.profiles); }

struct TrackInputReader::Impl {
  std::unique_ptr<ProfileCsvReader> csv;
  std::unique_ptr<ProfileExrReader> exr;
};

TrackInputReader::TrackInputReader(const fs::path& file) : impl_(std::make_unique<Impl>()) {
  const RecordingFormat format = recording_format(file);
  if (format == RecordingFormat::Csv) {
    info_.csv = true;
    impl_->csv = as_input_error([&] { return std::make_unique<ProfileCsvReader>(file); });
  } else if (format == RecordingFormat::Exr) {
    impl_->exr = as_input_error([&] { return std::make_unique<ProfileExrReader>(file); });
    info_.has_truth = impl_->exr->info().error_model;
    read_scene_joint(impl_->exr->info(), info_);
  } else {
    unknown_type(file);
  }
}

TrackInputReader::~TrackInputReader() = default;

bool TrackInputReader::next(std::vector<Profile>& batch, int max_profiles) {
  const bool more = as_input_error([&] {
    return impl_->csv ? impl_->csv->read(batch, max_profiles) : impl_->exr->read(max_profiles, batch) > 0;
  });
  if (truth_) vts::use_truth(batch);
  return more;
}

}  // namespace vts
