// vts export's writers (sensor/profile_export.h), read back by parsers written
// here from the formats' specifications (CSV through vts's own reader) and
// checked against the recording of tests/sensor/exr_fixture.h.
#include <catch2/catch.hpp>

#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "sensor/profile_csv.h"
#include "sensor/profile_export.h"
#include "tests/common/bytes.h"
#include "tests/common/temp_dir.h"
#include "tests/sensor/exr_fixture.h"

namespace fs = std::filesystem;
using vts::ExportFormat;
using vts::Profile;
using vts::ProfileRecording;

namespace {

struct TempDir : vts::test::TempDir {
  TempDir() : vts::test::TempDir("vts_export_test") {}
};

// The fixture's recording in memory; with_model false drops the error
// model's channels, with_reference false the reference.
ProfileRecording fixture_recording(bool with_model = true, bool with_reference = true) {
  ProfileRecording rec;
  rec.info = vts::test::fixture_info();
  rec.info.error_model = with_model;
  rec.info.has_reference = with_reference;
  const int n = rec.info.scanner.points;
  for (int r = 0; r < rec.info.profiles; ++r) {
    rec.profiles.push_back(vts::test::fixture_profile(n, r));
    if (with_reference) rec.reference.push_back(vts::test::fixture_profile(n, r, 1));
  }
  return rec;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

using vts::test::get;

template <class T>
std::string bytes_of(const std::vector<T>& v) {
  return std::string(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
}

// CRC-32 (ISO 3309, the ZIP one), bit by bit.
std::uint32_t crc32_of(const std::string& data) {
  std::uint32_t c = 0xFFFFFFFFu;
  for (unsigned char byte : data) {
    c ^= byte;
    for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xEDB88320u & (0u - (c & 1u)));
  }
  return ~c;
}

struct Member {
  std::string dict;  // the .npy header's dict, trailing spaces and '\n' removed
  std::string data;  // the array's bytes
};

// The members of a ZIP of stored .npy files, in order, each checked: local
// header, ZIP64 sizes, CRC-32, .npy magic and alignment. Then the central
// directory and the end records must follow.
std::vector<std::pair<std::string, Member>> read_npz(const std::string& b) {
  std::vector<std::pair<std::string, Member>> out;
  std::size_t at = 0;
  while (get<std::uint32_t>(b, at) == 0x04034b50u) {
    CHECK(get<std::uint16_t>(b, at + 8) == 0);  // stored
    const std::uint32_t crc = get<std::uint32_t>(b, at + 14);
    CHECK(get<std::uint32_t>(b, at + 18) == 0xFFFFFFFFu);
    const std::uint16_t name_len = get<std::uint16_t>(b, at + 26), extra_len = get<std::uint16_t>(b, at + 28);
    const std::string name = b.substr(at + 30, name_len);
    const std::size_t extra = at + 30 + name_len;
    REQUIRE(extra_len == 20);
    REQUIRE(get<std::uint16_t>(b, extra) == 1);  // ZIP64
    const std::uint64_t size = get<std::uint64_t>(b, extra + 4);
    CHECK(get<std::uint64_t>(b, extra + 12) == size);
    const std::size_t data = extra + extra_len;
    REQUIRE(data + size <= b.size());
    const std::string payload = b.substr(data, size);
    INFO(name);
    CHECK(crc32_of(payload) == crc);
    REQUIRE(payload.compare(0, 8, std::string("\x93NUMPY\x01\x00", 8)) == 0);
    const std::size_t header_len = get<std::uint16_t>(payload, 8);
    CHECK((10 + header_len) % 64 == 0);
    std::string dict = payload.substr(10, header_len);
    CHECK(dict.back() == '\n');
    while (!dict.empty() && (dict.back() == '\n' || dict.back() == ' ')) dict.pop_back();
    out.push_back({name, Member{dict, payload.substr(10 + header_len)}});
    at = data + size;
  }
  CHECK(get<std::uint32_t>(b, at) == 0x02014b50u);             // central directory
  CHECK(get<std::uint32_t>(b, b.size() - 22) == 0x06054b50u);  // end of central directory
  CHECK(get<std::uint32_t>(b, b.size() - 42) == 0x07064b50u);  // ZIP64 locator
  return out;
}

std::string dict(const char* descr, const std::string& shape) {
  return std::string("{'descr': '") + descr + "', 'fortran_order': False, 'shape': " + shape + ", }";
}

// Row-major concatenation of one per-column vector of every profile.
template <class T>
std::string column_bytes(const std::vector<Profile>& profiles, std::vector<T> Profile::*member) {
  std::string out;
  for (const Profile& p : profiles) out += bytes_of(p.*member);
  return out;
}

}  // namespace

TEST_CASE("export: format from a name or an extension", "[export]") {
  CHECK(vts::export_format_named("csv") == ExportFormat::Csv);
  CHECK(vts::export_format_named("ply") == ExportFormat::Ply);
  CHECK(vts::export_format_named("npz") == ExportFormat::Npz);
  CHECK_FALSE(vts::export_format_named("CSV"));
  CHECK_FALSE(vts::export_format_named("npy"));
  CHECK(vts::export_format_of("a/b.CSV") == ExportFormat::Csv);
  CHECK(vts::export_format_of("b.Ply") == ExportFormat::Ply);
  CHECK(vts::export_format_of("x.y.npz") == ExportFormat::Npz);
  CHECK_FALSE(vts::export_format_of("b.txt"));
  CHECK_FALSE(vts::export_format_of("csv"));
  CHECK_FALSE(vts::export_format_of("b."));
}

TEST_CASE("export: CSV reads back as the main channels", "[export]") {
  TempDir dir;
  const ProfileRecording rec = fixture_recording();
  const fs::path out = dir.path / "f.csv";
  vts::export_recording(rec, out, ExportFormat::Csv);
  CHECK(dir.entries() == std::vector<std::string>{"f.csv"});
  const std::vector<Profile> back = vts::read_profile_csv(out);
  REQUIRE(back.size() == rec.profiles.size());
  for (std::size_t r = 0; r < back.size(); ++r) {
    INFO("profile " << r);
    const Profile want = vts::test::fixture_profile(vts::test::kFixturePoints, static_cast<int>(r));
    CHECK(back[r].index == static_cast<std::int64_t>(r));
    CHECK(bytes_of(back[r].y_mm) == bytes_of(want.y_mm));
    CHECK(bytes_of(back[r].z_mm) == bytes_of(want.z_mm));
    CHECK(back[r].valid == want.valid);
  }
}

TEST_CASE("export: PLY holds every valid point in the world frame", "[export]") {
  TempDir dir;
  const bool model = GENERATE(true, false);
  INFO("error model " << model);
  const ProfileRecording rec = fixture_recording(model, false);
  const fs::path out = dir.path / "f.ply";
  vts::export_recording(rec, out, ExportFormat::Ply);
  const std::string b = slurp(out);

  std::size_t valid = 0;
  for (const Profile& p : rec.profiles) valid += static_cast<std::size_t>(p.valid_count());
  REQUIRE(valid > 0);
  const std::string header =
      std::string("ply\nformat binary_little_endian 1.0\n") +
      "comment vts point cloud: the valid points of a profile recording, world frame, mm (docs/CLI.md)\n"
      "comment scanner: fixture scanner\ncomment scene: fixture.yaml\n" +
      (model ? "comment error_model: triangulation\n" : "comment error_model: ideal (no intensity)\n") +
      "element vertex " + std::to_string(valid) +
      "\nproperty float x\nproperty float y\nproperty float z\nproperty int profile\nproperty int column\n" +
      (model ? "property float intensity\n" : "") + "end_header\n";
  REQUIRE(b.compare(0, header.size(), header) == 0);
  const std::size_t record = model ? 24 : 20;
  REQUIRE(b.size() == header.size() + valid * record);

  std::size_t at = header.size();
  double worst = 0.0;
  for (int r = 0; r < rec.info.profiles; ++r) {
    const Profile p = vts::test::fixture_profile(vts::test::kFixturePoints, r);
    // p_world = R(q) * (0, y, z) + t, with R from the fixture's quaternion.
    const Eigen::Matrix3d R = Eigen::Quaterniond(1.0, 0.01 * r, -0.02, 0.003 * r).normalized().toRotationMatrix();
    const Eigen::Vector3d t(100.0 + r * 1.1, -20.0 / 3.0, 300.0 + r / 7.0);
    for (int i = 0; i < p.size(); ++i) {
      if (!p.valid[i]) continue;
      const Eigen::Vector3d want = R.col(1) * double(p.y_mm[i]) + R.col(2) * double(p.z_mm[i]) + t;
      for (int k = 0; k < 3; ++k) worst = std::max(worst, std::abs(double(get<float>(b, at + 4 * k)) - want[k]));
      CHECK(get<std::int32_t>(b, at + 12) == r);
      CHECK(get<std::int32_t>(b, at + 16) == i);
      if (model) CHECK(get<float>(b, at + 20) == p.intensity[i]);
      at += record;
    }
  }
  CHECK(at == b.size());
  CHECK(worst < 1e-4);  // float rounding of coordinates below 500 mm: 3e-5
}

TEST_CASE("export: npz holds every channel, the exact poses and times, and the attributes", "[export]") {
  TempDir dir;
  const bool model = GENERATE(true, false);
  const bool reference = GENERATE(true, false);
  INFO("error model " << model << ", reference " << reference);
  const ProfileRecording rec = fixture_recording(model, reference);
  const fs::path out = dir.path / "f.npz";
  vts::export_recording(rec, out, ExportFormat::Npz);
  const auto members = read_npz(slurp(out));

  std::vector<std::string> names;
  for (const auto& [name, m] : members) names.push_back(name);
  std::vector<std::string> want_names = {"y.npy", "z.npy", "range.npy", "valid.npy"};
  if (model) want_names.insert(want_names.end(), {"intensity.npy", "true_y.npy", "true_z.npy", "true_valid.npy"});
  if (reference) want_names.insert(want_names.end(), {"ref_y.npy", "ref_z.npy", "ref_range.npy", "ref_valid.npy"});
  want_names.insert(want_names.end(), {"pose.npy", "time.npy", "header.npy"});
  REQUIRE(names == want_names);
  std::map<std::string, Member> m;
  for (const auto& [name, member] : members) m[name] = member;

  // The fixture, independently of the recording handed to the writer.
  std::vector<Profile> want, want_ref;
  std::vector<double> pose, time;
  for (int r = 0; r < vts::test::kFixtureRows; ++r) {
    want.push_back(vts::test::fixture_profile(vts::test::kFixturePoints, r));
    want_ref.push_back(vts::test::fixture_profile(vts::test::kFixturePoints, r, 1));
    const std::array<double, 8> v = vts::profile_row_values(want.back());
    pose.insert(pose.end(), v.begin(), v.begin() + 7);
    time.push_back(want.back().time_s);
  }
  const std::string grid = "(40, 32)";
  auto check = [&](const std::string& name, const char* descr, const std::string& shape, const std::string& data) {
    INFO(name);
    CHECK(m[name].dict == dict(descr, shape));
    CHECK(m[name].data == data);
  };
  check("y.npy", "<f4", grid, column_bytes(want, &Profile::y_mm));
  check("z.npy", "<f4", grid, column_bytes(want, &Profile::z_mm));
  check("range.npy", "<f4", grid, column_bytes(want, &Profile::range_mm));
  check("valid.npy", "|b1", grid, column_bytes(want, &Profile::valid));
  if (model) {
    check("intensity.npy", "<f4", grid, column_bytes(want, &Profile::intensity));
    check("true_y.npy", "<f4", grid, column_bytes(want, &Profile::true_y_mm));
    check("true_z.npy", "<f4", grid, column_bytes(want, &Profile::true_z_mm));
    check("true_valid.npy", "|b1", grid, column_bytes(want, &Profile::true_valid));
  }
  if (reference) {
    check("ref_y.npy", "<f4", grid, column_bytes(want_ref, &Profile::y_mm));
    check("ref_z.npy", "<f4", grid, column_bytes(want_ref, &Profile::z_mm));
    check("ref_range.npy", "<f4", grid, column_bytes(want_ref, &Profile::range_mm));
    check("ref_valid.npy", "|b1", grid, column_bytes(want_ref, &Profile::valid));
  }
  check("pose.npy", "<f8", "(40, 7)", bytes_of(pose));
  check("time.npy", "<f8", "(40,)", bytes_of(time));

  // header: a 0-d UTF-32 string of JSON; the scene text's "é" is one code point.
  const Member& h = m["header.npy"];
  const std::size_t n = h.data.size() / 4;
  CHECK(h.dict == dict(("<U" + std::to_string(n)).c_str(), "()"));
  std::u32string text(n, U'\0');
  std::memcpy(text.data(), h.data.data(), h.data.size());
  std::string ascii;
  bool e_acute = false;
  for (char32_t c : text) {
    if (c == U'\u00e9') e_acute = true;
    ascii += c < 0x80 ? static_cast<char>(c) : '?';
  }
  CHECK(e_acute);
  CHECK(ascii.front() == '{');
  CHECK(ascii.find("\"vts.scanner.name\":\"fixture scanner\"") != std::string::npos);
  CHECK(ascii.find("\"vts.scene.yaml\":\"# a scene text, not parsed: caf?\\nname: fixture\\n\"") != std::string::npos);
  CHECK(ascii.find(std::string("\"vts.error_model\":\"") + (model ? "triangulation" : "ideal") + "\"") !=
        std::string::npos);
  CHECK(ascii.find(std::string("\"vts.reference\":\"") + (reference ? "embree3-robust" : "none") + "\"") !=
        std::string::npos);
}

TEST_CASE("export: failures name the file and leave nothing", "[export]") {
  TempDir dir;
  ProfileRecording rec = fixture_recording();
  CHECK_THROWS_WITH(vts::export_recording(rec, dir.path / "no" / "f.csv", ExportFormat::Csv),
                    Catch::Contains("export '" + (dir.path / "no" / "f.csv").string() + "': cannot create"));
  fs::create_directories(dir.path / "d.csv");
  CHECK_THROWS_WITH(vts::export_recording(rec, dir.path / "d.csv", ExportFormat::Csv),
                    Catch::Contains("d.csv") && Catch::Contains("is a directory"));
  rec.profiles[3].z_mm.pop_back();
  CHECK_THROWS_WITH(vts::export_recording(rec, dir.path / "short.npz", ExportFormat::Npz),
                    Catch::Contains("export '" + (dir.path / "short.npz").string() + "': channel z of profile 3 has 31 "
                                    "points, expected vts.scanner.points = 32"));
  rec.profiles[3] = vts::test::fixture_profile(vts::test::kFixturePoints, 3);
  rec.reference[5].valid.push_back(1);
  std::ostringstream sink;
  CHECK_THROWS_WITH(vts::write_recording_ply(sink, rec),
                    Catch::Contains("channel ref.valid of profile 5 has 33 points"));
  CHECK(dir.entries() == std::vector<std::string>{"d.csv"});
}
