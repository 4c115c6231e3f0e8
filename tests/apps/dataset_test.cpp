// vts dataset end to end: the thread limit changes no byte, --shard makes
// one shard that a later run keeps, and a scene's EXR and its JSON lines are
// what vts track and vts score read (docs/DATASETS.md). Bad specs:
// tests/malformed/cases.txt.
#include <catch2/catch.hpp>

#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include "tests/apps/vts_runner.h"

using namespace vts_test;

namespace {

// Two shards of three scenes of 40 profiles on the raster source (a scan
// batch is split between threads), every view angle, two presets.
const char* const kSpec = R"(seed: 5
shards: 2
scenes_per_shard: 3
profiles_per_scene: 40
step_mm: 0.25
joints: {fillet: {gap_mm: [0, 2]}, butt: {}, vgroove: {}, jgroove: {}}
sensors: {mspot: {standoff_mm: [90, 120]}, lps-1280-mid: {}}
materials: {matte-steel: 1, aluminium: 1}
view: {tilt_deg: [-10, 10], roll_deg: [-5, 5], travel_deg: [-5, 5], offset_mm: [-2, 2]}
)";

std::map<std::string, std::string> contents(const fs::path& dir) {
  std::map<std::string, std::string> m;
  for (const auto& e : fs::directory_iterator(dir)) m[e.path().filename().string()] = slurp(e.path());
  return m;
}

}  // namespace

TEST_CASE("vts dataset: 1 and 2 threads write the same bytes", "[cli][gl][threads][dataset]") {
  TempDir dir;
  dir.write("spec.yaml", kSpec);
  for (const char* threads : {"1", "2"}) {
    const Result r = run_vts(dir, std::string("dataset --spec spec.yaml --out d") + threads + " --threads " + threads);
    INFO(r.out << r.err);
    REQUIRE(r.code == 0);
    CHECK(contains(r.out, "2 shards in d" + std::string(threads) + ": 2 written, 0 already complete; 240 profiles"));
  }
  const auto one = contents(dir.path / "d1");
  CHECK(one.size() == 2 * (3 + 2) + 1);
  CHECK(one == contents(dir.path / "d2"));
}

TEST_CASE("vts dataset: --shard makes one shard, a later run keeps it and writes the manifest", "[cli][dataset]") {
  TempDir dir;
  dir.write("spec.yaml", std::string(kSpec) + "source: reference\n");
  Result r = run_vts(dir, "dataset --spec spec.yaml --out d --shard 1");
  INFO(r.out << r.err);
  REQUIRE(r.code == 0);
  CHECK(r.out == "wrote shard-00001.json: 3 scenes, 120 profiles, 4 files in d\n");
  const auto shard1 = contents(dir.path / "d");
  CHECK(shard1.size() == 5);
  CHECK_FALSE(fs::exists(dir.path / "d" / "manifest.json"));
  r = run_vts(dir, "dataset --spec spec.yaml --out d");
  REQUIRE(r.code == 0);
  CHECK(contains(r.out, "2 shards in d: 1 written, 1 already complete; 120 profiles written"));
  CHECK(contains(r.out, "manifest: d/manifest.json"));
  for (const auto& [name, bytes] : shard1) CHECK(slurp(dir.path / "d" / name) == bytes);
  CHECK(contains(slurp(dir.path / "d" / "manifest.json"), "\"profiles\": 240"));
}

TEST_CASE("vts dataset: vts track reads a scene's EXR, vts score its JSON lines", "[cli][dataset]") {
  TempDir dir;
  dir.write("spec.yaml", R"(seed: 1
shards: 1
scenes_per_shard: 2
profiles_per_scene: 20
source: reference
ideal: true
joints: [fillet]
view: {tilt_deg: [-10, 10], roll_deg: [-5, 5], travel_deg: [-5, 5]}
)");
  Result r = run_vts(dir, "dataset --spec spec.yaml --out d");
  INFO(r.out << r.err);
  REQUIRE(r.code == 0);
  // Scene 1's lines: the truth for its EXR's profiles (by row).
  std::ifstream in(dir.path / "d" / "shard-00000.jsonl");
  std::ostringstream truth;
  int lines = 0;
  for (std::string line; std::getline(in, line);)
    if (contains(line, "\"scene\":1,")) truth << line << "\n", ++lines;
  CHECK(lines == 20);
  dir.write("truth.jsonl", truth.str());
  r = run_vts(dir, "track d/shard-00000-scene-0001.exr --independent --out track.jsonl");
  REQUIRE(r.code == 0);
  r = run_vts(dir, "score track.jsonl truth.jsonl");
  INFO(r.out);
  REQUIRE(r.code == 0);
  CHECK(contains(r.out, "| fillet | ideal | 20 (0) | 100.0 % |"));
}
