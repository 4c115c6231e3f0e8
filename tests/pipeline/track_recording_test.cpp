// The tracker over a recording (pipeline/track_recording.h): one JSON line
// per profile, in order, each profile alone or as a sequence. Profiles from
// the Embree reference (no OpenGL), ideal, of the built-in fillet.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "pipeline/scan_job.h"
#include "pipeline/sinks.h"
#include "pipeline/track_recording.h"
#include "sensor/profile_csv.h"
#include "tests/common/temp_dir.h"
#include "trackio/result_json.h"

namespace {

vts::ScanSpec fillet_spec(int profiles) {
  vts::ScanSpec spec;
  spec.cell = *vts::builtin_cell("fillet");
  spec.cell.path.profiles = profiles;
  spec.cell.scanner.ideal = true;
  spec.source = vts::SourceKind::Reference;
  return spec;
}

vts::TrackInput fillet_recording(int profiles) {
  const vts::ScanSpec spec = fillet_spec(profiles);
  vts::MemorySink memory;
  vts::run_scan_job(spec, memory);
  vts::TrackInput input;
  input.profiles = std::move(memory.recording.profiles);
  return input;
}

std::vector<vts::trackio::Json> track(const vts::TrackInput& input, bool independent) {
  vts::TrackRecordingOptions options;
  options.independent = independent;
  vts::tracker::TrackerParams params;
  params.joint = vts::tracker::JointType::Fillet;
  std::vector<vts::trackio::Json> lines;
  vts::track_recording(input, params, options, [&](const std::string& line) {
    REQUIRE(!line.empty());
    CHECK(line.back() == '\n');
    lines.push_back(vts::trackio::Json::parse(line));
  });
  return lines;
}

}  // namespace

TEST_CASE("track recording: one line per profile, in order, and the sequence locks on", "[pipeline]") {
  const vts::TrackInput input = fillet_recording(12);
  for (const bool independent : {true, false}) {
    INFO((independent ? "independent" : "sequence"));
    const auto lines = track(input, independent);
    REQUIRE(lines.size() == input.profiles.size());
    for (std::size_t i = 0; i < lines.size(); ++i) {
      CHECK(lines[i]["profile"] == input.profiles[i].index);
      CHECK(lines[i].contains("sequence") == !independent);
    }
    // An ideal fillet is read in every profile; the sequence is locked once
    // it has seen FollowParams::lock_profiles consistent readings.
    CHECK(lines.back()["status"] == "ok");
    if (!independent) CHECK(lines.back()["sequence"]["locked"] == true);
  }
}

namespace {

vts::tracker::TrackerParams fillet_params() {
  vts::tracker::TrackerParams params;
  params.joint = vts::tracker::JointType::Fillet;
  return params;
}

// The lines of a recording tracked as it is read from `file`; the lines
// written before an error are kept in `lines`.
void track_streamed(const std::filesystem::path& file, bool independent, std::vector<std::string>& lines) {
  vts::TrackRecordingOptions options;
  options.independent = independent;
  vts::TrackInputReader reader(file);
  vts::track_recording(reader, fillet_params(), options, [&](const std::string& line) { lines.push_back(line); });
}

std::vector<std::string> track_whole(const vts::TrackInput& input, bool independent) {
  vts::TrackRecordingOptions options;
  options.independent = independent;
  std::vector<std::string> lines;
  vts::track_recording(input, fillet_params(), options, [&](const std::string& line) { lines.push_back(line); });
  return lines;
}

}  // namespace

TEST_CASE("track recording: read as it is tracked, EXR and CSV give the lines of the whole recording", "[pipeline]") {
  vts::test::TempDir dir("vts_track_stream");
  // 600 profiles: the reader's batches of 256 and a last short one.
  const vts::ScanSpec spec = fillet_spec(600);
  vts::MemorySink memory;
  vts::ExrSink exr(dir.path / "r.exr");
  vts::run_scan_job(spec, memory);
  vts::run_scan_job(spec, exr);
  vts::TrackInput input;
  input.profiles = memory.recording.profiles;
  {
    std::ofstream csv(dir.path / "r.csv", std::ios::binary);
    vts::write_profile_csv(csv, input.profiles);
  }
  for (const bool independent : {true, false}) {
    INFO((independent ? "independent" : "sequence"));
    std::vector<std::string> from_exr, from_csv;
    track_streamed(dir.path / "r.exr", independent, from_exr);
    CHECK(from_exr == track_whole(input, independent));
    track_streamed(dir.path / "r.csv", independent, from_csv);
    vts::TrackInput csv_input = vts::read_track_input(dir.path / "r.csv");
    CHECK(from_csv == track_whole(csv_input, independent));
    CHECK(from_csv.size() == 600);
  }

  // Cut inside the pixels past the first batch: the first batch's lines,
  // then the reader's error.
  std::string bytes;
  {
    std::ifstream in(dir.path / "r.exr", std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  {
    std::ofstream out(dir.path / "cut.exr", std::ios::binary);
    out << bytes.substr(0, bytes.size() * 4 / 5);
  }
  std::vector<std::string> lines;
  CHECK_THROWS_AS(track_streamed(dir.path / "cut.exr", false, lines), vts::TrackInputError);
  CHECK(lines.size() >= 256);
  CHECK(lines.size() < 600);
  const std::vector<std::string> whole = track_whole(input, false);
  CHECK(std::equal(lines.begin(), lines.end(), whole.begin()));
}
