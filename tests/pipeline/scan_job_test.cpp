// The scan job (pipeline/scan_job.h): sinks, progress, statistics,
// cancellation. Jobs on the Embree reference need no OpenGL; [gl] ones use
// the raster emulator.
#include <catch2/catch.hpp>

#include <cstdlib>
#include <filesystem>
#include <stdexcept>

#include "../common/temp_dir.h"
#include "pipeline/scan_job.h"
#include "pipeline/sinks.h"
#include "sensor/profile_exr.h"

namespace {

vts::ScanSpec fillet_spec(int profiles, vts::SourceKind source = vts::SourceKind::Reference) {
  vts::ScanSpec spec;
  spec.cell = *vts::builtin_cell("fillet");
  spec.cell.path.profiles = profiles;
  spec.source = source;
  spec.seed = 5;
  spec.batch_profiles = 64;
  return spec;
}

bool same_points(const vts::Profile& a, const vts::Profile& b) {
  return a.index == b.index && a.y_mm == b.y_mm && a.z_mm == b.z_mm && a.valid == b.valid &&
         a.world_from_sensor.matrix() == b.world_from_sensor.matrix() && a.time_s == b.time_s;
}

// Counts calls, optionally throws on write number `fail_at`.
struct CountingSink final : vts::ScanSink {
  int begun = 0, writes = 0, finished = 0, fail_at = -1;
  std::int64_t rows = 0;
  void begin(const vts::ProfileFileInfo&) override { ++begun; }
  void write(const vts::ScanBatch& batch) override {
    if (writes++ == fail_at) throw std::runtime_error("sink full");
    CHECK(batch.first == rows);
    rows += static_cast<std::int64_t>(batch.profiles.size());
  }
  void finish() override { ++finished; }
};

}  // namespace

TEST_CASE("scan job: memory and EXR sinks receive the same profiles", "[pipeline]") {
  const vts::test::TempDir dir;
  vts::ScanSpec spec = fillet_spec(150);
  spec.with_reference = true;
  vts::MemorySink memory;
  const vts::ScanStats stats = vts::run_scan_job(spec, memory);
  vts::ExrSink exr(dir.path / "f.exr");
  vts::run_scan_job(spec, exr);
  const vts::ProfileRecording file = vts::read_profile_exr(dir.path / "f.exr");
  REQUIRE(memory.recording.profiles.size() == 150);
  REQUIRE(file.profiles.size() == 150);
  REQUIRE(memory.recording.reference.size() == 150);
  CHECK(memory.recording.info.seed == 5);
  CHECK(memory.recording.info.error_model);
  for (std::size_t i = 0; i < 150; ++i) {
    CHECK(same_points(memory.recording.profiles[i], file.profiles[i]));
    CHECK(memory.recording.profiles[i].index == static_cast<std::int64_t>(i));
  }
  CHECK(stats.profiles == 150);
  CHECK(stats.samples == 150 * spec.cell.scanner.points);
  CHECK(stats.valid > 0);
  CHECK(stats.error_model.lit >= stats.error_model.measured);
  CHECK(stats.error_model.measured == stats.valid);
}

TEST_CASE("scan job: progress after every batch, then finish once", "[pipeline]") {
  CountingSink sink;
  std::vector<std::int64_t> done;
  vts::ScanCallbacks callbacks;
  callbacks.progress = [&](std::int64_t d, std::int64_t total, const vts::ScanStats& s) {
    CHECK(total == 200);
    CHECK(s.profiles == d);
    done.push_back(d);
  };
  vts::run_scan_job(fillet_spec(200), sink, callbacks);
  CHECK(done == std::vector<std::int64_t>{64, 128, 192, 200});
  CHECK(sink.begun == 1);
  CHECK(sink.writes == 4);
  CHECK(sink.rows == 200);
  CHECK(sink.finished == 1);
}

TEST_CASE("scan job: cancelled between batches, the sink is not finished and the file not written", "[pipeline]") {
  const vts::test::TempDir dir;
  int polls = 0;
  vts::ScanCallbacks callbacks;
  callbacks.cancelled = [&] { return ++polls > 2; };  // after two batches
  CountingSink counting;
  CHECK_THROWS_AS(vts::run_scan_job(fillet_spec(500), counting, callbacks), vts::Cancelled);
  CHECK(counting.writes == 2);
  CHECK(counting.finished == 0);
  polls = 0;
  {
    vts::ExrSink exr(dir.path / "c.exr");
    CHECK_THROWS_AS(vts::run_scan_job(fillet_spec(500), exr, callbacks), vts::Cancelled);
  }
  CHECK(dir.entries().empty());
}

TEST_CASE("scan job: a sink that fails stops the job with its exception", "[pipeline]") {
  CountingSink sink;
  sink.fail_at = 1;
  CHECK_THROWS_WITH(vts::run_scan_job(fillet_spec(300), sink), "sink full");
  CHECK(sink.finished == 0);
}

TEST_CASE("scan job: the raster emulator checked against the reference", "[pipeline][gl]") {
  vts::ScanSpec spec = fillet_spec(100, vts::SourceKind::Raster);
  spec.with_reference = true;
  CountingSink sink;
  const vts::ScanStats stats = vts::run_scan_job(spec, sink);
  CHECK(stats.both_valid > 0);
  CHECK(stats.max_diff_mm < 0.001);
  CHECK(stats.hit_miss * 1000 < stats.samples);
  CHECK(std::abs(stats.error_model_ref.lit - stats.error_model.lit) <= stats.hit_miss);
}
