// The CSV profile reader and writer (sensor/profile_csv.h): round trip,
// hand-made files, and every error message.
#include <catch2/catch.hpp>

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "sensor/profile_csv.h"

using namespace vts;

namespace {

std::vector<Profile> read_text(const std::string& text, const std::string& name = "rec.csv") {
  std::istringstream in(text);
  return read_profile_csv(in, name);
}

// The message read_text throws, or "" if it does not throw.
std::string error_of(const std::string& text) {
  try {
    read_text(text);
  } catch (const CsvError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("profile csv: a hand-made file", "[csv]") {
  const auto p = read_text(
      "profile,y,z,valid\n"
      "0,-1.5,100,1\n"
      "0,0,99.5,1\n"
      "0,1.5,nan,0\n"
      "3,3,4,1\n"
      "3, 6 ,8 ,1\r\n"
      "\n"
      "  \n");
  REQUIRE(p.size() == 2);
  CHECK(p[0].index == 0);
  CHECK(p[1].index == 3);
  REQUIRE(p[0].size() == 3);
  REQUIRE(p[1].size() == 2);
  CHECK(p[0].y_mm == std::vector<float>{-1.5f, 0.0f, 0.0f});
  CHECK(p[0].z_mm == std::vector<float>{100.0f, 99.5f, 0.0f});
  CHECK(p[0].valid == std::vector<std::uint8_t>{1, 1, 0});
  // range = hypot(y, z): 3-4-5 and 6-8-10 triangles.
  CHECK(p[1].range_mm == std::vector<float>{5.0f, 10.0f});
  CHECK(p[0].range_mm[2] == 0.0f);
  CHECK(p[0].range_mm[1] == 99.5f);
  // Every other per-column vector is sized and zero.
  CHECK(p[1].sized(2));
  CHECK(p[1].true_valid == std::vector<std::uint8_t>{0, 0});
}

TEST_CASE("profile csv: columns in any order and no valid column", "[csv]") {
  const auto p = read_text("z,profile,y\n10,7,-2\n20,7,2\n");
  REQUIRE(p.size() == 1);
  CHECK(p[0].index == 7);
  CHECK(p[0].y_mm == std::vector<float>{-2.0f, 2.0f});
  CHECK(p[0].z_mm == std::vector<float>{10.0f, 20.0f});
  CHECK(p[0].valid == std::vector<std::uint8_t>{1, 1});
}

TEST_CASE("profile csv: round trip through the writer is exact", "[csv]") {
  std::vector<Profile> in(3);
  for (int k = 0; k < 3; ++k) {
    const int n = 5 + 7 * k;  // different sizes
    in[k].resize(n);
    in[k].index = 2 * k;
    for (int i = 0; i < n; ++i) {
      in[k].y_mm[i] = static_cast<float>(std::sin(0.37 * i + k) * 41.123456789);
      in[k].z_mm[i] = static_cast<float>(100.0 / 3.0 + i * 0.1 + k * 1e-7);
      in[k].valid[i] = (i % 4) != 3;
      if (!in[k].valid[i]) in[k].y_mm[i] = in[k].z_mm[i] = 0.0f;
    }
  }
  std::ostringstream out;
  write_profile_csv(out, in);
  const auto back = read_text(out.str());
  REQUIRE(back.size() == in.size());
  for (std::size_t k = 0; k < in.size(); ++k) {
    CHECK(back[k].index == in[k].index);
    CHECK(back[k].y_mm == in[k].y_mm);
    CHECK(back[k].z_mm == in[k].z_mm);
    CHECK(back[k].valid == in[k].valid);
  }
}

TEST_CASE("profile csv: a file on disk and a missing file", "[csv]") {
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() / ("vts_csv_test_" + std::to_string(::getpid()) + ".csv");
  {
    std::ofstream f(path);
    f << "profile,y,z\n0,1,2\n";
  }
  const auto p = read_profile_csv(path);
  REQUIRE(p.size() == 1);
  CHECK(p[0].z_mm[0] == 2.0f);
  std::filesystem::remove(path);
  try {
    read_profile_csv(path);
    FAIL("no exception");
  } catch (const CsvError& e) {
    CHECK(std::string(e.what()) == path.string() + ": no such file");
  }
  try {
    read_profile_csv(std::filesystem::temp_directory_path());
    FAIL("no exception");
  } catch (const CsvError& e) {
    CHECK(std::string(e.what()) == std::filesystem::temp_directory_path().string() + ": is a directory, expected a CSV file");
  }
}

TEST_CASE("profile csv: error messages name file line field and value", "[csv]") {
  const std::string head = "profile,y,z,valid\n";
  CHECK(error_of("") == "rec.csv:1: header: empty file, expected the header 'profile,y,z' (optionally ',valid')");
  CHECK(error_of("\n0,1,2\n") ==
        "rec.csv:1: header: empty line, expected the header 'profile,y,z' (optionally ',valid')");
  CHECK(error_of("profile,y\n0,1\n") == "rec.csv:1: header: missing column 'z'");
  CHECK(error_of("profile,z,valid\n") == "rec.csv:1: header: missing column 'y'");
  CHECK(error_of("y,z\n") == "rec.csv:1: header: missing column 'profile'");
  CHECK(error_of("profile,y,z,x\n") ==
        "rec.csv:1: header: unknown column 'x': expected profile, y, z and optionally valid (names are "
        "case-sensitive)");
  CHECK(error_of("Profile,y,z\n") ==
        "rec.csv:1: header: unknown column 'Profile': expected profile, y, z and optionally valid (names are "
        "case-sensitive)");
  CHECK(error_of("profile,y,z,y\n") == "rec.csv:1: header: column 'y' appears twice");
  CHECK(error_of(head) == "rec.csv:2: line: no data rows after the header");
  CHECK(error_of(head + "0,1,2,1\n0,1,abc,1\n") == "rec.csv:3: z: 'abc' is not a number");
  CHECK(error_of(head + "0,1x,2,1\n") == "rec.csv:2: y: '1x' is not a number");
  CHECK(error_of(head + "0,,2,1\n") == "rec.csv:2: y: '' is not a number");
  CHECK(error_of(head + "0,nan,2,1\n") ==
        "rec.csv:2: y: 'nan' is not finite (only rows with valid = 0 may hold nan or inf)");
  CHECK(error_of("profile,y,z\n0,1,-inf\n") ==
        "rec.csv:2: z: '-inf' is not finite (only rows with valid = 0 may hold nan or inf)");
  CHECK(error_of(head + "0,1e300,2,1\n") == "rec.csv:2: y: '1e300' is out of range (mm, single precision)");
  CHECK(error_of(head + "0,1,2,2\n") == "rec.csv:2: valid: '2' is not 0 or 1");
  CHECK(error_of(head + "0,1,2,true\n") == "rec.csv:2: valid: 'true' is not 0 or 1");
  CHECK(error_of(head + "0,1,2\n") == "rec.csv:2: line: 3 fields, expected 4 as in the header");
  CHECK(error_of(head + "0,1,2,1,5\n") == "rec.csv:2: line: 5 fields, expected 4 as in the header");
  CHECK(error_of(head + "1.5,1,2,1\n") == "rec.csv:2: profile: '1.5' is not an integer >= 0");
  CHECK(error_of(head + "-1,1,2,1\n") == "rec.csv:2: profile: '-1' is not an integer >= 0");
  CHECK(error_of(head + "99999999999999999999,1,2,1\n") ==
        "rec.csv:2: profile: '99999999999999999999' is out of range");
  CHECK(error_of(head + "4,1,2,1\n4,1,2,1\n3,1,2,1\n") ==
        "rec.csv:4: profile: 3 after 4: profile indices must not decrease (rows grouped by profile)");
  CHECK(error_of(head + "0,1,2,1\n\n0,1,2,1\n") ==
        "rec.csv:3: line: blank line inside the data (blank lines are allowed only at the end)");
}

TEST_CASE("profile csv: at most 4096 points per profile", "[csv]") {
  std::string text = "profile,y,z\n";
  for (int i = 0; i < 4096; ++i) text += "5,0," + std::to_string(i + 1) + "\n";
  text += "6,0,1\n";  // the next profile may start
  const auto ok = read_text(text);
  REQUIRE(ok.size() == 2);
  CHECK(ok[0].size() == 4096);
  text += "6,0,1\n";
  for (int i = 0; i < 4096; ++i) text += "7,0,1\n";
  // Line 1 header, 2..4097 profile 5, 4098..4099 profile 6, 4100.. profile 7;
  // the 4097th point of profile 7 is on line 4100 + 4096.
  text += "7,0,1\n";
  CHECK(error_of(text) == "rec.csv:" + std::to_string(4100 + 4096) +
                              ": profile: profile 7 (from line 4100) has more than 4096 points");
}

TEST_CASE("profile csv: non-finite values are accepted on invalid rows", "[csv]") {
  const auto p = read_text("profile,valid,y,z\n0,0,nan,inf\n0,1,1,2\n");
  REQUIRE(p.size() == 1);
  CHECK(p[0].valid == std::vector<std::uint8_t>{0, 1});
  CHECK(p[0].y_mm[0] == 0.0f);
  CHECK(p[0].z_mm[0] == 0.0f);
  // Still numbers, though.
  CHECK(error_of("profile,valid,y,z\n0,0,abc,1\n") == "rec.csv:2: y: 'abc' is not a number");
}

TEST_CASE("profile csv: the streaming reader gives the profiles in batches of any size", "[csv]") {
  // Hand-made: indices skip, profiles of 1 to 3 points, CRLF, blank lines at
  // the end; each value known.
  const std::string text =
      "profile,y,z,valid\r\n0,1,10,1\r\n0,2,20,1\r\n3,3,30,0\r\n4,4,40,1\r\n4,5,50,1\r\n4,6,60,1\r\n"
      "9,7,70,1\r\n12,8,80,1\r\n12,9,90,0\r\n\r\n\r\n";
  const std::vector<std::int64_t> indices = {0, 3, 4, 9, 12};
  const std::vector<std::vector<float>> ys = {{1, 2}, {0}, {4, 5, 6}, {7}, {8, 0}};
  for (const int batch : {1, 2, 3, 5, 100}) {
    INFO("batch " << batch);
    std::istringstream in(text);
    ProfileCsvReader reader(in, "rec.csv");
    std::vector<Profile> all, got;
    while (reader.read(got, batch)) {
      REQUIRE(got.size() <= std::size_t(batch));
      all.insert(all.end(), got.begin(), got.end());
    }
    CHECK(got.empty());
    CHECK_FALSE(reader.read(got, batch));
    REQUIRE(all.size() == indices.size());
    for (std::size_t k = 0; k < all.size(); ++k) {
      CHECK(all[k].index == indices[k]);
      CHECK(all[k].y_mm == ys[k]);
      CHECK(all[k].size() == int(ys[k].size()));
      for (std::size_t i = 0; i < ys[k].size(); ++i) CHECK(all[k].z_mm[i] == (all[k].valid[i] ? 10 * ys[k][i] : 0.0f));
    }
    const std::vector<Profile> whole = read_text(text);
    REQUIRE(whole.size() == all.size());
    for (std::size_t k = 0; k < all.size(); ++k) {
      CHECK(whole[k].y_mm == all[k].y_mm);
      CHECK(whole[k].range_mm == all[k].range_mm);
    }
  }
}

TEST_CASE("profile csv: a bad row further on is thrown by the read that reaches it", "[csv]") {
  const std::string text = "profile,y,z\n0,1,2\n1,1,2\n2,1,2\n3,1,x\n";
  std::istringstream in(text);
  ProfileCsvReader reader(in, "rec.csv");
  std::vector<Profile> got;
  REQUIRE(reader.read(got, 2));
  REQUIRE(got.size() == 2);
  CHECK(got[1].index == 1);
  try {
    reader.read(got, 2);
    FAIL("no exception");
  } catch (const CsvError& e) {
    CHECK(std::string(e.what()) == "rec.csv:5: z: 'x' is not a number");
    CHECK(error_of(text) == e.what());
  }
  // Errors of the header and of an empty file, at once.
  std::istringstream empty("");
  CHECK_THROWS_WITH(ProfileCsvReader(empty, "e.csv"),
                    "e.csv:1: header: empty file, expected the header 'profile,y,z' (optionally ',valid')");
}
