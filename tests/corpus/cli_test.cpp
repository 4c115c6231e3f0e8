// vts-corpus: the CSV `vts track` reads, the truth JSON Lines, bad arguments.
#include <catch2/catch.hpp>

#include "corpus.h"

#include <nlohmann/json.hpp>

#include <sys/wait.h>
#include <unistd.h>

#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace vc = vts_corpus;
namespace fs = std::filesystem;

namespace {

const std::string kCorpus = std::string(VTS_BIN_DIR) + "/vts-corpus";

struct TempDir {
  fs::path path;
  TempDir() {
    path = fs::temp_directory_path() / ("vts_corpus_cli_" + std::to_string(::getpid()));
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~TempDir() { fs::remove_all(path); }
  std::string operator/(const std::string& name) const { return (path / name).string(); }
  std::size_t files() const { return static_cast<std::size_t>(std::distance(fs::directory_iterator(path), {})); }
};

int run(const std::string& args, const TempDir& dir) {
  const std::string cmd = kCorpus + " " + args + " > " + (dir / "stdout.txt") + " 2> " + (dir / "stderr.txt");
  const int status = std::system(cmd.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string slurp(const std::string& path) {
  std::ifstream f(path);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::string cur;
  for (char c : s) {
    if (c == sep) {
      out.push_back(cur);
      cur.clear();
    } else {
      cur += c;
    }
  }
  if (!cur.empty()) out.push_back(cur);
  return out;
}

}  // namespace

TEST_CASE("vts-corpus: writes the profiles as vts track CSV and the truth as JSON Lines", "[corpus][cli]") {
  TempDir dir;
  REQUIRE(run("--joint butt --count 4 --seed 11 --noise 0.05 --decoy --csv " + (dir / "b.csv") + " --truth " +
                  (dir / "b.jsonl"),
              dir) == 0);
  CHECK(dir.files() == 4u);  // the two outputs, stdout, stderr: no temporary left
  const std::vector<std::string> lines = split(slurp(dir / "b.csv"), '\n');
  REQUIRE(lines.size() > 1);
  CHECK(lines[0] == "profile,y,z,valid");
  vc::Options o;
  o.noise_mm = 0.05;
  o.decoy = true;
  std::size_t row = 1;
  for (int k = 0; k < 4; ++k) {
    const vc::Profile p = vc::make_profile(vc::Joint::Butt, 11 + k, o);  // profile k: seed + k
    for (std::size_t i = 0; i < p.y.size(); ++i, ++row) {
      REQUIRE(row < lines.size());
      const std::vector<std::string> f = split(lines[row], ',');
      REQUIRE(f.size() == 4u);
      CHECK(f[0] == std::to_string(k));
      if (!p.valid[i]) {
        CHECK(lines[row] == std::to_string(k) + ",nan,nan,0");
        continue;
      }
      CHECK(f[3] == "1");
      float y = 0, z = 0;
      std::from_chars(f[1].data(), f[1].data() + f[1].size(), y);
      std::from_chars(f[2].data(), f[2].data() + f[2].size(), z);
      CHECK(y == p.y[i]);  // the text round-trips exactly
      CHECK(z == p.z[i]);
    }
  }
  CHECK(row == lines.size());

  const std::vector<std::string> truth = split(slurp(dir / "b.jsonl"), '\n');
  REQUIRE(truth.size() == 4u);
  for (int k = 0; k < 4; ++k) {
    const auto j = nlohmann::json::parse(truth[k]);
    const vc::Truth t = vc::make_profile(vc::Joint::Butt, 11 + k, o).truth;
    CHECK(j["profile"] == k);
    CHECK(j["joint"] == "butt");
    CHECK(j["track_point"]["y"].get<double>() == t.track_y_mm);
    CHECK(j["track_point"]["z"].get<double>() == t.track_z_mm);
    CHECK(j["gap_mm"].get<double>() == t.gap_mm);
    CHECK(j["mismatch_mm"].get<double>() == t.mismatch_mm);
    CHECK(j["angle_deg"].get<double>() == 180.0);
    CHECK(j["step_mm"].is_null());
    CHECK(j["depth_mm"].is_null());
    CHECK(j["break_points"].contains("B1"));
    CHECK(j["break_points"].contains("B3"));
    CHECK(j["break_points"]["B2"]["y"].get<double>() == t.track_y_mm);
    CHECK(j["decoy_point"].is_object());
    CHECK(j["tags"].is_array());
    CHECK(j["noise_mm"] == 0.05);
    CHECK(j["columns"] == t.columns);
    CHECK(j["standoff_mm"].get<double>() == t.standoff_mm);
    CHECK(j["seed"] == 11 + k);
    CHECK(j["params"]["gap_joint_mm"].get<double>() == t.param("gap_joint_mm"));
  }
}

TEST_CASE("vts-corpus: groove joints write the groove truth", "[corpus][cli]") {
  TempDir dir;
  for (vc::Joint joint : vc::kGrooveJoints) {
    const std::string name = vc::joint_name(joint);
    INFO(name);
    REQUIRE(run("--joint " + name + " --count 3 --seed 5 --truth " + (dir / "g.jsonl"), dir) == 0);
    const std::vector<std::string> truth = split(slurp(dir / "g.jsonl"), '\n');
    REQUIRE(truth.size() == 3u);
    for (int k = 0; k < 3; ++k) {
      const auto j = nlohmann::json::parse(truth[k]);
      const vc::Truth t = vc::make_profile(joint, 5 + k).truth;
      CHECK(j["joint"] == name);
      CHECK(j["depth_mm"].get<double>() == t.depth_mm);
      CHECK(j["area_mm2"].get<double>() == t.area_mm2);
      CHECK(j["wall_angle_a_deg"].get<double>() == t.wall_angle_a_deg);
      CHECK(j["wall_angle_b_deg"].get<double>() == t.wall_angle_b_deg);
      CHECK(j["top_width_mm"].get<double>() == t.top_width_mm);
      CHECK(j["fill_lowest"]["y"].get<double>() == t.fill_lowest_y_mm);
      CHECK(j["fill_lowest"]["z"].get<double>() == t.fill_lowest_z_mm);
      CHECK(j["passes"].get<int>() == t.passes);
      for (const char* b : {"B1", "B2", "B3", "B4", "B5"}) CHECK(j["break_points"].contains(b));
    }
  }
  REQUIRE(run("--joint butt --count 1 --truth " + (dir / "b.jsonl"), dir) == 0);
  const auto j = nlohmann::json::parse(slurp(dir / "b.jsonl"));
  CHECK(j["passes"].is_null());
  CHECK(j["fill_lowest"].is_null());
  CHECK(j["wall_angle_a_deg"].is_null());
}

TEST_CASE("vts-corpus: a recording numbers its profiles and keeps its seed", "[corpus][cli]") {
  TempDir dir;
  REQUIRE(run("--joint vgroove --recording --count 30 --seed 3 --ds 0.5 --decoy-every 10 --columns 300 --truth " +
                  (dir / "r.jsonl"),
              dir) == 0);
  const std::vector<std::string> truth = split(slurp(dir / "r.jsonl"), '\n');
  REQUIRE(truth.size() == 30u);
  for (int k = 0; k < 30; ++k) {
    const auto j = nlohmann::json::parse(truth[k]);
    CHECK(j["profile"] == k);
    CHECK(j["index"] == k);
    CHECK(j["seed"] == 3);
    CHECK(j["s_mm"].get<double>() == Approx(0.5 * k));
    CHECK(j["columns"] == 300);
    CHECK(j["decoy_point"].is_null() == ((k + 1) % 10 != 0));
  }
}

TEST_CASE("vts-corpus: bad arguments exit 2 and write nothing", "[corpus][cli]") {
  TempDir dir;
  const std::string out = " --csv " + (dir / "x.csv") + " --truth " + (dir / "x.jsonl");
  const std::vector<std::string> bad = {
      "--count 3" + out,                                   // no joint
      "--joint tee" + out,                                 // unknown joint
      "--joint butt --count 0" + out,                      // count
      "--joint butt --count 2x" + out,                     // not a number
      "--joint butt --noise -1" + out,                     // noise
      "--joint butt --noise abc" + out,                    // noise
      "--joint butt --columns 8" + out,                    // columns
      "--joint butt --seed -4" + out,                      // seed
      "--joint fillet --prob backing_bar=1" + out,         // a variant the joint does not have
      "--joint butt --prob gap=2" + out,                   // probability
      "--joint butt --prob gap" + out,                     // NAME=P
      "--joint butt --ds 0.5" + out,                       // needs --recording
      "--joint butt --frobnicate" + out,                   // unknown option
      "--joint butt",                                      // nothing to write
      "--joint butt --csv " + (dir / "missing/x.csv"),     // no such directory
      "--joint butt --csv " + (dir / "same") + " --truth " + (dir / "same"),
  };
  for (const std::string& args : bad) {
    INFO(args);
    CHECK(run(args, dir) == 2);
    CHECK(dir.files() == 2u);  // stdout.txt and stderr.txt only
    CHECK(slurp(dir / "stderr.txt").rfind("vts-corpus: ", 0) == 0);
  }
  CHECK(run("--help", dir) == 0);
  CHECK(slurp(dir / "stdout.txt").find("--joint TYPE") != std::string::npos);
}
