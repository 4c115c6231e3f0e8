// `vts track` and `vts static` end to end: runs bin/vts in a fresh temporary
// directory and checks its output against geometry worked out here.
#include <sys/wait.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "sensor/cell.h"
#include "sensor/error_model.h"
#include "vts_runner.h"

namespace {

namespace fs = std::filesystem;
using namespace vts_test;
using Json = nlohmann::json;
constexpr double kDeg = std::numbers::pi / 180.0;


std::vector<Json> json_lines(const std::string& text) {
  std::vector<Json> out;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) out.push_back(Json::parse(line));
  return out;
}

// A 90-degree fillet seen on its bisector with the root at (0, 100) in the
// sensor frame: the plates are z = 100 + y (y < 0) and z = 100 - y (y > 0).
// Column i's ray (0, t_i, 1), t_i = tan(20 deg) (2 (i + 0.5) / n - 1), meets
// them at z = 100 / (1 + |t_i|).
struct AnalyticFillet {
  int n = 256;
  double t(int i) const { return std::tan(20.0 * kDeg) * (2.0 * (i + 0.5) / n - 1.0); }
  double z(int i) const { return 100.0 / (1.0 + std::abs(t(i))); }
  double y(int i) const { return t(i) * z(i); }
};

std::string fmt9(double v) {
  char b[40];
  std::snprintf(b, sizeof b, "%.9g", v);
  return b;
}

double num(const Json& j) { return j.get<double>(); }

}  // namespace

TEST_CASE("vts track: a sequence rejects a joint that jumps, --independent reads it", "[cli][track]") {
  // Twelve profiles of the analytic fillet, 0.5 mm apart along the seam;
  // profile 6 shows it 25 mm to the side (a second joint, or the sensor's
  // view of something else): read alone it is a fillet there; in the
  // sequence, once the joint is confirmed by three readings, it lies outside
  // the region of interest (1.5 mm + 0.5 x 0.5 mm) and is rejected.
  TempDir dir;
  const AnalyticFillet f;
  std::string csv = "profile,y,z,valid\n";
  for (int k = 0; k < 12; ++k)
    for (int i = 0; i < f.n; ++i)
      csv += std::to_string(k) + "," + fmt9(f.y(i) + (k == 6 ? 25.0 : 0.0)) + "," + fmt9(f.z(i)) + ",1\n";
  dir.write("seq.csv", csv);
  Result r = run_vts(dir, "track seq.csv --travel 0.5");
  INFO(r.err);
  REQUIRE(r.code == 0);
  auto lines = json_lines(r.out);
  REQUIRE(lines.size() == 12);
  for (int k = 0; k < 12; ++k) {
    const Json& j = lines[k];
    INFO("profile " << k << ": " << j.dump());
    REQUIRE(j.contains("sequence"));
    if (k < 2) {
      CHECK(j["status"] == "rejected");
      CHECK(j["reason"] == "acquiring: " + std::to_string(k + 1) + " of 3 consistent readings");
      CHECK(j["sequence"]["locked"] == false);
    } else if (k == 6) {
      CHECK(j["status"] == "rejected");
      CHECK(j["reason"].get<std::string>().rfind("no joint within 1.75 mm of the predicted point", 0) == 0);
      CHECK(num(j["sequence"]["region"]["radius_mm"]) == Approx(1.75));
    } else {
      CHECK(j["status"] == "ok");
      CHECK(j["sequence"]["locked"] == true);
      CHECK(num(j["track_point"]["y"]) == Approx(0.0).margin(1e-4));
      CHECK(num(j["sequence"]["filtered"]["y"]) == Approx(0.0).margin(1e-4));
      CHECK(num(j["sequence"]["filtered"]["z"]) == Approx(100.0).margin(1e-4));
    }
  }
  r = run_vts(dir, "track seq.csv --independent");
  REQUIRE(r.code == 0);
  lines = json_lines(r.out);
  REQUIRE(lines.size() == 12);
  CHECK_FALSE(lines[0].contains("sequence"));
  CHECK(lines[6]["status"] == "ok");
  CHECK(num(lines[6]["track_point"]["y"]) == Approx(25.0).margin(1e-4));
  // --travel takes a number >= 0.
  r = run_vts(dir, "track seq.csv --travel -1");
  CHECK(r.code == 2);
  CHECK(r.err == "vts track: --travel = '-1': out of range: expected >= 0 mm\n");
}

TEST_CASE("vts track: CSV of an analytic fillet gives the hand-computed joint", "[cli][track]") {
  TempDir dir;
  const AnalyticFillet f;
  std::string csv = "profile,y,z,valid\n";
  for (int i = 0; i < f.n; ++i) csv += "0," + fmt9(f.y(i)) + "," + fmt9(f.z(i)) + ",1\n";
  // Profile 4: a flat plate at z = 80 (one segment), profile 9: three points.
  for (int i = 0; i < 40; ++i) csv += "4," + fmt9(-10.0 + 0.5 * i) + ",80,1\n";
  csv += "9,0,50,1\n9,1,50,1\n9,2,50,0\n9,3,50,1\n";
  dir.write("fillet.csv", csv);
  const Result r = run_vts(dir, "track fillet.csv --independent");
  INFO(r.err);
  REQUIRE(r.code == 0);
  CHECK(r.err.empty());
  const auto lines = json_lines(r.out);
  REQUIRE(lines.size() == 3);

  const Json& j = lines[0];
  CHECK(j["profile"] == 0);
  CHECK(j["joint"] == "fillet");
  CHECK(j["status"] == "ok");
  CHECK_FALSE(j.contains("reason"));
  CHECK(num(j["track_point"]["y"]) == Approx(0.0).margin(1e-4));
  CHECK(num(j["track_point"]["z"]) == Approx(100.0).margin(1e-4));
  CHECK(num(j["angle_deg"]) == Approx(90.0).margin(1e-3));
  CHECK(num(j["gap_mm"]) == Approx(0.0).margin(1e-4));
  CHECK(num(j["gap_paper_mm"]) == Approx(0.0).margin(1e-4));
  CHECK(j["mismatch_mm"].is_null());
  CHECK(j["step_mm"].is_null());
  CHECK(j["depth_mm"].is_null());
  CHECK(j["area_mm2"].is_null());
  CHECK(j["valid_points"] == f.n);
  CHECK(j["outliers"] == 0);
  // B0: the flange's outer end = column 0's point; B4 = the last column's
  // (with no gap the second plate in scan order is the web); B1..B3 the root.
  const Json& bp = j["break_points"];
  REQUIRE(bp.size() == 5);
  const double expect[5][2] = {{f.y(0), f.z(0)}, {0, 100}, {0, 100}, {0, 100}, {f.y(f.n - 1), f.z(f.n - 1)}};
  const char* meaning[5] = {"flange outer end", "root", "flange end seen under the web", "web edge",
                            "web outer end"};
  for (int k = 0; k < 5; ++k) {
    INFO("B" << k);
    CHECK(bp[k]["name"] == "B" + std::to_string(k));
    CHECK(bp[k]["meaning"] == meaning[k]);
    CHECK(num(bp[k]["y"]) == Approx(expect[k][0]).margin(1e-4));
    CHECK(num(bp[k]["z"]) == Approx(expect[k][1]).margin(1e-4));
  }
  // Two segments: columns 0..127 (y < 0) and 128..255; normals towards the
  // sensor: (1, -1)/sqrt 2 and (-1, -1)/sqrt 2, c = -100/sqrt 2.
  const Json& segs = j["segments"];
  REQUIRE(segs.size() == 2);
  CHECK(segs[0]["first"] == 0);
  CHECK(segs[0]["last"] == 127);
  CHECK(segs[0]["points"] == 128);
  CHECK(segs[1]["first"] == 128);
  CHECK(segs[1]["last"] == 255);
  const double h = std::sqrt(0.5);
  CHECK(num(segs[0]["line"]["ny"]) == Approx(h).margin(1e-5));
  CHECK(num(segs[0]["line"]["nz"]) == Approx(-h).margin(1e-5));
  CHECK(num(segs[0]["line"]["c"]) == Approx(-100.0 * h).margin(1e-4));
  CHECK(num(segs[1]["line"]["ny"]) == Approx(-h).margin(1e-5));
  CHECK(num(segs[1]["line"]["nz"]) == Approx(-h).margin(1e-5));
  CHECK(num(segs[1]["line"]["c"]) == Approx(-100.0 * h).margin(1e-4));
  CHECK(num(segs[0]["rms_mm"]) < 1e-5);

  CHECK(lines[1]["profile"] == 4);
  CHECK(lines[1]["status"] == "rejected");
  CHECK(lines[1]["reason"] == "too few segments: 1 with at least 8 points, the fillet needs 2");
  CHECK(lines[1]["segments"].size() == 1);
  CHECK(lines[1]["track_point"].is_null());
  CHECK(lines[2]["profile"] == 9);
  CHECK(lines[2]["status"] == "no_data");
  // Islands (docs/JOINTS.md step 1): (0, 50), (1, 50) are cut off by the
  // invalid column but lie on one line that (3, 50) beyond the cut continues,
  // so they are kept as a piece of a surface broken by a dropout; (3, 50)
  // alone in its run is removed. Two points are too few.
  CHECK(lines[2]["reason"] == "2 usable points, at least 8 needed");
  CHECK(lines[2]["valid_points"] == 3);
  CHECK(lines[2]["outliers"] == 1);

  // --out: the same lines in the file, nothing on stdout; --joint changes the template.
  const Result o = run_vts(dir, "track fillet.csv --out track.jsonl --joint corner --independent");
  REQUIRE(o.code == 0);
  CHECK(o.out.empty());
  const auto out_lines = json_lines(slurp(dir.path / "track.jsonl"));
  REQUIRE(out_lines.size() == 3);
  CHECK(out_lines[0]["joint"] == "corner");
  CHECK(out_lines[0]["status"] == "rejected");
  CHECK(out_lines[0]["reason"] == "no outside corner between two plates");
  CHECK(dir.files() == std::vector<std::string>{"fillet.csv", "track.jsonl"});
}

TEST_CASE("vts track: parameters from a YAML file and options", "[cli][track]") {
  TempDir dir;
  const AnalyticFillet f;
  std::string csv = "profile,y,z\n";
  for (int i = 0; i < f.n; ++i) csv += "0," + fmt9(f.y(i)) + "," + fmt9(f.z(i)) + "\n";
  dir.write("fillet.csv", csv);
  // A 90-degree joint outside the accepted angles: rejected with the reason.
  dir.write("narrow.yaml",
            "joint: fillet\n"
            "segmentation:\n"
            "  segments:\n"
            "    split_threshold_mm: 0.5\n"
            "fillet:\n"
            "  angle_deg: [30, 80]\n");
  Result r = run_vts(dir, "track fillet.csv --params narrow.yaml --independent");
  REQUIRE(r.code == 0);
  auto lines = json_lines(r.out);
  REQUIRE(lines.size() == 1);
  CHECK(lines[0]["status"] == "rejected");
  CHECK(lines[0]["reason"] == "angle 90 deg outside [30, 80]");
  // An option overrides the file.
  r = run_vts(dir, "track fillet.csv --params narrow.yaml --angle 85,95 --independent");
  REQUIRE(r.code == 0);
  CHECK(json_lines(r.out)[0]["status"] == "ok");
  // The minimum segment size above the plates' point count: no plate is long enough.
  r = run_vts(dir, "track fillet.csv --min-segment 200 --independent");
  REQUIRE(r.code == 0);
  CHECK(json_lines(r.out)[0]["reason"] == "too few segments: 0 with at least 200 points, the fillet needs 2");
}

TEST_CASE("vts track: bad input exits 2 naming file line field and value", "[cli][track]") {
  TempDir dir;
  dir.write("bad.csv", "profile,y,z\n0,1,2\n0,1,abc\n");
  dir.write("header.csv", "profile,y,depth\n0,1,2\n");
  dir.write("order.csv", "profile,y,z\n2,1,2\n1,1,2\n");
  dir.write("good.csv", "profile,y,z\n0,1,2\n");
  dir.write("profiles.txt", "profile,y,z\n0,1,2\n");
  dir.write("bad_value.yaml", "fillet:\n  gap_mm: [0, 3]\nsegmentation:\n  segments:\n    split_interval: two\n");
  dir.write("bad_key.yaml", "joint: fillet\nsurface_tol: 0.1\n");
  dir.write("bad_range.yaml", "corner:\n  angle_deg: [170, 60]\n");
  dir.write("bad_joint.yaml", "\njoint: tee\n");
  dir.write("bad_syntax.yaml", "joint: [fillet\n");
  dir.write("not.exr", "this is not an EXR file\n");
  const std::pair<std::string, std::string> cases[] = {
      {"track bad.csv --out o.jsonl", "vts track: bad.csv:3: z: 'abc' is not a number\n"},
      {"track header.csv --out o.jsonl",
       "vts track: header.csv:1: header: unknown column 'depth': expected profile, y, z and optionally valid "
       "(names are case-sensitive)\n"},
      {"track order.csv --out o.jsonl",
       "vts track: order.csv:3: profile: 1 after 2: profile indices must not decrease (rows grouped by profile)\n"},
      {"track missing.csv --out o.jsonl", "vts track: missing.csv: no such file\n"},
      {"track profiles.txt --out o.jsonl",
       "vts track: profiles.txt: unknown file type '.txt': expected .exr (vts profile EXR) or .csv\n"},
      {"track good.csv --joint tee --out o.jsonl",
       "vts track: --joint = 'tee': unknown joint; expected fillet, corner, lap, butt, vgroove, bevel, ugroove or jgroove\n"},
      {"track good.csv --split-threshold abc --out o.jsonl",
       "vts track: --split-threshold = 'abc': expected a number in mm\n"},
      {"track good.csv --split-threshold 0 --out o.jsonl",
       "vts track: --split-threshold = '0': out of range: expected > 0 mm\n"},
      {"track good.csv --min-segment 1 --out o.jsonl",
       "vts track: --min-segment = '1': expected an integer from 2 to 4096\n"},
      {"track good.csv --gap 3 --out o.jsonl", "vts track: --gap = '3': expected MIN,MAX in mm\n"},
      {"track good.csv --joint butt --angle 1,2 --out o.jsonl",
       "vts track: --angle = '1,2': the butt template has no angle range\n"},
      {"track good.csv --truth --out o.jsonl",
       "vts track: --truth: good.csv is a CSV file; only EXR files recorded with the error model carry ground "
       "truth\n"},
      {"track good.csv --params bad_value.yaml --out o.jsonl",
       "vts track: --params: bad_value.yaml:5: segmentation.segments.split_interval: expected an integer, got "
       "'two'\n"},
      {"track good.csv --params bad_key.yaml --out o.jsonl",
       "vts track: --params: bad_key.yaml:2: surface_tol: unknown key (expected one of: joint, surface_tol_mm, "
       "max_joint_width_mm, square_edges, hidden_face_deg, segmentation, fillet, corner, lap, butt, vgroove, groove, noise, confidence)\n"},
      {"track good.csv --params bad_range.yaml --out o.jsonl",
       "vts track: --params: bad_range.yaml:2: corner.angle_deg: min 170 is greater than max 60\n"},
      {"track good.csv --params bad_joint.yaml --out o.jsonl",
       "vts track: --params: bad_joint.yaml:2: joint: 'tee' is not a joint; expected fillet, corner, lap, butt, "
       "vgroove, bevel, ugroove or jgroove\n"},
      {"track good.csv --params missing.yaml --out o.jsonl", "vts track: --params: missing.yaml: cannot open file\n"},
      {"track good.csv --out nodir/o.jsonl",
       "vts track: --out = 'nodir/o.jsonl': directory '" + (dir.path / "nodir").string() + "' does not exist\n"},
  };
  for (const auto& [args, message] : cases) {
    INFO(args);
    const Result r = run_vts(dir, args);
    CHECK(r.code == 2);
    CHECK(r.err == message);
    CHECK(r.out.empty());
    CHECK_FALSE(fs::exists(dir.path / "o.jsonl"));
  }
  // yaml-cpp's own syntax errors still name the file and line.
  const Result syn = run_vts(dir, "track good.csv --params bad_syntax.yaml --out o.jsonl");
  CHECK(syn.code == 2);
  CHECK(syn.err.rfind("vts track: --params: bad_syntax.yaml:", 0) == 0);
  const Result exr = run_vts(dir, "track not.exr --out o.jsonl");
  CHECK(exr.code == 2);
  CHECK(exr.err.rfind("vts track: ", 0) == 0);
  CHECK(exr.err.find("not.exr") != std::string::npos);
  // Nothing but the inputs is left behind (no temporary files either).
  for (const auto& name : dir.files()) CHECK(name.find("o.jsonl") == std::string::npos);
}

TEST_CASE("vts track: EXR of the fillet cell from vts scan", "[cli][track][gl]") {
  TempDir dir;
  REQUIRE(run_vts(dir, "scan --cell fillet --ideal --profiles 3 --out f.exr").code == 0);
  // The joint comes from the file's scene. The fillet cell's sensor looks at
  // the root along the bisector from 100 mm: root (0, 100), 90 degrees, no gap.
  Result r = run_vts(dir, "track f.exr --independent");
  INFO(r.err);
  REQUIRE(r.code == 0);
  auto lines = json_lines(r.out);
  REQUIRE(lines.size() == 3);
  for (int i = 0; i < 3; ++i) {
    const Json& j = lines[i];
    CHECK(j["profile"] == i);
    CHECK(j["joint"] == "fillet");
    CHECK(j["status"] == "ok");
    CHECK(num(j["track_point"]["y"]) == Approx(0.0).margin(0.05));
    CHECK(num(j["track_point"]["z"]) == Approx(100.0).margin(0.05));
    CHECK(num(j["angle_deg"]) == Approx(90.0).margin(0.5));
    CHECK(num(j["gap_mm"]) == Approx(0.0).margin(0.1));
  }
  // --truth needs the error model's ground truth channels.
  r = run_vts(dir, "track f.exr --truth");
  CHECK(r.code == 2);
  CHECK(r.err ==
        "vts track: --truth: f.exr has no ground truth channels (true.y, true.z, true.valid: written only when the "
        "error model is on)\n");

  // With the error model on, --truth tracks the ideal points: the same joint
  // to the ideal tolerances.
  REQUIRE(run_vts(dir, "scan --cell static-E --profiles 2 --seed 7 --out e.exr").code == 0);
  r = run_vts(dir, "track e.exr --truth --independent");
  REQUIRE(r.code == 0);
  lines = json_lines(r.out);
  REQUIRE(lines.size() == 2);
  for (const Json& j : lines) {
    CHECK(j["status"] == "ok");
    // static-E: root on the optical axis at 98 mm, gap 2 mm.
    CHECK(num(j["track_point"]["y"]) == Approx(0.0).margin(0.05));
    CHECK(num(j["track_point"]["z"]) == Approx(98.0).margin(0.05));
    CHECK(num(j["angle_deg"]) == Approx(90.0).margin(0.5));
    // The web edge lies between two rays: one ray spacing along the web at
    // 45 degrees to the ray, times sin 90 degrees onto the flange normal.
    const vts::ScannerDesc desc;
    const double spacing = std::sqrt(2.0) * vts::lateral_spacing_mm(desc, 98.0);
    CHECK(num(j["gap_mm"]) == Approx(2.0).margin(std::max(0.1, spacing)));
  }
}

namespace {

// table3.csv as column name -> value, one map per row.
std::vector<std::map<std::string, std::string>> read_table(const fs::path& path) {
  std::istringstream in(slurp(path));
  std::string line;
  std::vector<std::string> head;
  std::vector<std::map<std::string, std::string>> rows;
  auto split = [](const std::string& s) {
    std::vector<std::string> out;
    std::stringstream ss(s);
    std::string f;
    while (std::getline(ss, f, ',')) out.push_back(f);
    return out;
  };
  std::getline(in, line);
  head = split(line);
  while (std::getline(in, line)) {
    const auto f = split(line);
    REQUIRE(f.size() == head.size());
    std::map<std::string, std::string> row;
    for (std::size_t i = 0; i < f.size(); ++i) row[head[i]] = f[i];
    rows.push_back(row);
  }
  return rows;
}

// Checks the deviations in table3.csv. Tolerances (mm, deg) at the setup's
// distance D, with the ray spacing along a plate at 45 degrees to the optical
// axis s = sqrt(2) * lateral_spacing(D) (1 / sin 45 of the spacing across the
// ray), and, with the error model, sigma = sqrt(noise^2 + step^2 / 12) the
// standard deviation of one point along its ray (speckle noise plus the
// uniform quantization of the sub-pixel peak):
// - B1 (the root, where the fitted lines meet): 0.05 + 3 sigma. One point's
//   3-sigma error bounds an intersection fitted through hundreds of points.
// - B0, B4 (each plate's last point, on its line): 0.01 ideal; with the error
//   model a dropout of the last columns moves it by whole spacings: 2 s + 3 sigma.
// - B2, B3 (the flange end seen under the web, the web edge): between two
//   column rays, s; with the error model 2 s + 3 sigma (a dropout next to it).
// - gap: max(0.1, s) (the web edge's position along the web, s, times sin 90);
//   with the error model + 3 sigma.
// - angle: 0.5 deg; with the error model + 6 sigma / L rad, L = D tan 20 deg
//   the shorter plate's seen length (the slope error of a fitted line is at
//   most its end points' error over its length).
void check_table(const fs::path& csv, bool ideal) {
  const auto rows = read_table(csv);
  REQUIRE(rows.size() == 6);
  const vts::ScannerDesc desc;  // the mspot preset of the built-in cells
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const auto& row = rows[i];
    const vts::StaticSetup setup = vts::kStaticSetups[i];
    INFO(row.at("setup"));
    CHECK(row.at("setup") == std::string("static-") + setup.label);
    CHECK(std::stod(row.at("distance_mm")) == setup.distance_mm);
    CHECK(std::stod(row.at("gap_true_mm")) == setup.gap_mm);
    CHECK(row.at("accepted") == row.at("profiles"));
    const double d = setup.distance_mm;
    const double s = std::sqrt(2.0) * vts::lateral_spacing_mm(desc, d);
    const double noise = vts::depth_noise_mm(desc, d), step = vts::depth_step_mm(desc, d);
    const double sigma = ideal ? 0.0 : std::sqrt(noise * noise + step * step / 12.0);
    const double tol_root = 0.05 + 3 * sigma;
    const double tol_end = ideal ? 0.01 : 2 * s + 3 * sigma;
    const double tol_edge = ideal ? 1.05 * s : 2 * s + 3 * sigma;
    const double tol_gap = std::max(0.1, 1.05 * s) + 3 * sigma;
    const double tol_angle = 0.5 + 6 * sigma / (d * std::tan(20.0 * kDeg)) / kDeg;
    const double tol[5] = {tol_end, tol_root, tol_edge, tol_edge, tol_end};
    for (int k = 0; k < 5; ++k) {
      const std::string b = "B" + std::to_string(k);
      INFO(b << " tolerance " << tol[k]);
      const double dy = std::stod(row.at(b + "_dy")), dz = std::stod(row.at(b + "_dz"));
      CHECK(std::hypot(dy, dz) <= tol[k]);
      // The deviation columns are measured - true.
      CHECK(std::stod(row.at(b + "_y")) - std::stod(row.at(b + "_y_true")) == Approx(dy).margin(2e-4));
    }
    // In the physical frame the root is the origin (docs/STATIC.md).
    CHECK(std::abs(std::stod(row.at("B1_y_true"))) < 1e-3);
    CHECK(std::abs(std::stod(row.at("B1_z_true"))) < 1e-3);
    // The plates' outer ends lie towards the sensor: physical z > 0.
    CHECK(std::stod(row.at("B0_z_true")) > 0.0);
    CHECK(std::abs(std::stod(row.at("gap_dev_mm"))) <= tol_gap);
    CHECK(std::abs(std::stod(row.at("gap_mm")) - setup.gap_mm) <= tol_gap);
    CHECK(std::abs(std::stod(row.at("angle_dev_deg"))) <= tol_angle);
  }
}

}  // namespace

TEST_CASE("vts static: ideal profiles within the issue's tolerances", "[cli][static][gl]") {
  TempDir dir;
  const Result r = run_vts(dir, "static --ideal --profiles 2 --out-dir out");
  INFO(r.err);
  REQUIRE(r.code == 0);
  const fs::path out = dir.path / "out";
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(out)) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  CHECK(names == std::vector<std::string>{"grooves.md", "static-A.png", "static-B.png", "static-C.png",
                                          "static-D.png", "static-E.png", "static-F.png", "table3.csv", "table3.md"});
  for (const auto& n : names) CHECK(fs::file_size(out / n) > 100);
  CHECK(slurp(out / "static-A.png").substr(1, 3) == "PNG");
  const std::string md = slurp(out / "table3.md");
  CHECK(md.find("| setup | distance | accepted |") != std::string::npos);
  CHECK(r.out.find("| A | 63 | 2/2 |") != std::string::npos);
  check_table(out / "table3.csv", true);
  // The groove cells' table: every cell read, depth left within 0.1 mm and
  // area within 2 % of the cells' analytic truth (columns 4-7).
  std::istringstream grooves(slurp(out / "grooves.md"));
  int rows = 0;
  for (std::string line; std::getline(grooves, line);) {
    if (line.rfind("| ", 0) != 0 || line.find("| cell |") == 0) continue;
    std::vector<std::string> cols;
    std::istringstream cells(line);
    for (std::string c; std::getline(cells, c, '|');) cols.push_back(c);
    REQUIRE(cols.size() >= 8);
    INFO(line);
    CHECK(cols[3] == " 2/2 ");
    CHECK(std::abs(std::stod(cols[4]) - std::stod(cols[5])) <= 0.1);
    CHECK(std::abs(std::stod(cols[6]) - std::stod(cols[7])) <= 0.02 * std::stod(cols[7]));
    ++rows;
  }
  CHECK(rows == 7);  // vgroove, vgroove-thick, bevel, bevel-thick, ugroove, ugroove-fill, jgroove
}

TEST_CASE("vts static: error model on within the sensor's resolution", "[cli][static][gl]") {
  TempDir dir;
  const Result r = run_vts(dir, "static --profiles 10 --seed 3");
  INFO(r.err);
  REQUIRE(r.code == 0);
  CHECK(r.out.find("error model on, seed 3, 10 profiles") != std::string::npos);
  check_table(dir.path / "static" / "table3.csv", false);
}

TEST_CASE("vts static: bad options exit 2 and write nothing", "[cli][static]") {
  TempDir dir;
  dir.write("file", "x");
  const std::pair<std::string, std::string> cases[] = {
      {"static --profiles 0", "vts static: --profiles = '0': expected an integer from 1 to 100000\n"},
      {"static --seed -1",
       "vts static: --seed = '-1': expected an unsigned 64-bit integer (0 .. 18446744073709551615)\n"},
      {"static --source gl", "vts static: --source = 'gl': expected 'raster' or 'reference'\n"},
      {"static --out-dir file", "vts static: --out-dir = 'file': exists and is not a directory\n"},
  };
  for (const auto& [args, message] : cases) {
    INFO(args);
    const Result r = run_vts(dir, args);
    CHECK(r.code == 2);
    CHECK(r.err == message);
    CHECK(dir.files() == std::vector<std::string>{"file"});
  }
}
