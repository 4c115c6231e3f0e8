#include <catch2/catch.hpp>

#include <unistd.h>

#include <array>
#include <bit>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputPart.h>
#include <ImfMultiPartInputFile.h>
#include <ImfMultiPartOutputFile.h>
#include <ImfOutputPart.h>
#include <ImfCompression.h>
#include <ImfStringAttribute.h>

#include "tests/common/temp_dir.h"
#include "tests/sensor/exr_fixture.h"
#include "sensor/pose.h"
#include "sensor/profile_exr.h"

namespace fs = std::filesystem;
using vts::ExrError;
using vts::Profile;
using vts::ProfileExrWriter;
using vts::ProfileFileInfo;

namespace {

// A fresh directory under the system temp dir, removed at the end of the test.
struct TempDir : vts::test::TempDir {
  TempDir() : vts::test::TempDir("vts_exr_test") {}
};

ProfileFileInfo make_info(int points, int profiles, bool reference) {
  ProfileFileInfo info;
  info.scanner.name = "test scanner";
  info.scanner.points = points;
  info.scanner.fan_deg = 0.1 + 0.2;  // not representable in few digits
  info.scanner.min_range_mm = 1.0 / 3.0;
  info.scanner.max_range_mm = 987.654321e0;
  info.scanner.max_hit_mm = 1234.5;
  info.scanner.rate_hz = 299.999;
  info.scanner.tool_from_laser =
      vts::pose_from_xyz_rpy(vts::Vec3(50.0, -1e-7, 100.0 / 7.0), vts::Vec3(1.0, -2.0, 33.3));
  info.scene_name = "cells/t_joint.yaml";
  info.scene_text = "# scene\nworkpiece:\n  type: t_joint\n  plate_mm: [200, 100, 8]\n\"quoted\": 'x'\n";
  info.profiles = profiles;
  info.has_reference = reference;
  return info;
}

Profile random_profile(std::mt19937& rng, int points, std::int64_t index) {
  std::uniform_real_distribution<float> yd(-300.0f, 300.0f), zd(20.0f, 1000.0f);
  std::uniform_real_distribution<double> td(-2000.0, 2000.0), qd(-1.0, 1.0);
  Profile p;
  p.resize(points);
  for (int i = 0; i < points; ++i) {
    if (rng() % 5 == 0) continue;  // invalid: zeros, as the sources store them
    p.valid[i] = 1;
    p.y_mm[i] = yd(rng);
    p.z_mm[i] = zd(rng);
    p.range_mm[i] = std::hypot(p.y_mm[i], p.z_mm[i]);
  }
  Eigen::Quaterniond q(qd(rng), qd(rng), qd(rng), qd(rng));
  p.world_from_sensor = vts::pose_from_quat(vts::Vec3(td(rng), td(rng), td(rng)), q);
  p.time_s = 12345.0 + index / 299.999 + 1e-9 * (rng() % 1000);
  p.index = index;
  return p;
}

bool same_bits(const std::vector<float>& a, const std::vector<float>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (std::bit_cast<std::uint32_t>(a[i]) != std::bit_cast<std::uint32_t>(b[i])) return false;
  return true;
}

void check_same(const Profile& got, const Profile& want) {
  REQUIRE(got.index == want.index);
  REQUIRE(same_bits(got.range_mm, want.range_mm));
  REQUIRE(same_bits(got.y_mm, want.y_mm));
  REQUIRE(same_bits(got.z_mm, want.z_mm));
  REQUIRE(got.valid == want.valid);
  REQUIRE(got.time_s == want.time_s);
  REQUIRE(got.world_from_sensor.translation() == want.world_from_sensor.translation());
  REQUIRE((got.world_from_sensor.matrix() - want.world_from_sensor.matrix()).cwiseAbs().maxCoeff() <
          1e-12);
}

void check_same_info(const ProfileFileInfo& got, const ProfileFileInfo& want) {
  const vts::ScannerDesc& s = got.scanner;
  CHECK(s.name == want.scanner.name);
  CHECK(s.points == want.scanner.points);
  CHECK(s.fan_deg == want.scanner.fan_deg);
  CHECK(s.min_range_mm == want.scanner.min_range_mm);
  CHECK(s.max_range_mm == want.scanner.max_range_mm);
  CHECK(s.max_hit_mm == want.scanner.max_hit_mm);
  CHECK(s.rate_hz == want.scanner.rate_hz);
  CHECK(s.tool_from_laser.matrix() == want.scanner.tool_from_laser.matrix());
  CHECK(got.scene_name == want.scene_name);
  CHECK(got.scene_text == want.scene_text);
  CHECK(got.profiles == want.profiles);
  CHECK(got.has_reference == want.has_reference);
  CHECK(got.error_model == want.error_model);
  CHECK(got.seed == want.seed);
}

// Writes `rows` random profiles (and references) and returns what was written.
struct Written {
  std::vector<Profile> profiles, reference;
};
Written write_random(const fs::path& file, const ProfileFileInfo& info, unsigned seed,
                     vts::ExrCompression compression = vts::ExrCompression::Zip) {
  std::mt19937 rng(seed);
  Written w;
  ProfileExrWriter writer(file, info, compression);
  for (int r = 0; r < info.profiles; ++r) {
    w.profiles.push_back(random_profile(rng, info.scanner.points, r));
    if (info.has_reference) {
      w.reference.push_back(random_profile(rng, info.scanner.points, r));
      w.reference.back().world_from_sensor = w.profiles.back().world_from_sensor;
      w.reference.back().time_s = w.profiles.back().time_s;
    }
    writer.write(w.profiles.back(), info.has_reference ? &w.reference.back() : nullptr);
  }
  writer.finish();
  return w;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

void spit(const fs::path& p, const std::string& bytes) {
  std::ofstream out(p, std::ios::binary | std::ios::trunc);
  out << bytes;
}

// Renames a channel in the header of an EXR file image. Same length and same
// sort position keep the file valid.
std::string rename_channel(std::string b, const std::string& from, const std::string& to) {
  REQUIRE(from.size() == to.size());
  const std::string key = std::string(1, '\0') + from + '\0';
  const auto at = b.find(key);
  REQUIRE(at != std::string::npos);
  REQUIRE(b.find(key, at + 1) == std::string::npos);
  b.replace(at + 1, from.size(), to);
  return b;
}

}  // namespace

TEST_CASE("exr: round trip is bit-exact", "[exr]") {
  TempDir dir;
  const bool reference = GENERATE(false, true);
  const int rows = GENERATE(1, 64, 203);  // below, at and across the chunk size
  INFO("reference " << reference << ", rows " << rows);
  const ProfileFileInfo info = make_info(96, rows, reference);
  const fs::path file = dir.path / "sub" / "run.exr";  // the writer makes "sub"
  const Written w = write_random(file, info, 1234u + rows);
  CHECK(dir.entries() == std::vector<std::string>{"sub"});
  CHECK(fs::exists(file));
  CHECK(std::distance(fs::directory_iterator(file.parent_path()), fs::directory_iterator()) == 1);

  const vts::ProfileRecording rec = vts::read_profile_exr(file);
  check_same_info(rec.info, info);

  REQUIRE(rec.profiles.size() == std::size_t(rows));
  REQUIRE(rec.reference.size() == (reference ? std::size_t(rows) : 0u));
  for (int r = 0; r < rows; ++r) {
    INFO("row " << r);
    check_same(rec.profiles[r], w.profiles[r]);
    if (reference) check_same(rec.reference[r], w.reference[r]);
  }
}

TEST_CASE("exr: every compression reads back bit-exact, whole and in blocks", "[exr]") {
  TempDir dir;
  const std::vector<std::string> names = vts::exr_compression_names();
  REQUIRE(names == std::vector<std::string>{"zip", "zips", "piz", "rle", "none"});
  const ProfileFileInfo info = make_info(80, 300, true);  // across a chunk (256) and the blocks (16, 32)
  for (const std::string& name : names) {
    INFO("compression " << name);
    const auto compression = vts::exr_compression_from_string(name);
    REQUIRE(compression);
    CHECK(vts::to_string(*compression) == name);
    const fs::path file = dir.path / (name + ".exr");
    const Written w = write_random(file, info, 77u, *compression);
    {
      Imf::MultiPartInputFile in(file.c_str());
      REQUIRE(in.parts() == 2);
      const Imf::Compression want = name == "zip"    ? Imf::ZIP_COMPRESSION
                                    : name == "zips" ? Imf::ZIPS_COMPRESSION
                                    : name == "piz"  ? Imf::PIZ_COMPRESSION
                                    : name == "rle"  ? Imf::RLE_COMPRESSION
                                                     : Imf::NO_COMPRESSION;
      CHECK(in.header(0).compression() == want);
      CHECK(in.header(1).compression() == want);
    }
    const vts::ProfileRecording rec = vts::read_profile_exr(file);
    check_same_info(rec.info, info);
    REQUIRE(rec.profiles.size() == w.profiles.size());
    for (std::size_t r = 0; r < w.profiles.size(); ++r) {
      check_same(rec.profiles[r], w.profiles[r]);
      check_same(rec.reference[r], w.reference[r]);
    }
    vts::ProfileExrReader reader(file);
    std::vector<Profile> block, ref;
    std::size_t r = 0;
    while (const int n = reader.read(37, block, &ref)) {
      for (int k = 0; k < n; ++k, ++r) {
        check_same(block[k], w.profiles[r]);
        check_same(ref[k], w.reference[r]);
      }
    }
    CHECK(r == w.profiles.size());
  }
  CHECK_FALSE(vts::exr_compression_from_string("lzw"));
  CHECK_FALSE(vts::exr_compression_from_string("ZIP"));
}

TEST_CASE("exr: writer rejects rows out of order and extra rows and wrong sizes", "[exr]") {
  TempDir dir;
  const fs::path file = dir.path / "bad.exr";
  std::mt19937 rng(7);
  ProfileExrWriter writer(file, make_info(32, 3, false));
  Profile p = random_profile(rng, 32, 1);
  CHECK_THROWS_WITH(writer.write(p), Catch::Contains("bad.exr") && Catch::Contains("index = 1"));
  p.index = 0;
  Profile wrong = random_profile(rng, 31, 0);
  CHECK_THROWS_WITH(writer.write(wrong), Catch::Contains("has 31 points"));
  CHECK_THROWS_WITH(writer.write(p, &p), Catch::Contains("no reference channels"));
  writer.write(p);
  for (int r = 1; r < 3; ++r) {
    p.index = r;
    writer.write(p);
  }
  p.index = 3;
  CHECK_THROWS_AS(writer.write(p), ExrError);
  CHECK_THROWS_WITH(writer.write(p), Catch::Contains("more rows than the 3 announced"));
  writer.finish();
  CHECK(vts::read_profile_exr(file).profiles.size() == 3);
  CHECK(dir.entries() == std::vector<std::string>{"bad.exr"});
}

TEST_CASE("exr: a writer destroyed without finish leaves nothing", "[exr]") {
  TempDir dir;
  const fs::path file = dir.path / "unfinished.exr";
  std::mt19937 rng(8);
  {
    ProfileExrWriter writer(file, make_info(32, 200, false));
    for (int r = 0; r < 100; ++r) writer.write(random_profile(rng, 32, r));
    CHECK(dir.entries().size() == 1);  // the temporary file
    CHECK_FALSE(fs::exists(file));
  }
  CHECK(dir.entries().empty());
}

TEST_CASE("exr: finish with too few rows throws and leaves nothing", "[exr]") {
  TempDir dir;
  const fs::path file = dir.path / "short.exr";
  std::mt19937 rng(9);
  ProfileExrWriter writer(file, make_info(32, 10, true));
  for (int r = 0; r < 4; ++r) {
    const Profile p = random_profile(rng, 32, r);
    writer.write(p, &p);
  }
  CHECK_THROWS_WITH(writer.finish(),
                    Catch::Contains("short.exr") && Catch::Contains("only 4 of 10 rows"));
  CHECK(dir.entries().empty());
}

TEST_CASE("exr: an existing file is replaced only on finish", "[exr]") {
  TempDir dir;
  const fs::path file = dir.path / "run.exr";
  write_random(file, make_info(16, 5, false), 1u);
  {
    ProfileExrWriter writer(file, make_info(16, 9, false));
  }
  CHECK(vts::read_profile_exr(file).info.profiles == 5);
  write_random(file, make_info(16, 9, false), 2u);
  CHECK(vts::read_profile_exr(file).info.profiles == 9);
  CHECK(dir.entries() == std::vector<std::string>{"run.exr"});
}

TEST_CASE("exr: writer errors name the file", "[exr]") {
  TempDir dir;
  spit(dir.path / "plain", "x");
  // A directory cannot be made below a regular file.
  CHECK_THROWS_WITH(ProfileExrWriter(dir.path / "plain" / "x.exr", make_info(16, 1, false)),
                    Catch::Contains("x.exr") && Catch::Contains("cannot create directory"));
  CHECK_THROWS_WITH(ProfileExrWriter(dir.path / "zero.exr", make_info(16, 0, false)),
                    Catch::Contains("zero.exr") && Catch::Contains("profiles = 0"));
  CHECK_THROWS_WITH(ProfileExrWriter(dir.path / "few.exr", make_info(8, 1, false)),
                    Catch::Contains("few.exr") && Catch::Contains("points = 8"));
}

TEST_CASE("exr: reading bad files gives errors naming the file", "[exr]") {
  TempDir dir;
  const fs::path good = dir.path / "good.exr";
  write_random(good, make_info(64, 300, true), 3u);
  const std::string bytes = slurp(good);

  SECTION("missing file") {
    const fs::path missing = dir.path / "missing.exr";
    CHECK_THROWS_WITH(vts::read_profile_exr(missing),
                      Catch::Contains("missing.exr") && Catch::Contains("no such file"));
  }
  SECTION("a text file") {
    const fs::path text = dir.path / "notes.txt";
    spit(text, "this is not an EXR file\n");
    CHECK_THROWS_WITH(vts::read_profile_exr(text),
                      Catch::Contains("notes.txt") && Catch::Contains("not an OpenEXR file"));
  }
  SECTION("a truncated file") {
    const fs::path cut = dir.path / "cut.exr";
    spit(cut, bytes.substr(0, bytes.size() * 6 / 10));
    CHECK_THROWS_WITH(vts::read_profile_exr(cut), Catch::Contains("cut.exr"));
  }
  SECTION("a file cut inside its header") {
    const fs::path cut = dir.path / "cut_header.exr";
    spit(cut, bytes.substr(0, 300));
    CHECK_THROWS_WITH(vts::read_profile_exr(cut), Catch::Contains("cut_header.exr"));
  }
  auto renamed = [&](const std::string& from, const std::string& to) {
    return rename_channel(bytes, from, to);
  };
  SECTION("no range channel") {
    const fs::path f = dir.path / "norange.exr";
    spit(f, renamed("range", "rangf"));
    CHECK_THROWS_WITH(vts::read_profile_exr(f),
                      Catch::Contains("norange.exr") && Catch::Contains("'range' is missing"));
  }
  SECTION("no ref.valid channel while vts.reference says there is a reference") {
    const fs::path f = dir.path / "noref.exr";
    spit(f, renamed("ref.valid", "ref.valie"));
    CHECK_THROWS_WITH(vts::read_profile_exr(f),
                      Catch::Contains("noref.exr") && Catch::Contains("'ref.valid' is missing"));
  }
  SECTION("half of an exact pose channel pair") {
    const fs::path f = dir.path / "half.exr";
    spit(f, renamed("f64lo.time", "f64lo.timf"));
    CHECK_THROWS_WITH(vts::read_profile_exr(f),
                      Catch::Contains("half.exr") && Catch::Contains("'f64lo.time' is missing"));
  }
  SECTION("unparsable attribute") {
    const fs::path f = dir.path / "badattr.exr";
    std::string b = bytes;
    const std::string key = "vts.scanner.fan_deg";
    const auto at = b.find(key);
    REQUIRE(at != std::string::npos);
    // name\0 "string"\0 size(4) value: spoil the value's first character.
    const auto value = at + key.size() + 1 + 7 + 4;
    b[value] = 'x';
    spit(f, b);
    CHECK_THROWS_WITH(vts::read_profile_exr(f), Catch::Contains("badattr.exr") &&
                                                    Catch::Contains("vts.scanner.fan_deg") &&
                                                    Catch::Contains("not a number"));
  }
  SECTION("width does not match vts.scanner.points") {
    const fs::path f = dir.path / "width.exr";
    std::string b = bytes;
    const std::string key = std::string("vts.scanner.points") + '\0' + "string" + '\0';
    const auto at = b.find(key);
    REQUIRE(at != std::string::npos);
    REQUIRE(b.substr(at + key.size() + 4, 2) == "64");
    b[at + key.size() + 4] = '3';  // "34"
    spit(f, b);
    CHECK_THROWS_WITH(vts::read_profile_exr(f), Catch::Contains("width.exr") &&
                                                    Catch::Contains("width 64") &&
                                                    Catch::Contains("vts.scanner.points = 34"));
  }
}

TEST_CASE("exr: without the exact f64 channels the FLOAT pose channels are used", "[exr]") {
  TempDir dir;
  const fs::path good = dir.path / "good.exr";
  const Written w = write_random(good, make_info(16, 20, false), 4u);
  const fs::path f = dir.path / "float_time.exr";
  spit(f, rename_channel(rename_channel(slurp(good), "f64hi.time", "f64hi.timf"), "f64lo.time",
                         "f64lo.timf"));
  const vts::ProfileRecording rec = vts::read_profile_exr(f);
  REQUIRE(rec.profiles.size() == 20);
  for (int r = 0; r < 20; ++r) {
    INFO("row " << r);
    CHECK(rec.profiles[r].time_s == double(static_cast<float>(w.profiles[r].time_s)));
    CHECK(rec.profiles[r].time_s != w.profiles[r].time_s);
    CHECK(rec.profiles[r].world_from_sensor.translation() ==
          w.profiles[r].world_from_sensor.translation());
  }
}

namespace {

const fs::path kV1Fixture = fs::path(VTS_SOURCE_DIR) / "tests" / "data" / "profiles-v1.exr";

void write_fixture(const fs::path& file) {
  const ProfileFileInfo info = vts::test::fixture_info();
  ProfileExrWriter writer(file, info);
  for (int r = 0; r < info.profiles; ++r) {
    const Profile p = vts::test::fixture_profile(info.scanner.points, r);
    const Profile ref = vts::test::fixture_profile(info.scanner.points, r, 1);
    writer.write(p, &ref);
  }
  writer.finish();
}

// Every value of a file holding the recording of tests/sensor/exr_fixture.h,
// against the formulas.
void check_fixture(const vts::ProfileRecording& rec) {
  const ProfileFileInfo want = vts::test::fixture_info();
  check_same_info(rec.info, want);
  REQUIRE(rec.profiles.size() == std::size_t(want.profiles));
  REQUIRE(rec.reference.size() == std::size_t(want.profiles));
  REQUIRE(rec.row_values.size() == std::size_t(want.profiles));
  for (int r = 0; r < want.profiles; ++r) {
    INFO("row " << r);
    const Profile p = vts::test::fixture_profile(want.scanner.points, r);
    const Profile ref = vts::test::fixture_profile(want.scanner.points, r, 1);
    check_same(rec.profiles[r], p);
    check_same(rec.reference[r], ref);
    CHECK(same_bits(rec.profiles[r].intensity, p.intensity));
    CHECK(same_bits(rec.profiles[r].true_y_mm, p.true_y_mm));
    CHECK(same_bits(rec.profiles[r].true_z_mm, p.true_z_mm));
    CHECK(rec.profiles[r].true_valid == p.true_valid);
    CHECK(rec.row_values[r] == vts::profile_row_values(p));  // the stored doubles, bit for bit
  }
}

}  // namespace

TEST_CASE("exr: version 2 round trip of every channel", "[exr]") {
  TempDir dir;
  const fs::path file = dir.path / "v2.exr";
  write_fixture(file);
  const vts::ProfileRecording rec = vts::read_profile_exr(file);
  check_fixture(rec);
}

TEST_CASE("exr: a version-1 file is still read", "[exr]") {
  // Written by the version-1 writer (tests/data/README.md): one part, the
  // per-row channels x-subsampled.
  Imf::MultiPartInputFile in(kV1Fixture.c_str());
  REQUIRE(in.parts() == 1);
  REQUIRE(in.header(0).findTypedAttribute<Imf::StringAttribute>("vts.format")->value() == "vts-profiles 1");
  REQUIRE(in.header(0).channels().findChannel("time")->xSampling == vts::test::kFixturePoints);
  check_fixture(vts::read_profile_exr(kV1Fixture));
}

TEST_CASE("exr: version 2 is two parts without subsampled channels, rows exact in part 'rows'", "[exr]") {
  // Read with plain OpenEXR, not with read_profile_exr.
  TempDir dir;
  const fs::path file = dir.path / "v2.exr";
  write_fixture(file);
  const ProfileFileInfo info = vts::test::fixture_info();
  const int w = info.scanner.points, h = info.profiles;
  Imf::MultiPartInputFile in(file.c_str());
  REQUIRE(in.parts() == 2);
  CHECK(in.header(0).name() == "profiles");
  CHECK(in.header(1).name() == "rows");
  for (int part = 0; part < 2; ++part) {
    INFO("part " << part);
    const Imf::Header& hd = in.header(part);
    CHECK(hd.findTypedAttribute<Imf::StringAttribute>("vts.format")->value() == "vts-profiles 2");
    CHECK(hd.compression() == Imf::ZIP_COMPRESSION);
    CHECK(hd.dataWindow() == Imath::Box2i(Imath::V2i(0, 0), Imath::V2i(part == 0 ? w - 1 : 0, h - 1)));
    for (auto c = hd.channels().begin(); c != hd.channels().end(); ++c) {
      INFO("channel " << c.name());
      CHECK(c.channel().xSampling == 1);
      CHECK(c.channel().ySampling == 1);
    }
  }
  std::vector<std::string> points, rows;
  for (auto c = in.header(0).channels().begin(); c != in.header(0).channels().end(); ++c) points.push_back(c.name());
  for (auto c = in.header(1).channels().begin(); c != in.header(1).channels().end(); ++c) rows.push_back(c.name());
  CHECK(points == std::vector<std::string>{"intensity", "range", "ref.range", "ref.valid", "ref.y", "ref.z",
                                           "true.valid", "true.y", "true.z", "valid", "y", "z"});
  const std::vector<std::string> names = {"pose.qw", "pose.qx", "pose.qy", "pose.qz",
                                          "pose.tx", "pose.ty", "pose.tz", "time"};
  std::vector<std::string> want_rows;
  for (const char* prefix : {"f64hi.", "f64lo.", ""})
    for (const std::string& n : names) want_rows.push_back(prefix + n);
  CHECK(rows == want_rows);

  // Part "rows": the doubles in the UINT pairs, rounded in the FLOAT channels.
  Imf::InputPart part(in, 1);
  std::vector<std::uint32_t> hi(h), lo(h);
  std::vector<float> f(h);
  const std::pair<const char*, int> checked[] = {{"pose.tx", 0}, {"pose.qw", 3}, {"pose.qz", 6}, {"time", 7}};
  for (const auto& [name, k] : checked) {
    INFO(name);
    Imf::FrameBuffer fb;
    fb.insert(std::string("f64hi.") + name, Imf::Slice(Imf::UINT, reinterpret_cast<char*>(hi.data()), 4, 4));
    fb.insert(std::string("f64lo.") + name, Imf::Slice(Imf::UINT, reinterpret_cast<char*>(lo.data()), 4, 4));
    fb.insert(name, Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(f.data()), 4, 4));
    part.setFrameBuffer(fb);
    part.readPixels(0, h - 1);
    for (int r = 0; r < h; ++r) {
      const double want = vts::profile_row_values(vts::test::fixture_profile(w, r))[k];
      CHECK(std::bit_cast<double>(std::uint64_t(hi[r]) << 32 | lo[r]) == want);
      CHECK(f[r] == static_cast<float>(want));
    }
  }
}

TEST_CASE("exr: a two-part file whose second part is not 'rows' is refused", "[exr]") {
  TempDir dir;
  const fs::path good = dir.path / "good.exr";
  write_fixture(good);
  std::string b = slurp(good);
  const std::string key = std::string("name") + '\0' + "string" + '\0' + std::string("\x04\0\0\0", 4) + "rows";
  const auto at = b.find(key);
  REQUIRE(at != std::string::npos);
  b[at + key.size() - 1] = 'z';  // "rowz"
  const fs::path f = dir.path / "rowz.exr";
  spit(f, b);
  CHECK_THROWS_WITH(vts::read_profile_exr(f), Catch::Contains("rowz.exr") &&
                                                  Catch::EndsWith("rowz.exr': a vts-profiles 2 file has two parts, 'profiles' and "
                                                                  "'rows'; this one has 2: 'profiles', 'rowz'"));
}

namespace {

// Every row of `file` through a ProfileExrReader, `batch` rows a call.
vts::ProfileRecording read_streamed(const fs::path& file, int batch) {
  vts::ProfileExrReader reader(file);
  vts::ProfileRecording rec;
  rec.info = reader.info();
  std::vector<Profile> p, ref;
  std::vector<std::array<double, 8>> rows;
  while (const int n = reader.read(batch, p, &ref, &rows)) {
    REQUIRE(n <= batch);
    REQUIRE(p.size() == std::size_t(n));
    REQUIRE(ref.size() == (rec.info.has_reference ? std::size_t(n) : 0u));
    rec.profiles.insert(rec.profiles.end(), p.begin(), p.end());
    rec.reference.insert(rec.reference.end(), ref.begin(), ref.end());
    rec.row_values.insert(rec.row_values.end(), rows.begin(), rows.end());
    REQUIRE(reader.rows_read() == int(rec.profiles.size()));
  }
  CHECK(reader.read(batch, p) == 0);
  CHECK(p.empty());
  return rec;
}

// `src` with part "profiles" stored with `compression`, by plain OpenEXR.
void recompress(const fs::path& src, const fs::path& dst, Imf::Compression compression) {
  Imf::MultiPartInputFile in(src.c_str());
  std::vector<Imf::Header> headers;
  for (int i = 0; i < in.parts(); ++i) headers.push_back(in.header(i));
  headers[0].compression() = compression;
  std::vector<std::vector<std::vector<std::uint32_t>>> data(in.parts());
  std::vector<Imf::FrameBuffer> fbs(in.parts());
  for (int i = 0; i < in.parts(); ++i) {
    const Imath::Box2i dw = headers[i].dataWindow();
    const std::size_t w = dw.max.x + 1, h = dw.max.y + 1;
    for (auto it = headers[i].channels().begin(); it != headers[i].channels().end(); ++it) {
      REQUIRE(it.channel().xSampling == 1);
      data[i].emplace_back(w * h);
      fbs[i].insert(it.name(), Imf::Slice(it.channel().type, reinterpret_cast<char*>(data[i].back().data()), 4, 4 * w));
    }
    Imf::InputPart part(in, i);
    part.setFrameBuffer(fbs[i]);
    part.readPixels(dw.min.y, dw.max.y);
  }
  Imf::MultiPartOutputFile out(dst.c_str(), headers.data(), int(headers.size()));
  for (int i = 0; i < in.parts(); ++i) {
    Imf::OutputPart part(out, i);
    part.setFrameBuffer(fbs[i]);
    part.writePixels(headers[i].dataWindow().max.y + 1);
  }
}

}  // namespace

TEST_CASE("exr: the streaming reader gives the written rows bit for bit, any batch size", "[exr]") {
  TempDir dir;
  const bool reference = GENERATE(false, true);
  // 300 rows: more than one of the reader's 256-row blocks, not a multiple of
  // ZIP's 16-row blocks.
  const ProfileFileInfo info = make_info(40, 300, reference);
  const fs::path file = dir.path / "s.exr";
  const Written w = write_random(file, info, 11);
  const auto compression = GENERATE(Imf::ZIP_COMPRESSION, Imf::ZIPS_COMPRESSION, Imf::NO_COMPRESSION,
                                    Imf::PIZ_COMPRESSION, Imf::RLE_COMPRESSION);
  const fs::path other = dir.path / "other.exr";
  recompress(file, other, compression);
  const vts::ProfileRecording whole = vts::read_profile_exr(other);
  for (const int batch : {1, 3, 16, 17, 255, 256, 257, 1000}) {
    INFO("compression " << int(compression) << ", batch " << batch);
    const vts::ProfileRecording rec = read_streamed(other, batch);
    check_same_info(rec.info, info);
    REQUIRE(rec.profiles.size() == w.profiles.size());
    REQUIRE(rec.row_values == whole.row_values);
    for (std::size_t r = 0; r < w.profiles.size(); ++r) {
      check_same(rec.profiles[r], w.profiles[r]);
      check_same(whole.profiles[r], w.profiles[r]);
      if (reference) check_same(rec.reference[r], w.reference[r]);
    }
  }
}

TEST_CASE("exr: the streaming reader reads versions 2 and 1 as the whole-file reader", "[exr]") {
  TempDir dir;
  const fs::path v2 = dir.path / "v2.exr";
  write_fixture(v2);
  for (const fs::path& file : {v2, kV1Fixture})
    for (const int batch : {1, 2, 7, 256}) {
      INFO(file << ", batch " << batch);
      check_fixture(read_streamed(file, batch));
    }
}

TEST_CASE("exr: a file cut in its pixels streams up to the cut, then fails as a whole read does", "[exr]") {
  TempDir dir;
  const ProfileFileInfo info = make_info(16, 600, false);
  const fs::path file = dir.path / "long.exr";
  const Written w = write_random(file, info, 5);
  const std::string bytes = slurp(file);
  const fs::path cut = dir.path / "cut.exr";
  spit(cut, bytes.substr(0, bytes.size() * 3 / 4));
  std::string whole_message;
  try {
    vts::read_profile_exr(cut);
  } catch (const ExrError& e) {
    whole_message = e.what();
  }
  REQUIRE_THAT(whole_message, Catch::Contains("cut.exr") && Catch::Contains("Early end of file"));
  vts::ProfileExrReader reader(cut);
  std::vector<Profile> batch;
  REQUIRE(reader.read(256, batch) == 256);  // the cut is past the first block
  for (int r = 0; r < 256; ++r) check_same(batch[r], w.profiles[r]);
  std::string message;
  try {
    while (reader.read(256, batch) > 0) {
    }
  } catch (const ExrError& e) {
    message = e.what();
  }
  CHECK(message == whole_message);
}

TEST_CASE("exr: the camera image's scanner fields round-trip, and files without them read the defaults", "[exr]") {
  TempDir dir;
  ProfileFileInfo info = make_info(64, 3, false);
  vts::ScannerDesc& s = info.scanner;
  s.scheimpflug_deg = 2.5;
  s.f_number = 4.0;
  s.wavelength_nm = 450.0;
  s.psf_sigma_px = 0.8;
  s.laser_power_mw = 1.0 / 3.0;  // not representable in few digits
  s.sheet_waist_mm = 0.07;
  s.sheet_focus_mm = 150.0;
  s.sheet_m2 = 1.1;
  s.exposure_us = 123.0;
  s.gain = 2.0;
  s.quantum_efficiency = 0.3;
  s.full_well_e = 8000.0;
  s.read_noise_e = 7.5;
  s.dark_offset_dn = 3.0;
  s.ambient_w_m2 = 0.0;
  s.specular_reflectance = 0.5;
  s.specular_lobe_deg = 2.0;
  s.speckle_contrast = 0.6;
  s.peak_threshold_dn = 40.0;
  s.image_bits = 12;
  s.image_roi_first_row = 100;
  s.image_roi_rows = 64;
  s.peak_window_px = 6;
  s.peak_method = "gaussian";
  s.peak_policy = "strongest";
  s.image_noise = false;
  s.camera_image = true;
  const fs::path file = dir.path / "image.exr";
  write_random(file, info, 7u);
  const vts::ScannerDesc got = vts::read_profile_exr(file).info.scanner;
  CHECK(got.scheimpflug_deg == s.scheimpflug_deg);
  CHECK(got.f_number == s.f_number);
  CHECK(got.wavelength_nm == s.wavelength_nm);
  CHECK(got.psf_sigma_px == s.psf_sigma_px);
  CHECK(got.laser_power_mw == s.laser_power_mw);
  CHECK(got.sheet_waist_mm == s.sheet_waist_mm);
  CHECK(got.sheet_focus_mm == s.sheet_focus_mm);
  CHECK(got.sheet_m2 == s.sheet_m2);
  CHECK(got.exposure_us == s.exposure_us);
  CHECK(got.gain == s.gain);
  CHECK(got.quantum_efficiency == s.quantum_efficiency);
  CHECK(got.full_well_e == s.full_well_e);
  CHECK(got.read_noise_e == s.read_noise_e);
  CHECK(got.dark_offset_dn == s.dark_offset_dn);
  CHECK(got.ambient_w_m2 == s.ambient_w_m2);
  CHECK(got.specular_reflectance == s.specular_reflectance);
  CHECK(got.specular_lobe_deg == s.specular_lobe_deg);
  CHECK(got.speckle_contrast == s.speckle_contrast);
  CHECK(got.peak_threshold_dn == s.peak_threshold_dn);
  CHECK(got.image_bits == 12);
  CHECK(got.image_roi_first_row == 100);
  CHECK(got.image_roi_rows == 64);
  CHECK(got.peak_window_px == 6);
  CHECK(got.peak_method == "gaussian");
  CHECK(got.peak_policy == "strongest");
  CHECK_FALSE(got.image_noise);
  CHECK(got.camera_image);

  // A file written before these fields existed (the attributes renamed away
  // with the same length, so the file stays valid) reads the defaults.
  std::string bytes = slurp(file);
  for (const char* name : {"vts.scanner.exposure_us", "vts.scanner.peak_policy", "vts.scanner.camera_image"}) {
    const std::string from = std::string(name) + '\0';
    std::string to = from;
    to.replace(0, 4, "xyz.");
    const auto at = bytes.find(from);
    REQUIRE(at != std::string::npos);
    bytes.replace(at, from.size(), to);
  }
  spit(dir.path / "old.exr", bytes);
  const vts::ScannerDesc old = vts::read_profile_exr(dir.path / "old.exr").info.scanner;
  CHECK(old.exposure_us == vts::ScannerDesc{}.exposure_us);
  CHECK(old.peak_policy == vts::ScannerDesc{}.peak_policy);
  CHECK_FALSE(old.camera_image);
  CHECK(old.f_number == s.f_number);  // the others still read
}
