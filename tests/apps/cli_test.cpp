// Runs bin/vts in a fresh temporary directory and checks exit codes, messages
// and the files it leaves behind.
#include <sys/wait.h>
#include <csignal>
#include <cstdio>
#include <unistd.h>

#include <catch2/catch.hpp>

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "sensor/cell.h"
#include "sensor/error_model.h"
#include "sensor/mesh_file.h"
#include "sensor/profile_exr.h"
#include "sensor/scene_file.h"
#include "vts_runner.h"

namespace {

namespace fs = std::filesystem;
using namespace vts_test;

const fs::path kExamples = fs::path(VTS_SOURCE_DIR) / "examples";

// Raster and reference channels of one recording. Ideal profiles: ranges
// agree to 1 um where both are valid; hit/miss differs in at most 2 columns of
// any profile (only a ray grazing a mesh edge can do that). With the error
// model on, both sources' ideal profiles went through the same draws, so the
// measured depths differ by at most one quantization step (a sub-micrometre
// difference can round to the neighbouring step), and camera-shadow edges may
// add a column or two.
void check_against_reference(const vts::ProfileRecording& rec) {
  REQUIRE(rec.info.has_reference);
  REQUIRE(rec.reference.size() == rec.profiles.size());
  const bool model = rec.info.error_model;
  int total_valid = 0;
  for (std::size_t i = 0; i < rec.profiles.size(); ++i) {
    const vts::Profile& p = rec.profiles[i];
    const vts::Profile& r = rec.reference[i];
    REQUIRE(p.size() == r.size());
    int disagreements = 0;
    double max_excess = 0.0;
    for (int c = 0; c < p.size(); ++c) {
      if (p.valid[c] && r.valid[c]) {
        const double allowed =
            model ? 1.01 * vts::depth_step_mm(rec.info.scanner, p.z_mm[c]) + 0.001 : 0.001;
        const double diff = model ? std::abs(p.z_mm[c] - r.z_mm[c]) : std::abs(p.range_mm[c] - r.range_mm[c]);
        max_excess = std::max(max_excess, diff - allowed);
      } else if (p.valid[c] != r.valid[c]) {
        ++disagreements;
      }
    }
    INFO("profile " << i);
    CHECK(max_excess <= 0.0);
    CHECK(disagreements <= (model ? 4 : 2));
    total_valid += p.valid_count();
  }
  CHECK(total_valid > 0);
}

}  // namespace

TEST_CASE("vts: no subcommand prints help and exits 0", "[cli]") {
  TempDir dir;
  const Result r = run_vts(dir, "");
  CHECK(r.code == 0);
  CHECK(contains(r.out, "scan"));
  CHECK(contains(r.out, "cells"));
  CHECK(contains(r.out, "--version"));
}

TEST_CASE("vts: --version", "[cli]") {
  TempDir dir;
  const Result r = run_vts(dir, "--version");
  CHECK(r.code == 0);
  CHECK(contains(r.out, "vts 0."));
}

TEST_CASE("vts cells: lists every built-in cell with a description", "[cli]") {
  TempDir dir;
  const Result r = run_vts(dir, "cells");
  REQUIRE(r.code == 0);
  std::istringstream lines(r.out);
  std::vector<std::string> got;
  for (std::string line; std::getline(lines, line);) got.push_back(line);
  const auto names = vts::builtin_cell_names();
  REQUIRE(got.size() == names.size());
  for (std::size_t i = 0; i < names.size(); ++i) {
    INFO(got[i]);
    CHECK(got[i].rfind(names[i] + " ", 0) == 0);
    CHECK(got[i].size() > names[i].size() + 10);  // a description follows
  }
}

TEST_CASE("vts scan --help: every option with units", "[cli]") {
  TempDir dir;
  const Result r = run_vts(dir, "scan --help");
  REQUIRE(r.code == 0);
  for (const char* opt : {"--cell", "--scene", "--start", "--direction", "--step", "--speed", "--rate",
                          "--profiles", "--standoff", "--points", "--seed", "--out", "--reference",
                          "--source"})
    CHECK(contains(r.out, opt));
  for (const char* unit : {"mm", "mm/s", "Hz", "16..4096"}) CHECK(contains(r.out, unit));
}

TEST_CASE("vts scan: no arguments writes static-B.exr and says where", "[cli][gl]") {
  TempDir dir;
  const Result r = run_vts(dir, "scan");
  INFO(r.out << r.err);
  REQUIRE(r.code == 0);
  const fs::path file = fs::canonical(dir.path) / "static-B.exr";
  CHECK(fs::exists(file));
  CHECK(contains(r.out, "wrote 100 profiles x 512 points to " + file.string() + "\n"));
  CHECK(contains(r.out, "valid"));
  CHECK(contains(r.out, "mean range"));
  CHECK(r.err.empty());  // short runs print no progress
  const vts::ProfileRecording rec = vts::read_profile_exr(file);
  CHECK(rec.info.scene_name == "static-B");
  CHECK(rec.profiles.size() == 100);
  CHECK_FALSE(rec.info.has_reference);
  // The header's scene text rebuilds the cell that was scanned.
  const vts::Cell stored = vts::parse_scene(rec.info.scene_text, "header");
  const vts::Cell builtin = *vts::builtin_cell("static-B");
  CHECK(stored.name == "static-B");
  CHECK((stored.path.start.matrix() - builtin.path.start.matrix()).cwiseAbs().maxCoeff() < 1e-9);
  CHECK(stored.workpieces.size() == builtin.workpieces.size());
}

TEST_CASE("vts scan: every built-in cell - raster against the Embree reference", "[cli][gl]") {
  // fillet-1m (a million triangles) is scanned in "vts mesh: fillet-1m" below.
  for (const std::string& name : vts::builtin_cell_names(vts::CellSet::Small)) {
    DYNAMIC_SECTION(name) {
      TempDir dir;
      const Result r = run_vts(dir, "scan --cell " + name + " --reference --profiles 5 --out x.exr");
      INFO(r.out << r.err);
      REQUIRE(r.code == 0);
      const vts::ProfileRecording rec = vts::read_profile_exr(dir.path / "x.exr");
      CHECK(rec.info.scene_name == name);
      REQUIRE(rec.profiles.size() == 5);
      check_against_reference(rec);
      // Rows follow the cell's path: pose i = start + i * step * direction, time i / rate.
      const vts::Cell cell = *vts::builtin_cell(name);
      for (int i = 0; i < 5; ++i) {
        const vts::Vec3 expected = cell.path.start.translation() +
                                   i * cell.path.step_mm * cell.path.direction;
        CHECK((rec.profiles[i].world_from_sensor.translation() - expected).norm() < 1e-9);
        CHECK(rec.profiles[i].time_s == Approx(i / cell.scanner.rate_hz));
        CHECK(rec.profiles[i].index == i);
      }
    }
  }
}

TEST_CASE("vts scan: the example scenes run", "[cli][gl]") {
  for (const char* example : {"fillet_gap.yaml", "vgroove.yaml", "lap_tilted.yaml"}) {
    DYNAMIC_SECTION(example) {
      TempDir dir;
      const fs::path scene = kExamples / example;
      const Result r = run_vts(dir, "scan --scene " + shell_quote(scene.string()) +
                                        " --reference --ideal --profiles 5 --out e.exr");
      INFO(r.out << r.err);
      REQUIRE(r.code == 0);
      const vts::ProfileRecording rec = vts::read_profile_exr(dir.path / "e.exr");
      CHECK(rec.info.scene_name == scene.string());
      const vts::Cell original = vts::load_scene(scene);
      CHECK(rec.info.scanner.points == original.scanner.points);
      const vts::Cell stored = vts::parse_scene(rec.info.scene_text, "header");
      CHECK(stored.name == original.name);
      CHECK(stored.path.profiles == 5);  // after the override
      REQUIRE(stored.workpieces.size() == original.workpieces.size());
      CHECK(stored.workpieces[0].params.gap_mm == original.workpieces[0].params.gap_mm);
      check_against_reference(rec);
    }
  }
  SECTION("default output name is the scene's name") {
    TempDir dir;
    const Result r =
        run_vts(dir, "scan --scene " + shell_quote((kExamples / "fillet_gap.yaml").string()) +
                         " --profiles 2");
    INFO(r.out << r.err);
    REQUIRE(r.code == 0);
    CHECK(fs::exists(dir.path / "fillet-gap.exr"));
  }
}

TEST_CASE("vts scan: path and scanner and seed overrides", "[cli]") {
  // The Embree source alone needs no GL context.
  TempDir dir;
  const Result r = run_vts(dir,
                           "scan --cell plate --source reference --start=10,-5,90 --direction 0,2,0 "
                           "--step 0.25 --profiles 7 --points 64 --rate 100 --seed 18446744073709551615 "
                           "--out sub/o.exr");
  INFO(r.out << r.err);
  REQUIRE(r.code == 0);
  const vts::ProfileRecording rec = vts::read_profile_exr(dir.path / "sub" / "o.exr");
  REQUIRE(rec.profiles.size() == 7);
  CHECK(rec.info.scanner.points == 64);
  CHECK(rec.info.scanner.rate_hz == 100.0);
  const vts::Cell plate = *vts::builtin_cell("plate");
  for (int i = 0; i < 7; ++i) {
    const vts::Pose& pose = rec.profiles[i].world_from_sensor;
    CHECK((pose.translation() - vts::Vec3(10, -5 + 0.25 * i, 90)).norm() < 1e-9);
    // Orientation kept from the cell's path.
    CHECK((pose.linear() - plate.path.start.linear()).cwiseAbs().maxCoeff() < 1e-9);
    CHECK(rec.profiles[i].time_s == Approx(i / 100.0));
    // Straight down onto the plate top (z = 0) from 90 mm: the middle column's
    // ground truth is 90 mm; the measurement is within 6 sd of the speckle
    // noise plus a quantization step of it.
    CHECK(rec.profiles[i].true_valid[32]);
    CHECK(rec.profiles[i].true_z_mm[32] == Approx(90.0).margin(1e-3));
    if (rec.profiles[i].valid[32]) {
      const double tol = 6.0 * vts::depth_noise_mm(rec.info.scanner, 90.0) +
                         vts::depth_step_mm(rec.info.scanner, 90.0);
      CHECK(rec.profiles[i].z_mm[32] == Approx(90.0).margin(tol));
    }
  }

  SECTION("--speed with --rate sets the step") {
    TempDir d2;
    const Result s = run_vts(d2, "scan --cell plate --source reference --speed 50 --rate 25 "
                                 "--profiles 3 --out s.exr");
    INFO(s.out << s.err);
    REQUIRE(s.code == 0);
    const vts::ProfileRecording srec = vts::read_profile_exr(d2.path / "s.exr");
    const double step = (srec.profiles[1].world_from_sensor.translation() -
                         srec.profiles[0].world_from_sensor.translation()).norm();
    CHECK(step == Approx(2.0).margin(1e-9));
    CHECK(srec.profiles[2].time_s == Approx(2 / 25.0));
  }
  SECTION("--standoff re-derives the path of a built-in cell") {
    TempDir d3;
    const Result s = run_vts(d3, "scan --cell plate --source reference --standoff 150 "
                                 "--profiles 1 --points 64 --ideal --out s.exr");
    INFO(s.out << s.err);
    REQUIRE(s.code == 0);
    const vts::ProfileRecording srec = vts::read_profile_exr(d3.path / "s.exr");
    CHECK(srec.profiles[0].z_mm[32] == Approx(150.0).margin(1e-3));
  }
}

TEST_CASE("vts scan: bad inputs exit 2 - name the option and value - create nothing", "[cli]") {
  struct Case {
    std::string args;
    std::vector<std::string> expected;  // in stderr
  };
  const std::string bad_scene =
      "workpieces:\n"
      "  - joint: fillet\n"
      "    gap_mm: abc\n";
  const std::string broken_scene = "workpieces:\n  - joint: [fillet\n";
  const std::vector<Case> cases = {
      {"--cell nosuch", {"--cell", "'nosuch'", "unknown cell", "static-B", "vgroove"}},
      {"--points 8", {"--points", "'8'", "16 to 4096"}},
      {"--points abc", {"--points", "'abc'"}},
      {"--points 5000", {"--points", "'5000'"}},
      {"--step -1", {"--step", "'-1'", "> 0"}},
      {"--step 0", {"--step", "'0'"}},
      {"--step nan", {"--step", "'nan'", "finite"}},
      {"--speed=-3", {"--speed", "'-3'"}},
      {"--rate 0", {"--rate", "'0'"}},
      {"--profiles 0", {"--profiles", "'0'"}},
      {"--profiles 1.5", {"--profiles", "'1.5'"}},
      {"--direction 0,0,0", {"--direction", "'0,0,0'", "zero"}},
      {"--direction 1,2", {"--direction", "'1,2'", "X,Y,Z"}},
      {"--start 1,x,3", {"--start", "'1,x,3'"}},
      {"--start 1,inf,3", {"--start", "finite"}},
      {"--seed=-1", {"--seed", "'-1'"}},
      {"--source gpu", {"--source", "'gpu'"}},
      {"--scene missing.yaml", {"missing.yaml", "not found"}},
      {"--scene bad.yaml", {"bad.yaml:3: workpieces[0].gap_mm", "'abc'"}},
      {"--scene broken.yaml", {"broken.yaml:", "YAML syntax error"}},
      {"--scene bad.yaml --cell fillet", {"--cell", "--scene"}},
      {"--step 1 --speed 2", {"--step", "--speed"}},
      {"--scene " + shell_quote((kExamples / "vgroove.yaml").string()) + " --standoff 50",
       {"--standoff", "built-in"}},
      {"--out .", {"--out", "directory"}},
      {"--out bad.yaml/x.exr", {"--out", "'bad.yaml/x.exr'", "not a directory"}},
      {"--bogus 1", {"--bogus"}},
  };
  for (const Case& c : cases) {
    DYNAMIC_SECTION(c.args) {
      TempDir dir;
      std::ofstream(dir.path / "bad.yaml") << bad_scene;
      std::ofstream(dir.path / "broken.yaml") << broken_scene;
      const std::string args = "scan " + c.args + (contains(c.args, "--out") ? "" : " --out x.exr");
      const Result r = run_vts(dir, args);
      INFO("vts " << args << "\nstdout: " << r.out << "\nstderr: " << r.err);
      CHECK(r.code == 2);
      for (const auto& e : c.expected) CHECK(contains(r.err, e));
      CHECK(r.out.empty());
      std::vector<std::string> files = dir.files();
      std::erase(files, "bad.yaml");
      std::erase(files, "broken.yaml");
      CHECK(files.empty());  // no x.exr, no temporary file
    }
  }
}

TEST_CASE("vts scan: a failing EXR write exits 1 and leaves no file", "[cli]") {
  TempDir dir;
  // /proc accepts no new files, even for root.
  const Result r = run_vts(dir, "scan --cell plate --source reference --profiles 2 --out /proc/vts_x.exr");
  INFO(r.out << r.err);
  CHECK(r.code == 1);
  CHECK(contains(r.err, "/proc/vts_x.exr"));
  CHECK_FALSE(fs::exists("/proc/vts_x.exr"));
}

TEST_CASE("vts sensors: lists the presets with near and far resolution and the materials",
          "[cli]") {
  TempDir dir;
  const Result r = run_vts(dir, "sensors");
  INFO(r.out << r.err);
  REQUIRE(r.code == 0);
  for (const char* name : {"mspot", "lps-2048-short", "lps-1280-mid", "matte-steel", "shiny-steel",
                           "aluminium", "rough", "lambertian"})
    CHECK(contains(r.out, name));
  // The paper's figures, from the default preset's camera.
  CHECK(contains(r.out, "depth step 0.0150 mm at 100 mm"));
  CHECK(contains(r.out, "1.5000 mm at 1000 mm"));

  const Result p = run_vts(dir, "sensors --plot res.png --sensor lps-1280-mid");
  INFO(p.out << p.err);
  CHECK(p.code == 0);
  CHECK(fs::file_size(dir.path / "res.png") > 1000);
  const Result bad = run_vts(dir, "sensors --plot x.png --sensor nope");
  CHECK(bad.code == 2);
  CHECK(contains(bad.err, "--sensor 'nope': unknown sensor"));
  CHECK_FALSE(fs::exists(dir.path / "x.png"));
}

TEST_CASE("vts scan: the same seed writes the same bytes - another seed does not", "[cli][gl]") {
  // (Issue 3, 7e.) Two runs of one scan with the error model on.
  TempDir dir;
  auto scan = [&](const std::string& seed, const std::string& out) {
    const Result r = run_vts(dir, "scan --cell lap --material shiny-steel --profiles 30 --seed " +
                                      seed + " --out " + out);
    INFO(r.out << r.err);
    REQUIRE(r.code == 0);
    return slurp(dir.path / out);
  };
  const std::string a = scan("5", "a.exr"), b = scan("5", "b.exr"), c = scan("6", "c.exr");
  CHECK(a.size() > 1000);
  CHECK(a == b);
  CHECK(a != c);
}

TEST_CASE("vts scan: error model channels - ground truth - intensity - presets", "[cli][gl]") {
  TempDir dir;
  SECTION("default: measured points plus true.* and intensity") {
    const Result r = run_vts(dir, "scan --cell fillet --profiles 3 --out m.exr");
    INFO(r.out << r.err);
    REQUIRE(r.code == 0);
    CHECK(contains(r.out, "error model (mspot, matte-steel, seed 0)"));
    const vts::ProfileRecording rec = vts::read_profile_exr(dir.path / "m.exr");
    CHECK(rec.info.error_model);
    CHECK_FALSE(rec.info.scanner.ideal);
    int measured_off_truth = 0, with_intensity = 0;
    for (const vts::Profile& p : rec.profiles)
      for (int i = 0; i < p.size(); ++i) {
        if (!p.valid[i]) continue;
        REQUIRE(p.true_valid[i]);  // a measured point always has a lit ideal point
        measured_off_truth += p.z_mm[i] != p.true_z_mm[i];
        with_intensity += p.intensity[i] > 0.0f && p.intensity[i] <= 1.0f;
        // Within 6 sd of the noise, a step, or an outlier's displacement.
        CHECK(std::abs(p.z_mm[i] - p.true_z_mm[i]) <=
              6.0 * vts::depth_noise_mm(rec.info.scanner, p.true_z_mm[i]) +
                  vts::depth_step_mm(rec.info.scanner, p.true_z_mm[i]) +
                  rec.info.scanner.shiny_offset_max_mm);
      }
    CHECK(measured_off_truth > 100);
    CHECK(with_intensity > 1000);
  }
  SECTION("--ideal: no error model channels and the ideal points") {
    const Result r = run_vts(dir, "scan --cell fillet --profiles 3 --ideal --out i.exr");
    INFO(r.out << r.err);
    REQUIRE(r.code == 0);
    CHECK_FALSE(contains(r.out, "error model"));
    const vts::ProfileRecording rec = vts::read_profile_exr(dir.path / "i.exr");
    CHECK_FALSE(rec.info.error_model);
    CHECK(rec.info.scanner.ideal);
  }
  SECTION("--sensor selects a preset") {
    const Result r = run_vts(dir, "scan --cell vgroove --sensor lps-1280-mid --standoff 200 "
                                  "--profiles 2 --out s.exr");
    INFO(r.out << r.err);
    REQUIRE(r.code == 0);
    const vts::ProfileRecording rec = vts::read_profile_exr(dir.path / "s.exr");
    CHECK(rec.info.scanner.name == "lps-1280-mid");
    CHECK(rec.info.scanner.points == 1280);
    CHECK(rec.info.scanner.rate_hz == 2000.0);
    CHECK(rec.profiles[0].size() == 1280);
    CHECK(rec.profiles[0].valid_count() > 600);
  }
  SECTION("unknown preset names exit 2 naming the option") {
    Result r = run_vts(dir, "scan --sensor nope --out n.exr");
    CHECK(r.code == 2);
    CHECK(contains(r.err, "--sensor"));
    CHECK(contains(r.err, "mspot, lps-2048-short, lps-1280-mid"));
    r = run_vts(dir, "scan --material glass --out n.exr");
    CHECK(r.code == 2);
    CHECK(contains(r.err, "--material"));
    CHECK_FALSE(fs::exists(dir.path / "n.exr"));
  }
}

namespace {

// Starts `vts ARGS...` in dir (no shell), stdout/stderr to files there.
pid_t spawn_vts(const TempDir& dir, const std::vector<std::string>& args) {
  const pid_t pid = fork();
  if (pid == 0) {
    if (chdir(dir.path.c_str()) != 0) _exit(127);
    std::freopen("stdout.txt", "w", stdout);
    std::freopen("stderr.txt", "w", stderr);
    std::vector<char*> argv;
    std::string exe = kVts.string();
    argv.push_back(exe.data());
    std::vector<std::string> copy = args;
    for (auto& a : copy) argv.push_back(a.data());
    argv.push_back(nullptr);
    execv(exe.c_str(), argv.data());
    _exit(127);
  }
  return pid;
}

// Any file in dir whose name starts with prefix.
bool any_file_starting(const fs::path& dir, const std::string& prefix) {
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().filename().string().rfind(prefix, 0) == 0) return true;
  return false;
}

}  // namespace

TEST_CASE("vts scan: SIGINT or SIGTERM leaves no file under the output name", "[cli]") {
  // (Issue 8, 4.) A scan far too long to finish (2M profiles of 4,096 points,
  // minutes) is stopped once its temporary file exists; then the same seed
  // still writes the same bytes. Not 100M profiles: OpenEXR sets up its line
  // offset table of that many rows for about 35 s before the first profile.
  TempDir dir;
  const Result first = run_vts(dir, "scan --cell lap --source reference --profiles 300 --seed 11 --out before.exr");
  REQUIRE(first.code == 0);
  const std::string before = slurp(dir.path / "before.exr");

  for (int sig : {SIGINT, SIGTERM}) {
    DYNAMIC_SECTION("signal " << sig) {
      const pid_t pid = spawn_vts(dir, {"scan", "--cell", "lap", "--source", "reference",
                                        "--points", "4096", "--profiles", "2000000", "--seed",
                                        "11", "--out", "long.exr"});
      REQUIRE(pid > 0);
      // Wait (up to 60 s) for the writer's temporary file, then signal.
      bool started = false;
      for (int k = 0; k < 6000 && !started; ++k) {
        started = any_file_starting(dir.path, "long.exr.tmp-");
        if (!started) usleep(10000);
      }
      REQUIRE(started);
      usleep(200000);
      REQUIRE(kill(pid, sig) == 0);
      int status = 0;
      REQUIRE(waitpid(pid, &status, 0) == pid);
      REQUIRE(WIFEXITED(status));
      CHECK(WEXITSTATUS(status) == 128 + sig);
      const std::string err = slurp(dir.path / "stderr.txt");
      INFO(err);
      CHECK(contains(err, sig == SIGTERM ? "interrupted by SIGTERM" : "interrupted by SIGINT"));
      CHECK(contains(err, "nothing was written to"));
      CHECK_FALSE(fs::exists(dir.path / "long.exr"));
      CHECK_FALSE(any_file_starting(dir.path, "long.exr.tmp-"));

      const Result again = run_vts(dir, "scan --cell lap --source reference --profiles 300 --seed 11 --out after.exr");
      REQUIRE(again.code == 0);
      CHECK(slurp(dir.path / "after.exr") == before);
    }
  }
}

namespace {

// "position_mm: [x, y, z]" and "rpy_deg: [r, p, y]" lines of a pose, exactly.
std::string pose_yaml(const vts::Pose& pose, const std::string& indent) {
  const auto list = [](const vts::Vec3& v) {
    char buf[128];
    std::snprintf(buf, sizeof buf, "[%.17g, %.17g, %.17g]", v.x(), v.y(), v.z());
    return std::string(buf);
  };
  return indent + "position_mm: " + list(pose.translation()) + "\n" + indent + "rpy_deg: " +
         list(vts::rpy_deg_of(pose)) + "\n";
}

}  // namespace

TEST_CASE("vts mesh: a cell written as STL scans back through a scene file like the cell", "[cli]") {
  TempDir dir;
  const Result w = run_vts(dir, "mesh --cell fillet --out parts/fillet.stl");
  INFO(w.out << w.err);
  REQUIRE(w.code == 0);
  const vts::Cell cell = *vts::builtin_cell("fillet");
  const std::size_t triangles = cell.mesh().triangle_count();
  CHECK(contains(w.out, "wrote " + std::to_string(triangles) + " triangles"));
  CHECK(contains(w.out, "closed"));
  CHECK(w.err.empty());
  CHECK(vts::load_mesh_file(dir.path / "parts/fillet.stl").triangle_count() == triangles);

  // The scene: the STL (relative to the scene file), the built-in cell's path.
  fs::create_directories(dir.path / "scenes");
  dir.write("scenes/fillet_mesh.yaml", "scanner:\n  points: 256\n"
                                       "workpieces:\n  - mesh: ../parts/fillet.stl\n    joint: fillet\n"
                                       "path:\n  start:\n" + pose_yaml(cell.path.start, "    ") +
                                       "  profiles: 4\n");
  const Result m = run_vts(dir, "scan --scene scenes/fillet_mesh.yaml --source reference --ideal --out m.exr");
  INFO(m.out << m.err);
  REQUIRE(m.code == 0);
  CHECK(m.err == "vts scan: workpieces[0]: mesh scenes/../parts/fillet.stl: " + std::to_string(triangles) +
                     " triangles, 0 degenerate skipped, 0 open edges\n");
  const Result c = run_vts(dir, "scan --cell fillet --source reference --ideal --points 256 --profiles 4 --out c.exr");
  REQUIRE(c.code == 0);
  CHECK(c.err.empty());
  const vts::ProfileRecording rm = vts::read_profile_exr(dir.path / "m.exr");
  const vts::ProfileRecording rc = vts::read_profile_exr(dir.path / "c.exr");
  REQUIRE(rm.profiles.size() == 4);
  REQUIRE(rc.profiles.size() == 4);
  int valid = 0;
  for (std::size_t i = 0; i < 4; ++i)
    for (int k = 0; k < 256; ++k) {
      INFO("profile " << i << " column " << k);
      REQUIRE(rm.profiles[i].valid[k] == rc.profiles[i].valid[k]);
      CHECK(std::abs(rm.profiles[i].range_mm[k] - rc.profiles[i].range_mm[k]) <= 1e-4);
      valid += rm.profiles[i].valid[k];
    }
  CHECK(valid > 4 * 256 / 2);
  // The recording's scene names the mesh (absolute) and the joint; vts track
  // takes the fillet template from it without reading the mesh.
  const vts::Cell stored = vts::parse_scene(rm.info.scene_text, "header", vts::MeshFiles::Skip);
  REQUIRE(stored.workpieces.size() == 1);
  CHECK(stored.workpieces[0].mesh_file == fs::canonical(dir.path / "parts/fillet.stl").string());
  fs::remove(dir.path / "parts/fillet.stl");
  const Result t = run_vts(dir, "track m.exr --independent");
  INFO(t.out << t.err);
  REQUIRE(t.code == 0);
  std::istringstream lines(t.out);
  int n = 0;
  for (std::string line; std::getline(lines, line); ++n) {
    CHECK(contains(line, "\"joint\":\"fillet\""));
    CHECK(contains(line, "\"status\":\"ok\""));
  }
  CHECK(n == 4);
}

TEST_CASE("vts mesh: fillet-1m as binary PLY", "[cli]") {
  TempDir dir;
  const Result r = run_vts(dir, "mesh --cell fillet-1m --out fillet-1m.ply");
  INFO(r.out << r.err);
  REQUIRE(r.code == 0);
  CHECK(contains(r.out, "wrote 1010888 triangles, 505448 vertices"));
  CHECK(contains(r.out, "closed"));
  std::ifstream in(dir.path / "fillet-1m.ply", std::ios::binary);
  std::string header;
  for (std::string line; std::getline(in, line) && line != "end_header";) header += line + "\n";
  CHECK(contains(header, "format binary_little_endian 1.0\n"));
  CHECK(contains(header, "element vertex 505448\n"));
  CHECK(contains(header, "element face 1010888\n"));
  const auto data_start = static_cast<std::uintmax_t>(in.tellg());
  CHECK(fs::file_size(dir.path / "fillet-1m.ply") == data_start + 12 * 505448 + 13 * 1010888);
  CHECK(dir.files() == std::vector<std::string>{"fillet-1m.ply"});
}

TEST_CASE("vts mesh: bad inputs exit 2 and create nothing", "[cli]") {
  struct Case {
    std::string args, expected;
  };
  const std::vector<Case> cases = {
      {"--cell nosuch --out x.stl", "vts mesh: --cell = 'nosuch': unknown cell; valid names: fillet, corner"},
      {"--cell fillet --out x.step", "vts mesh: --out = 'x.step': unsupported mesh file type '.step' (expected .stl, .obj or .ply)"},
      {"--cell fillet", "--out is required"},
      {"--scene missing.yaml --out x.stl", "vts mesh: --scene: missing.yaml:0: scene file not found"},
      {"--scene m.yaml --out x.stl", "vts mesh: --scene: m.yaml:2: workpieces[0].mesh: nothing.obj: mesh file not found"},
      {"--cell fillet --scene m.yaml --out x.stl", "--cell"},
  };
  for (const Case& c : cases) {
    DYNAMIC_SECTION(c.args) {
      TempDir dir;
      dir.write("m.yaml", "workpieces:\n  - mesh: nothing.obj\n");
      const Result r = run_vts(dir, "mesh " + c.args);
      INFO("stdout: " << r.out << "\nstderr: " << r.err);
      CHECK(r.code == 2);
      CHECK(contains(r.err, c.expected));
      CHECK(r.out.empty());
      CHECK(dir.files() == std::vector<std::string>{"m.yaml"});
    }
  }
}

TEST_CASE("vts scan, static: 1 and 2 threads write the same bytes", "[cli][gl][threads]") {
  // Draws are keyed by profile index and every split of a batch gives the
  // same rows, so the thread limit (docs/CLI.md, --threads) changes nothing
  // in the output. 1100 profiles: two full batches of 512 and one of 76,
  // split at a point that is not a multiple of the raster's 16-profile blocks.
  TempDir dir;
  auto scan = [&](const std::string& args, const std::string& out) {
    const Result r = run_vts(dir, "scan --cell fillet --profiles 1100 --seed 3 " + args + " --out " + out);
    INFO(r.out << r.err);
    REQUIRE(r.code == 0);
    return slurp(dir.path / out);
  };
  const std::string one = scan("--reference --threads 1", "r1.exr");
  const std::string two = scan("--reference --threads 2", "r2.exr");
  CHECK(one.size() > 100000);
  CHECK(one == two);
  CHECK(scan("--source reference --threads 1", "e1.exr") == scan("--source reference --threads 2", "e2.exr"));
  for (const char* threads : {"1", "2"}) {
    const Result r =
        run_vts(dir, std::string("static --profiles 70 --out-dir s") + threads + " --threads " + threads);
    INFO(r.out << r.err);
    REQUIRE(r.code == 0);
  }
  for (const char* file : {"table3.csv", "static-A.png", "static-F.png"})
    CHECK(slurp(dir.path / "s1" / file) == slurp(dir.path / "s2" / file));
}

TEST_CASE("vts scan: --threads and VTS_THREADS checked before anything is written", "[cli][threads]") {
  TempDir dir;
  Result r = run_vts(dir, "scan --threads 0 --out a.exr");
  CHECK(r.code == 2);
  CHECK(contains(r.err, "vts scan: --threads = '0': out of range: expected an integer from 1 to 1024"));
  r = run_vts(dir, "scan --threads two --out a.exr");
  CHECK(r.code == 2);
  CHECK(contains(r.err, "--threads = 'two': expected an integer from 1 to 1024"));
  r = run_vts(dir, "scan --out a.exr", "VTS_THREADS=many");
  CHECK(r.code == 2);
  CHECK(contains(r.err, "vts scan: VTS_THREADS = 'many': expected an integer >= 1"));
  r = run_vts(dir, "static --out-dir s", "VTS_THREADS=many");
  CHECK(r.code == 2);
  CHECK(contains(r.err, "vts static: VTS_THREADS = 'many': expected an integer >= 1"));
  CHECK(dir.files().empty());
}
