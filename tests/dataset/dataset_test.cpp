// Datasets (dataset/dataset.h): shards as pure functions of (spec, k),
// resume, damaged files, cancellation, and the labels against an
// independent computation. Small shards on the Embree reference (no OpenGL)
// except the [gl] case, which runs the default raster source.
#include <catch2/catch.hpp>

#include <sys/wait.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "../common/temp_dir.h"
#include "common/parallel.h"
#include "dataset/dataset.h"
#include "pipeline/scan_job.h"
#include "sensor/profile_exr.h"
#include "tracker/tracker.h"
#include "trackio/result_json.h"

namespace {

namespace fs = std::filesystem;
using vts::trackio::Json;

// Three shards of two scenes of four profiles; every joint the tracker
// knows, two presets, two materials, every view angle.
const char* const kSmallSpec = R"(seed: 11
shards: 3
scenes_per_shard: 2
profiles_per_scene: 4
source: reference
joints:
  fillet: {gap_mm: [0, 2], angle_deg: [80, 100]}
  corner: {gap_mm: [0, 1]}
  lap: {gap_mm: [0, 1]}
  butt: {gap_mm: [0.5, 2], mismatch_mm: [0, 1]}
  vgroove: {thickness_mm: [8, 14], passes: [0, 1]}
  bevel: {}
  ugroove: {}
  jgroove: {}
sensors:
  mspot: {standoff_mm: [90, 120]}
  lps-1280-mid: {standoff_mm: [150, 200], weight: 0.5}
materials: [matte-steel, shiny-steel]
view:
  tilt_deg: [-10, 10]
  roll_deg: [-5, 5]
  travel_deg: [-8, 8]
  offset_mm: [-2, 2]
)";

vts::DatasetSpec small_spec() { return vts::parse_dataset_spec(kSmallSpec, "small.yaml"); }

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// Every file of the directory, by name, with its bytes.
std::map<std::string, std::string> contents(const fs::path& dir) {
  std::map<std::string, std::string> m;
  for (const auto& e : fs::directory_iterator(dir)) m[e.path().filename().string()] = slurp(e.path());
  return m;
}

std::vector<Json> lines_of(const fs::path& jsonl) {
  std::vector<Json> out;
  std::ifstream in(jsonl);
  for (std::string line; std::getline(in, line);) out.push_back(Json::parse(line));
  return out;
}

vts::Pose pose_of(const Json& j) {
  const Json& p = j.at("pose");
  const auto& t = p.at("position_mm");
  const auto& q = p.at("quaternion_wxyz");
  return vts::pose_from_quat(vts::Vec3(t[0].get<double>(), t[1].get<double>(), t[2].get<double>()),
                             Eigen::Quaterniond(q[0].get<double>(), q[1].get<double>(), q[2].get<double>(),
                                                q[3].get<double>()));
}

// The message of the DatasetSpecError the text gives.
std::string spec_error(const std::string& text, const std::string& file) {
  try {
    vts::parse_dataset_spec(text, file);
  } catch (const vts::DatasetSpecError& e) {
    return e.what();
  }
  return "(no error)";
}

vts::Vec2 yz(const Json& p) { return vts::Vec2(p.at("y").get<double>(), p.at("z").get<double>()); }

// Where the laser plane of `pose` cuts the line {(x, y, z): x} (world = the
// joint frame), in the sensor frame: written out here from the plane's
// equation n . (p - t) = 0, n = the sensor's x axis.
vts::Vec2 cut(const vts::Pose& pose, double y, double z) {
  const Eigen::Matrix3d r = pose.rotation();
  const vts::Vec3 n = r.col(0), t = pose.translation();
  const double x = (n.dot(t) - n.y() * y - n.z() * z) / n.x();
  const vts::Vec3 d = vts::Vec3(x, y, z) - t;
  return vts::Vec2(r.col(1).dot(d), r.col(2).dot(d));
}

}  // namespace

TEST_CASE("dataset spec: the canonical form reads back as the same spec", "[dataset]") {
  const vts::DatasetSpec s = small_spec();
  const std::string canonical = vts::dataset_spec_to_yaml(s);
  const vts::DatasetSpec back = vts::parse_dataset_spec(canonical, "canonical.yaml");
  CHECK(back == s);
  CHECK(vts::dataset_spec_to_yaml(back) == canonical);
  CHECK(vts::shard_count(s) == 3);
  CHECK(vts::profiles_per_shard(s) == 8);
  // Unlisted joints are not drawn; unset dimensions keep the joint's default.
  CHECK(s.joints.size() == 8);
  CHECK(s.joints[0].numbers[4] == vts::Range{0.0, 2.0});  // fillet gap_mm
  CHECK(s.joints[0].numbers[2] == vts::Range{6.0, 6.0});  // fillet thickness_mm: default
  // The order of the keys in the file does not matter.
  const vts::DatasetSpec reordered = vts::parse_dataset_spec(
      "profiles_per_scene: 4\nscenes_per_shard: 2\nshards: 3\nseed: 11\nsource: reference\n"
      "materials: [shiny-steel, matte-steel]\n"
      "sensors: {lps-1280-mid: {weight: 0.5, standoff_mm: [150, 200]}, mspot: {standoff_mm: [90, 120]}}\n"
      "view: {offset_mm: [-2, 2], travel_deg: [-8, 8], roll_deg: [-5, 5], tilt_deg: [-10, 10]}\n"
      "joints: {jgroove: {}, ugroove: {}, bevel: {}, vgroove: {passes: [0, 1], thickness_mm: [8, 14]},\n"
      "  butt: {mismatch_mm: [0, 1], gap_mm: [0.5, 2]}, lap: {gap_mm: [0, 1]}, corner: {gap_mm: [0, 1]},\n"
      "  fillet: {angle_deg: [80, 100], gap_mm: [0, 2]}}\n",
      "r.yaml");
  CHECK(reordered == s);
  // compression: written only when not zip, read back.
  CHECK(canonical.find("compression") == std::string::npos);
  vts::DatasetSpec none = s;
  none.compression = vts::ExrCompression::None;
  CHECK(vts::dataset_spec_to_yaml(none).find("\ncompression: none\n") != std::string::npos);
  CHECK(vts::parse_dataset_spec(vts::dataset_spec_to_yaml(none), "n.yaml") == none);
  // The example spec reads.
  const vts::DatasetSpec example = vts::load_dataset_spec(fs::path(VTS_SOURCE_DIR) / "examples" / "dataset.yaml");
  CHECK(vts::parse_dataset_spec(vts::dataset_spec_to_yaml(example), "e.yaml") == example);
}

TEST_CASE("dataset spec: bad specs name the file, line, field and value", "[dataset]") {
  const std::string base = "shards: 2\nscenes_per_shard: 1\nprofiles_per_scene: 2\n";
  auto error = [&](const std::string& more) { return spec_error(base + more, "bad.yaml"); };
  CHECK(error("shard_count: 3\n") ==
        "bad.yaml:4: shard_count: unknown key (expected one of: seed, shards, scenes_per_shard, profiles_per_scene, "
        "step_mm, source, ideal, compression, joints, sensors, materials, view)");
  CHECK(error("joints:\n  fillet:\n    gap_mm: [3, 1]\n") == "bad.yaml:6: joints.fillet.gap_mm: [3, 1]: min must not exceed max");
  CHECK(error("joints:\n  fillet:\n    gap: 1\n") ==
        "bad.yaml:6: joints.fillet.gap: unknown key (expected one of: weight, length_mm, width_mm, thickness_mm, "
        "height_mm, gap_mm, angle_deg, mismatch_mm, root_face_mm, segment_mm, cell_mm, layer_mm, crown_mm, "
        "radius_mm, passes)");
  CHECK(error("joints: [fillet, plate]\n") ==
        "bad.yaml:4: joints[1]: unknown joint 'plate' (expected one of: fillet, corner, lap, butt, vgroove, bevel, "
        "ugroove, jgroove)");
  CHECK(error("joints:\n  tee: {}\n") ==
        "bad.yaml:5: joints.tee: unknown joint 'tee' (expected one of: fillet, corner, lap, butt, vgroove, bevel, "
        "ugroove, jgroove)");
  CHECK(error("sensors: [mspot, lps-9000]\n") ==
        "bad.yaml:4: sensors[1]: unknown sensor preset 'lps-9000' (expected one of: mspot, lps-2048-short, "
        "lps-1280-mid; see `vts sensors`)");
  CHECK(error("materials: {glass: 1}\n") ==
        "bad.yaml:4: materials.glass: unknown material 'glass' (expected one of: matte-steel, shiny-steel, "
        "aluminium, rough, lambertian; see `vts sensors`)");
  CHECK(error("materials: {matte-steel: 0}\n") == "bad.yaml:4: materials: every weight is 0: nothing to draw");
  CHECK(error("joints: {butt: {weight: -1}}\n") == "bad.yaml:4: joints.butt.weight: weight = -1: must be >= 0");
  CHECK(error("view: {tilt_deg: [-70, 0]}\n") == "bad.yaml:4: view.tilt_deg: [-70, 0]: must lie within [-60, 60] deg");
  CHECK(error("joints: {vgroove: {passes: [0, 1.5]}}\n") ==
        "bad.yaml:4: joints.vgroove.passes: passes = [0, 1.5]: expected integers");
  CHECK(error("source: gpu\n") == "bad.yaml:4: source: source = 'gpu': expected raster or reference");
  CHECK(error("step_mm: 0\n") == "bad.yaml:4: step_mm: step_mm = 0: must be > 0");
  CHECK(error("compression: lzw\n") ==
        "bad.yaml:4: compression: compression = 'lzw': expected one of zip, zips, piz, rle, none");
  CHECK(error("seed: -3\n") == "bad.yaml:4: seed: seed = '-3': expected an integer 0 .. 18446744073709551615");
  CHECK(error("sensors: {mspot: {standoff_mm: [0, 100]}}\n") ==
        "bad.yaml:4: sensors.mspot.standoff_mm: [0, 100]: must be > 0");
  // Counts.
  auto counts_error = [](const std::string& text) { return spec_error(text, "c.yaml"); };
  CHECK(counts_error("shards: 0\nscenes_per_shard: 1\nprofiles_per_scene: 1\n") ==
        "c.yaml:1: shards: shards = 0: must be between 1 and 1000000");
  CHECK(counts_error("shards: 1\nprofiles_per_scene: 1\n") == "c.yaml:1: scenes_per_shard: missing (required)");
  CHECK(counts_error("shards: 1\nscenes_per_shard: [1]\nprofiles_per_scene: 1\n") ==
        "c.yaml:2: scenes_per_shard: expected an integer, got a list of 1");
  CHECK(counts_error("shards: [1\n") .find("c.yaml:2: YAML syntax error") == 0);
  // A joint whose ranges give no usable workpiece: the draws' refusal.
  CHECK(error("joints:\n  corner: {gap_mm: [6, 8]}\n") ==
        "bad.yaml:5: joints.corner: only 0 of 200 trial draws give a usable scene; narrow the ranges (the last "
        "refused: gap_mm = 6.52708: corner gap must be smaller than thickness_mm)");
  CHECK_THROWS_WITH(vts::load_dataset_spec("no/such/spec.yaml"), "no/such/spec.yaml:0: spec file not found");
}

TEST_CASE("dataset: compression none writes the same profiles and labels as zip", "[dataset]") {
  const vts::DatasetSpec spec = small_spec();
  vts::DatasetSpec none = spec;
  none.compression = vts::ExrCompression::None;
  const vts::test::TempDir a, b;
  const vts::ShardInfo zipped = vts::write_shard(spec, 1, a.path);
  const vts::ShardInfo stored = vts::write_shard(none, 1, b.path);
  REQUIRE(zipped.files.size() == stored.files.size());
  CHECK(zipped.files.back().sha256 == stored.files.back().sha256);  // the JSON Lines
  for (std::size_t f = 0; f + 1 < zipped.files.size(); ++f) {
    const vts::ProfileRecording x = vts::read_profile_exr(a.path / zipped.files[f].name);
    const vts::ProfileRecording y = vts::read_profile_exr(b.path / stored.files[f].name);
    CHECK(fs::file_size(b.path / stored.files[f].name) > fs::file_size(a.path / zipped.files[f].name));
    REQUIRE(x.profiles.size() == y.profiles.size());
    for (std::size_t i = 0; i < x.profiles.size(); ++i) {
      CHECK(x.profiles[i].y_mm == y.profiles[i].y_mm);
      CHECK(x.profiles[i].z_mm == y.profiles[i].z_mm);
      CHECK(x.profiles[i].valid == y.profiles[i].valid);
      CHECK(x.profiles[i].true_z_mm == y.profiles[i].true_z_mm);
    }
    CHECK(x.row_values == y.row_values);
  }
}

TEST_CASE("dataset: a shard is a pure function of (spec, k)", "[dataset]") {
  const vts::DatasetSpec spec = small_spec();
  const vts::test::TempDir a, b, c;
  const vts::ShardInfo first = vts::write_shard(spec, 1, a.path);
  const vts::ShardInfo again = vts::write_shard(spec, 1, b.path);
  CHECK(first == again);
  CHECK(contents(a.path) == contents(b.path));
  REQUIRE(first.files.size() == 3);  // two scenes' EXRs and the JSONL
  CHECK(first.files[0].name == "shard-00001-scene-0000.exr");
  CHECK(first.files[2].name == "shard-00001.jsonl");
  CHECK(first.profiles == 8);
  CHECK(fs::exists(a.path / "shard-00001.json"));
  // Written over an existing copy: the same bytes again.
  CHECK(vts::write_shard(spec, 1, a.path) == first);
  CHECK(contents(a.path) == contents(b.path));
  // Another shard: other scenes.
  const vts::ShardInfo other = vts::write_shard(spec, 2, c.path);
  CHECK(other.files[0].sha256 != first.files[0].sha256);
  CHECK(other.files[2].sha256 != first.files[2].sha256);
  // Another seed: another shard 1.
  vts::DatasetSpec reseeded = spec;
  reseeded.seed = 12;
  const vts::test::TempDir d;
  CHECK(vts::write_shard(reseeded, 1, d.path).files[2].sha256 != first.files[2].sha256);
  CHECK_THROWS_AS(vts::write_shard(spec, 3, d.path), std::out_of_range);
}

// Run by the next test in a process of its own (the thread limit is fixed
// by a process's first parallel loop): writes shard 1 of the small spec to
// $VTS_DATASET_TEST_OUT with set_thread_limit($VTS_DATASET_TEST_THREADS).
TEST_CASE("dataset: helper writing a shard with a thread limit", "[.][helper]") {
  const char* out = std::getenv("VTS_DATASET_TEST_OUT");
  const char* threads = std::getenv("VTS_DATASET_TEST_THREADS");
  REQUIRE(out);
  REQUIRE(threads);
  vts::set_thread_limit(std::atoi(threads));
  vts::write_shard(small_spec(), 1, out);
}

TEST_CASE("dataset: a shard written with 1 and with 2 threads is the same", "[dataset][threads]") {
  const vts::test::TempDir dir;
  const fs::path self = fs::read_symlink("/proc/self/exe");
  for (const char* threads : {"1", "2"}) {
    const std::string cmd = "VTS_DATASET_TEST_OUT='" + (dir.path / threads).string() + "' VTS_DATASET_TEST_THREADS=" +
                            threads + " '" + self.string() + "' 'dataset: helper writing a shard with a thread limit'" +
                            " > '" + (dir.path / "log.txt").string() + "' 2>&1";
    const int status = std::system(cmd.c_str());
    INFO(slurp(dir.path / "log.txt"));
    REQUIRE(WIFEXITED(status));
    REQUIRE(WEXITSTATUS(status) == 0);
  }
  const auto one = contents(dir.path / "1");
  CHECK(one.size() == 4);
  CHECK(one == contents(dir.path / "2"));
}

TEST_CASE("dataset: resume rewrites only what is missing or damaged", "[dataset]") {
  const vts::DatasetSpec spec = small_spec();
  const vts::test::TempDir dir;
  const vts::DatasetResult first = vts::run_dataset(spec, dir.path);
  CHECK(first.written == std::vector<int>{0, 1, 2});
  CHECK(first.skipped.empty());
  CHECK(first.profiles_written == 24);
  const auto original = contents(dir.path);
  CHECK(original.size() == 3 * 4 + 1);  // per shard 2 EXRs, JSONL, record; the manifest
  const Json manifest = Json::parse(original.at("manifest.json"));
  CHECK(manifest.at("totals").at("profiles") == 24);
  CHECK(manifest.at("spec").get<std::string>() == vts::dataset_spec_to_yaml(spec));
  CHECK(manifest.at("shards").size() == 3);

  SECTION("nothing to do") {
    const vts::DatasetResult r = vts::run_dataset(spec, dir.path);
    CHECK(r.written.empty());
    CHECK(r.skipped == std::vector<int>{0, 1, 2});
    CHECK(contents(dir.path) == original);
  }
  SECTION("a shard deleted") {
    for (const auto& [name, bytes] : original)
      if (name.rfind("shard-00001", 0) == 0) fs::remove(dir.path / name);
    std::string why;
    CHECK_FALSE(vts::verified_shard(spec, 1, dir.path, &why));
    CHECK(why == "shard-00001: no record (shard-00001.json)");
    const vts::DatasetResult r = vts::run_dataset(spec, dir.path);
    CHECK(r.written == std::vector<int>{1});
    CHECK(r.skipped == std::vector<int>{0, 2});
    CHECK(contents(dir.path) == original);  // the manifest too
  }
  SECTION("a truncated EXR") {
    const fs::path exr = dir.path / "shard-00002-scene-0001.exr";
    fs::resize_file(exr, fs::file_size(exr) - 100);
    std::string why;
    CHECK_FALSE(vts::verified_shard(spec, 2, dir.path, &why));
    CHECK(why.find("shard-00002: shard-00002-scene-0001.exr has ") == 0);
    const vts::DatasetResult r = vts::run_dataset(spec, dir.path);
    CHECK(r.written == std::vector<int>{2});
    CHECK(contents(dir.path) == original);
  }
  SECTION("a changed byte in the JSONL") {
    const fs::path jsonl = dir.path / "shard-00000.jsonl";
    std::string text = slurp(jsonl);
    text[10] = text[10] == '1' ? '2' : '1';
    std::ofstream(jsonl, std::ios::binary) << text;
    std::string why;
    CHECK_FALSE(vts::verified_shard(spec, 0, dir.path, &why));
    CHECK(why == "shard-00000: shard-00000.jsonl differs from its recorded SHA-256");
    CHECK(vts::run_dataset(spec, dir.path).written == std::vector<int>{0});
    CHECK(contents(dir.path) == original);
  }
  SECTION("another spec: every shard again") {
    vts::DatasetSpec other = spec;
    other.view.offset_mm = {0.0, 0.0};
    std::string why;
    CHECK_FALSE(vts::verified_shard(other, 0, dir.path, &why));
    CHECK(why == "shard-00000: written for another spec");
    CHECK(vts::run_dataset(other, dir.path).written == std::vector<int>{0, 1, 2});
  }
}

TEST_CASE("dataset: a cancelled run leaves the shard in hand without its record", "[dataset]") {
  const vts::DatasetSpec spec = small_spec();
  const vts::test::TempDir dir;
  int scenes = 0;
  vts::DatasetCallbacks cb;
  std::vector<std::int64_t> done;
  cb.progress = [&](const vts::DatasetProgress& p) {
    done.push_back(p.profiles_done);
    CHECK(p.profiles_total == 24);
  };
  cb.cancelled = [&] { return ++scenes > 6; };  // polled before each scene and each batch: stops in shard 1
  CHECK_THROWS_AS(vts::run_dataset(spec, dir.path, cb), vts::Cancelled);
  CHECK(vts::verified_shard(spec, 0, dir.path));
  CHECK_FALSE(vts::verified_shard(spec, 1, dir.path));
  CHECK_FALSE(fs::exists(dir.path / "manifest.json"));
  for (const auto& [name, bytes] : contents(dir.path)) CHECK(name.find(".tmp-") == std::string::npos);
  CHECK(done.front() == 4);
  const vts::DatasetResult r = vts::run_dataset(spec, dir.path);
  CHECK(r.skipped == std::vector<int>{0});
  CHECK(r.written == std::vector<int>{1, 2});
}

TEST_CASE("dataset: the labels agree with the plane cut worked out here and with the EXR rows", "[dataset]") {
  vts::DatasetSpec spec = small_spec();
  spec.scenes_per_shard = 12;
  const vts::test::TempDir dir;
  vts::write_shard(spec, 0, dir.path);
  const std::vector<Json> lines = lines_of(dir.path / "shard-00000.jsonl");
  REQUIRE(lines.size() == 48);
  std::map<std::string, int> joints;
  std::map<std::string, vts::ProfileRecording> recordings;
  for (const Json& j : lines) {
    const std::string joint = j.at("joint");
    ++joints[joint];
    const vts::Pose pose = pose_of(j);
    const Json& p = j.at("params");
    const double g = p.at("gap_mm"), m = p.at("mismatch_mm");
    INFO(j.dump());
    // The row of the EXR holds this pose exactly, and the time.
    const std::string exr = j.at("exr");
    if (!recordings.count(exr)) recordings[exr] = vts::read_profile_exr(dir.path / exr);
    const vts::Profile& row = recordings[exr].profiles.at(j.at("profile").get<std::size_t>());
    CHECK(row.world_from_sensor.matrix() == pose.matrix());
    CHECK(row.time_s == j.at("time_s").get<double>());
    CHECK(recordings[exr].info.seed == j.at("sensor").at("seed").get<std::uint64_t>());
    const vts::Vec2 track = yz(j.at("track_point"));
    std::map<std::string, vts::Vec2> bp;
    for (const Json& b : j.at("break_points")) bp[b.at("name")] = yz(b);
    if (joint == "fillet") {
      // The root, and the web's edge g above the flange on the web's line.
      const double a = p.at("angle_deg").get<double>() * M_PI / 180.0;
      CHECK((track - cut(pose, 0.0, 0.0)).norm() < 1e-9);
      CHECK((bp.at("B3") - cut(pose, g / std::tan(a), g)).norm() < 1e-9);
      CHECK(j.at("gap_mm").get<double>() == g);
      CHECK(j.at("mismatch_mm").is_null());
    } else if (joint == "butt") {
      const vts::Vec2 left = cut(pose, -0.5 * g, 0.0), right = cut(pose, 0.5 * g, m);
      const bool left_first = left.x() / left.y() < right.x() / right.y();
      CHECK((bp.at("B1") - (left_first ? left : right)).norm() < 1e-9);
      CHECK((bp.at("B3") - (left_first ? right : left)).norm() < 1e-9);
      CHECK((track - cut(pose, 0.0, 0.0)).norm() < 1e-9);
      CHECK(j.at("mismatch_mm").get<double>() == m);
    } else if (joint == "lap") {
      const double t = p.at("thickness_mm");
      CHECK((bp.at("B3") - cut(pose, 0.0, g + t)).norm() < 1e-9);
      CHECK(j.at("step_mm").get<double>() == Approx(g + t));
    }
    if (j.at("sensor").at("preset") == "mspot")  // a 40-degree fan, 40-1000 mm
      CHECK(j.at("in_window").get<bool>() ==
            (std::abs(track.x()) <= std::tan(20.0 * M_PI / 180.0) * track.y() && track.y() >= 40.0 &&
             track.y() <= 1000.0));
  }
  CHECK(joints.size() >= 5);  // the draws reach most joints in 12 scenes
  CHECK(joints["fillet"] + joints["butt"] + joints["lap"] > 0);
}

TEST_CASE("dataset: on ideal profiles the tracker finds the labelled track point", "[dataset]") {
  // Fillets and butts, ideal profiles: the tracker's reading is an
  // independent measurement of where the joint lies in each profile.
  const vts::DatasetSpec spec = vts::parse_dataset_spec(R"(seed: 3
shards: 1
scenes_per_shard: 6
profiles_per_scene: 3
source: reference
ideal: true
joints:
  fillet: {gap_mm: [0, 1.5], angle_deg: [80, 100]}
  butt: {gap_mm: [1, 2.5], mismatch_mm: [0, 1]}
sensors:
  mspot: {standoff_mm: [80, 130]}
view: {tilt_deg: [-10, 10], roll_deg: [-6, 6], travel_deg: [-10, 10], offset_mm: [-3, 3]}
)",
                                                        "ideal.yaml");
  const vts::test::TempDir dir;
  vts::write_shard(spec, 0, dir.path);
  int ok = 0, total = 0;
  double worst = 0.0;
  std::map<std::string, vts::ProfileRecording> recordings;
  for (const Json& j : lines_of(dir.path / "shard-00000.jsonl")) {
    const std::string exr = j.at("exr");
    if (!recordings.count(exr)) recordings[exr] = vts::read_profile_exr(dir.path / exr);
    const vts::Profile& p = recordings[exr].profiles.at(j.at("profile").get<std::size_t>());
    vts::tracker::TrackerParams params;
    params.joint = *vts::tracker::joint_type_from_string(j.at("joint").get<std::string>());
    vts::tracker::Tracker tracker(params);
    const vts::tracker::TrackResult& r = tracker.track({p.y_mm, p.z_mm, p.valid});
    ++total;
    INFO(j.at("joint") << " " << j.at("view").dump() << ": " << vts::tracker::to_string(r.status) << " " << r.reason);
    if (r.status != vts::tracker::TrackStatus::Ok) continue;
    ++ok;
    const double err = (*r.track_point - yz(j.at("track_point"))).norm();
    CHECK(err < 0.1 + r.track_uncertainty_mm);
    worst = std::max(worst, err);
    if (j.at("joint") == "fillet") CHECK(r.gap_mm == Approx(j.at("gap_mm").get<double>()).margin(0.15));
  }
  CHECK(total == 18);
  CHECK(ok >= 16);
  WARN("worst track point error " << worst << " mm over " << ok << " readings");
}

TEST_CASE("dataset: the raster source writes the same shard twice", "[dataset][gl]") {
  vts::DatasetSpec spec = small_spec();
  spec.source = vts::SourceKind::Raster;
  const vts::test::TempDir a, b;
  CHECK(vts::write_shard(spec, 0, a.path) == vts::write_shard(spec, 0, b.path));
  CHECK(contents(a.path) == contents(b.path));
}
