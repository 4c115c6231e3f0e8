// The tracker over a recording (pipeline/track_recording.h): one JSON line
// per profile, in order, each profile alone or as a sequence. Profiles from
// the Embree reference (no OpenGL), ideal, of the built-in fillet.
#include <catch2/catch.hpp>

#include <string>
#include <vector>

#include "pipeline/scan_job.h"
#include "pipeline/sinks.h"
#include "pipeline/track_recording.h"
#include "trackio/result_json.h"

namespace {

vts::TrackInput fillet_recording(int profiles) {
  vts::ScanSpec spec;
  spec.cell = *vts::builtin_cell("fillet");
  spec.cell.path.profiles = profiles;
  spec.cell.scanner.ideal = true;
  spec.source = vts::SourceKind::Reference;
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
