// vts scan --camera-image [--images DIR]: profiles read from the rendered
// stripe, the images and their labels, same bytes for the same seed, and the
// options refused where they mean nothing.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "sensor/profile_exr.h"
#include "vts_runner.h"

namespace {

namespace fs = std::filesystem;
using namespace vts_test;

std::uint32_t be32(const std::string& s, std::size_t at) {
  return (std::uint32_t(std::uint8_t(s[at])) << 24) | (std::uint32_t(std::uint8_t(s[at + 1])) << 16) |
         (std::uint32_t(std::uint8_t(s[at + 2])) << 8) | std::uint32_t(std::uint8_t(s[at + 3]));
}

}  // namespace

TEST_CASE("vts scan --camera-image: profiles from the image agree with the truth, images and labels written",
          "[cli][gl][camera_image]") {
  TempDir dir;
  const Result r = run_vts(dir, "scan --cell vgroove --camera-image --profiles 3 --images imgs --out v.exr");
  INFO(r.out << r.err);
  REQUIRE(r.code == 0);
  const vts::ProfileRecording rec = vts::read_profile_exr(dir.path / "v.exr");
  REQUIRE(rec.profiles.size() == 3);
  std::vector<double> errors;
  int truth = 0;
  for (const vts::Profile& p : rec.profiles)
    for (int c = 0; c < p.size(); ++c) {
      truth += p.true_valid[c];
      if (p.valid[c] && p.true_valid[c]) errors.push_back(std::abs(p.z_mm[c] - p.true_z_mm[c]));
    }
  // The v-groove at 100 mm: depth step 0.015 mm, speckle 0.1 px = 0.024 mm.
  REQUIRE(errors.size() >= static_cast<std::size_t>(truth) * 9 / 10);
  std::sort(errors.begin(), errors.end());
  CHECK(errors[errors.size() / 2] < 0.03);
  CHECK(errors[errors.size() * 95 / 100] < 0.1);

  for (int i = 0; i < 3; ++i) {
    char name[32];
    std::snprintf(name, sizeof name, "imgs/image_%06d", i);
    const std::string png = slurp(dir.path / (std::string(name) + ".png"));
    REQUIRE(png.size() > 100);
    CHECK(png.substr(1, 3) == "PNG");
    CHECK(be32(png, 16) == 1280);  // IHDR width, height: the mspot image
    CHECK(be32(png, 20) == 1024);
    std::istringstream csv(slurp(dir.path / (std::string(name) + ".csv")));
    std::string line;
    std::getline(csv, line);
    CHECK(line.rfind("# vts camera image", 0) == 0);
    std::getline(csv, line);
    CHECK(line == "column,true_row,bounce_row,mirror_row,true_peak,chosen_peak,chosen_row,peaks");
    int rows = 0, labelled = 0, chosen_true = 0;
    while (std::getline(csv, line)) {
      ++rows;
      std::vector<std::string> f;
      std::stringstream ls(line);
      for (std::string x; std::getline(ls, x, ',');) f.push_back(x);
      f.resize(8);
      if (f[1].empty() || f[6].empty()) continue;
      ++labelled;
      chosen_true += f[4] == f[5] && std::abs(std::stod(f[1]) - std::stod(f[6])) < 1.0;
    }
    CHECK(rows == 1280);
    CHECK(labelled > 1000);
    CHECK(chosen_true >= labelled * 95 / 100);
  }
  CHECK(r.out.find("camera image") != std::string::npos);
}

TEST_CASE("vts scan --camera-image: the same seed gives the same bytes", "[cli][gl][camera_image]") {
  TempDir dir;
  for (const char* out : {"a", "b"}) {
    const Result r = run_vts(dir, std::string("scan --cell fillet --camera-image --profiles 2 --seed 3 --out ") + out +
                                      ".exr --images " + out);
    INFO(r.out << r.err);
    REQUIRE(r.code == 0);
  }
  CHECK(slurp(dir.path / "a.exr") == slurp(dir.path / "b.exr"));
  CHECK(slurp(dir.path / "a/image_000001.png") == slurp(dir.path / "b/image_000001.png"));
}

TEST_CASE("vts scan: --images needs --camera-image, which refuses --ideal", "[cli][camera_image]") {
  TempDir dir;
  Result r = run_vts(dir, "scan --cell fillet --profiles 2 --images imgs");
  CHECK(r.code == 2);
  CHECK(r.err.find("--images") != std::string::npos);
  r = run_vts(dir, "scan --cell fillet --profiles 2 --camera-image --ideal");
  CHECK(r.code == 2);
  CHECK(r.err.find("--camera-image") != std::string::npos);
  CHECK(!fs::exists(dir.path / "imgs"));
  CHECK(!fs::exists(dir.path / "fillet.exr"));
}
