// vts export: runs bin/vts on files vts scan wrote and reads the outputs back
// (the exact messages for bad input are in tests/malformed/cases.txt).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "sensor/profile_exr.h"
#include "tests/common/bytes.h"
#include "vts_runner.h"

namespace {

namespace fs = std::filesystem;
using namespace vts_test;

using vts::test::get;

// The header lines of a PLY file, up to and including "end_header"; `data`
// gets the offset of the first vertex.
std::vector<std::string> ply_header(const std::string& b, std::size_t& data) {
  std::vector<std::string> lines;
  std::size_t at = 0;
  while (true) {
    const std::size_t end = b.find('\n', at);
    REQUIRE(end != std::string::npos);
    lines.push_back(b.substr(at, end - at));
    at = end + 1;
    if (lines.back() == "end_header") break;
  }
  data = at;
  return lines;
}

}  // namespace

TEST_CASE("vts export: the CSV gives vts track the EXR's results", "[cli][gl]") {
  TempDir dir;
  REQUIRE(run_vts(dir, "scan --cell fillet --profiles 40 --points 128 --out s.exr").code == 0);
  const Result e = run_vts(dir, "export s.exr --out s.csv");
  REQUIRE(e.code == 0);
  CHECK(e.err.empty());
  CHECK(e.out.rfind("wrote 40 profiles (", 0) == 0);
  CHECK(dir.files() == std::vector<std::string>{"s.csv", "s.exr"});

  // The CSV has no scene (the joint) and no poses (the travel per profile):
  // given as options, the tracker reads the same.
  const vts::ProfileRecording rec = vts::read_profile_exr(dir.path / "s.exr");
  const double step =
      (rec.profiles[1].world_from_sensor.translation() - rec.profiles[0].world_from_sensor.translation()).norm();
  char travel[64];
  std::snprintf(travel, sizeof travel, "%.17g", step);
  const std::string pairs[][2] = {
      {"track s.exr --independent", "track s.csv --independent --joint fillet"},
      {"track s.exr", std::string("track s.csv --joint fillet --travel ") + travel},
  };
  for (const auto& [exr, csv] : pairs) {
    INFO(exr << " against " << csv);
    const Result a = run_vts(dir, exr), b = run_vts(dir, csv);
    REQUIRE(a.code == 0);
    REQUIRE(b.code == 0);
    CHECK(contains(a.out, "\"status\":\"ok\""));
    CHECK(a.out == b.out);
  }
}

TEST_CASE("vts export: PLY vertices are the EXR's valid points in the world frame", "[cli][gl]") {
  TempDir dir;
  const bool ideal = GENERATE(false, true);
  INFO("ideal " << ideal);
  REQUIRE(run_vts(dir, std::string("scan --cell lap --profiles 12 --points 64 --reference") + (ideal ? " --ideal" : "") +
                           " --out s.exr")
              .code == 0);
  REQUIRE(run_vts(dir, "export s.exr --out S.PLY").code == 0);  // the extension in any case
  const vts::ProfileRecording rec = vts::read_profile_exr(dir.path / "s.exr");
  const std::string b = slurp(dir.path / "S.PLY");
  std::size_t at = 0;
  const std::vector<std::string> header = ply_header(b, at);
  std::size_t valid = 0;
  for (const vts::Profile& p : rec.profiles) valid += static_cast<std::size_t>(p.valid_count());
  REQUIRE(valid > 0);
  CHECK(header[0] == "ply");
  CHECK(header[1] == "format binary_little_endian 1.0");
  CHECK(std::count(header.begin(), header.end(), "comment scanner: mspot") == 1);
  CHECK(std::count(header.begin(), header.end(), "comment scene: lap") == 1);
  CHECK(std::count(header.begin(), header.end(), "element vertex " + std::to_string(valid)) == 1);
  std::vector<std::string> properties;
  for (const std::string& l : header)
    if (l.rfind("property ", 0) == 0) properties.push_back(l);
  std::vector<std::string> want = {"property float x", "property float y", "property float z", "property int profile",
                                   "property int column"};
  if (!ideal) want.push_back("property float intensity");
  REQUIRE(properties == want);
  const std::size_t record = ideal ? 20 : 24;
  REQUIRE(b.size() == at + valid * record);
  double worst = 0.0;
  for (std::size_t r = 0; r < rec.profiles.size(); ++r) {
    const vts::Profile& p = rec.profiles[r];
    for (int i = 0; i < p.size(); ++i) {
      if (!p.valid[i]) continue;
      const vts::Vec3 w = p.world_from_sensor * vts::Vec3(0.0, p.y_mm[i], p.z_mm[i]);
      for (int k = 0; k < 3; ++k) worst = std::max(worst, std::abs(get<float>(b, at + 4 * k) - w[k]));
      CHECK(get<std::int32_t>(b, at + 12) == static_cast<std::int32_t>(r));
      CHECK(get<std::int32_t>(b, at + 16) == i);
      if (!ideal) CHECK(get<float>(b, at + 20) == p.intensity[i]);
      at += record;
    }
  }
  CHECK(worst < 1e-4);  // float rounding of world coordinates of a few hundred mm
}

TEST_CASE("vts export: --format overrides the extension, and a failed write exits 1 and leaves nothing", "[cli][gl]") {
  TempDir dir;
  REQUIRE(run_vts(dir, "scan --cell plate --source reference --profiles 3 --points 32 --out s.exr").code == 0);
  const Result r = run_vts(dir, "export s.exr --out arrays.bin --format npz");
  REQUIRE(r.code == 0);
  CHECK(slurp(dir.path / "arrays.bin").compare(0, 4, "PK\x03\x04") == 0);

  const Result w = run_vts(dir, "export s.exr --out /proc/vts_x.csv");
  CHECK(w.code == 1);
  CHECK(contains(w.err, "vts export: export '/proc/vts_x.csv': cannot create"));
  CHECK_FALSE(fs::exists("/proc/vts_x.csv"));

  const Result d = run_vts(dir, "export s.exr --out s.exr.d/x.ply");
  CHECK(d.code == 2);
  CHECK(d.err == "vts export: --out = 's.exr.d/x.ply': directory 's.exr.d' does not exist\n");
  CHECK(dir.files() == std::vector<std::string>{"arrays.bin", "s.exr"});
}
