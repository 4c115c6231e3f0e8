// `vts sim` end to end: runs bin/vts in a fresh temporary directory, reads
// the JSON summary and the files it writes back. The reference source needs
// no GL; the raster run is tagged [gl].
#include <sys/wait.h>
#include <unistd.h>

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "sensor/profile_exr.h"
#include "vts_runner.h"

namespace {

namespace fs = std::filesystem;
using namespace vts_test;
using Json = nlohmann::json;

// `vts sim ARGS` in dir.
Result run_sim_cli(const TempDir& dir, const std::string& args) { return run_vts(dir, "sim " + args); }

void check_targets(const Json& j) {
  REQUIRE(j.at("seams").size() == 2);
  for (const Json& s : j.at("seams")) {
    INFO(s.dump());
    CHECK(s.at("start_found").get<bool>());
    CHECK(s.at("end_found").get<bool>());
    CHECK(s.at("rms_lateral_mm").get<double>() <= 0.1);
    CHECK(s.at("rms_vertical_mm").get<double>() <= 0.1);
    CHECK(s.at("max_error_mm").get<double>() <= 0.3);
    CHECK(s.at("start_error_mm").get<double>() <= 0.5);
    CHECK(s.at("end_error_mm").get<double>() <= 1.0);
  }
  CHECK(j["seams"][1]["search_mm"].get<double>() < j["seams"][0]["search_mm"].get<double>());
}

}  // namespace

TEST_CASE("vts sim: JSON summary and output files (reference source)", "[cli][sim]") {
  TempDir dir;
  const Result r = run_sim_cli(dir, "--source reference --seed 5 --json --out-dir out");
  INFO(r.err);
  REQUIRE(r.code == 0);
  // One JSON object on one line.
  REQUIRE(r.out.find('\n') == r.out.size() - 1);
  const Json j = Json::parse(r.out);
  CHECK(j.at("source") == "reference");
  CHECK(j.at("seed") == 5);
  CHECK(j.at("error_model") == true);
  CHECK(j.at("workpiece_offset_mm").get<double>() <= 10.0);
  CHECK(j.at("workpiece_rotation_deg").get<double>() <= 5.0);
  check_targets(j);

  const fs::path out = dir.path / "out";
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(out)) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  CHECK(names == std::vector<std::string>{"profiles.exr", "timeseries.csv", "tracking_error.png"});

  const std::string csv = slurp(out / "timeseries.csv");
  CHECK(csv.rfind("time_s,seam,phase,sensor_state,tcp_x_mm", 0) == 0);
  CHECK(csv.find(",weld,") != std::string::npos);
  CHECK(csv.find(",searching,") != std::string::npos);
  CHECK(csv.find(",end-found,") != std::string::npos);

  const vts::ProfileRecording rec = vts::read_profile_exr(out / "profiles.exr");
  CHECK(static_cast<long long>(rec.profiles.size()) >= j.at("profiles").get<long long>());
  CHECK(rec.info.error_model);
  for (std::size_t i = 0; i < rec.profiles.size(); ++i) REQUIRE(rec.profiles[i].index == static_cast<long long>(i));

  const std::string png = slurp(out / "tracking_error.png");
  REQUIRE(png.size() > 8);
  CHECK(png.compare(1, 3, "PNG") == 0);

  // The master on the recording of this run: the same figures.
  const Result replay =
      run_sim_cli(dir, "--replay out/profiles.exr --seed 5 --json --out-dir replayed");
  INFO(replay.err);
  REQUIRE(replay.code == 0);
  const Json jr = Json::parse(replay.out);
  CHECK(jr.at("source") == "replay");
  for (int k = 0; k < 2; ++k)
    for (const char* key : {"rms_lateral_mm", "rms_vertical_mm", "max_error_mm", "start_error_mm",
                            "end_error_mm", "search_mm"})
      CHECK(jr["seams"][k][key].get<double>() == j["seams"][k][key].get<double>());
  CHECK_FALSE(fs::exists(dir.path / "replayed" / "profiles.exr"));
}

TEST_CASE("vts sim: a replay at another speed is refused clearly", "[cli][sim]") {
  TempDir dir;
  REQUIRE(run_sim_cli(dir, "--source reference --seed 5 --rate 40 --out-dir out").code == 0);
  // The master moves differently from the recorded run: the recorded sensor says so.
  const Result r = run_sim_cli(dir, "--replay out/profiles.exr --seed 5 --speed 12 --out-dir other");
  CHECK(r.code == 1);
  CHECK(r.out.find("did not move as in the recorded run") != std::string::npos);
}

TEST_CASE("vts sim: bad options name the option and value and exit 2", "[cli][sim]") {
  TempDir dir;
  const std::pair<const char*, const char*> cases[] = {
      {"--speed abc", "--speed = 'abc'"},        {"--speed 0", "--speed = '0'"},
      {"--rate 20000", "--rate = '20000'"},      {"--offset 30", "--offset = '30'"},
      {"--rotation -1", "--rotation = '-1'"},    {"--source gpu", "--source = 'gpu'"},
      {"--seed x1", "--seed = 'x1'"},            {"--sensor nope", "--sensor = 'nope'"},
      {"--material glass", "--material = 'glass'"}, {"--replay missing.exr", "--replay = 'missing.exr'"},
      {"--robot ur5", "--robot = 'ur5'"},        {"--robot-seed 3", "--robot-seed = '3': only with an arm"},
      {"--scenario nope", "no scenario 'nope' (built in: arm-accuracy,"},
      {"--scenario weaving --seed 4", "--seed = '4': a scenario sets it"},
      {"--scenario missing.yaml", "missing.yaml"},
  };
  for (const auto& [args, message] : cases) {
    const Result r = run_sim_cli(dir, std::string(args) + " --out-dir out");
    INFO(args << ": " << r.err);
    CHECK(r.code == 2);
    CHECK(r.err.find(message) != std::string::npos);
  }
  // Nothing was created.
  CHECK_FALSE(fs::exists(dir.path / "out"));
}

TEST_CASE("vts sim: scenarios are listed, run by name with their verdict, and by file", "[cli][sim]") {
  TempDir dir;
  const Result list = run_sim_cli(dir, "--scenarios");
  REQUIRE(list.code == 0);
  CHECK(list.out.find("weaving") != std::string::npos);
  CHECK(list.out.find("seam-ends-early        fail") != std::string::npos);

  // A failing scenario whose failure is the expected one exits 0 and says why.
  const Result r = run_sim_cli(dir, "--scenario seam-ends-early --json --out-dir out");
  INFO(r.err);
  REQUIRE(r.code == 0);
  const Json j = Json::parse(r.out);
  CHECK(j.at("verdict") == "fail");
  CHECK(j.at("as_expected") == true);
  CHECK(j.at("reason").get<std::string>().find("lost") != std::string::npos);
  CHECK(j.at("robot") == "kr16");
  CHECK(j.at("seams").at(0).at("open_loop").at("max_error_mm").get<double>() > 0.0);
  CHECK(fs::exists(dir.path / "out" / "tracking_error.png"));

  // The same file expecting a pass: exit 1.
  std::ifstream in(std::string(VTS_SOURCE_DIR) + "/examples/scenarios/seam-ends-early.yaml");
  std::stringstream text;
  text << in.rdbuf();
  std::string yaml = text.str();
  yaml.replace(yaml.find("expect: fail"), 12, "expect: pass");
  std::ofstream(dir.path / "mine.yaml") << yaml;
  const Result mine = run_sim_cli(dir, "--scenario mine.yaml --out-dir mine");
  CHECK(mine.code == 1);
  CHECK(mine.out.find("verdict: fail") != std::string::npos);
}

TEST_CASE("vts sim: the default raster run meets the targets", "[cli][sim][gl]") {
  TempDir dir;
  const Result r = run_sim_cli(dir, "--json --out-dir out");
  INFO(r.err);
  REQUIRE(r.code == 0);
  const Json j = Json::parse(r.out);
  CHECK(j.at("source") == "raster");
  check_targets(j);
}

TEST_CASE("vts sim --cell: the adaptive fill by default, the bias, the model's fill and a stop", "[cli][sim]") {
  TempDir dir;
  // The laser line's +y is the part's -y in vgroove-thick: a +0.5 mm bias
  // lays the beads 0.5 mm towards side a (tests/pipeline/groove_passes_test).
  Result r = run_sim_cli(dir, "--cell vgroove-thick --source reference --passes 2 --profiles 3 --fill-bias 0.5 --json");
  INFO(r.err);
  REQUIRE(r.code == 0);
  Json j = Json::parse(r.out);
  CHECK(j["fill"] == "adaptive");
  CHECK(j["stopped"] == "");
  REQUIRE(j["passes"].size() == 3);
  for (int k = 0; k < 2; ++k) {
    CHECK(j["passes"][k]["next_bead_laid"].get<bool>());
    CHECK(std::abs(j["passes"][k]["next_bead_offset_mm"].get<double>() + 0.5) < 0.3);
  }
  CHECK_FALSE(j["passes"][2]["next_bead_laid"].get<bool>());
  r = run_sim_cli(dir, "--cell vgroove-thick --source reference --passes 1 --profiles 2 --fill model");
  CHECK(r.code == 0);
  CHECK(r.out.find("beads where the cell's model centres them") != std::string::npos);
  CHECK(r.out.find("| 0.000 / 0.000 (+0.000) |") != std::string::npos);
  // The empty thick bevel is not read: the adaptive fill stops, exit 1.
  r = run_sim_cli(dir, "--cell bevel-thick --source reference --profiles 2");
  CHECK(r.code == 1);
  CHECK(r.out.find("STOPPED: after 0 beads no profile was accepted") != std::string::npos);
}
