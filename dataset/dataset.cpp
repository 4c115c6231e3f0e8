#include "dataset/dataset.h"

#include <chrono>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "common/atomic_file.h"
#include "common/sha256.h"
#include "common/version.h"
#include "pipeline/profile_truth.h"
#include "pipeline/scan_job.h"
#include "pipeline/sinks.h"
#include "trackio/result_json.h"

namespace vts {
namespace {

namespace fs = std::filesystem;
namespace tk = vts::tracker;
using Json = trackio::Json;

constexpr const char* kRecordFormat = "vts-dataset-shard 1";
constexpr const char* kManifestFormat = "vts-dataset 1";

// The scene's EXR, and each row's count of valid points on the way.
class SceneSink final : public ScanSink {
 public:
  SceneSink(fs::path path, ExrCompression compression) : exr_(std::move(path), compression) {}
  void begin(const ProfileFileInfo& info) override {
    exr_.begin(info);
    valid_points.assign(static_cast<std::size_t>(info.profiles), 0);
  }
  void write(const ScanBatch& batch) override {
    exr_.write(batch);
    for (std::size_t k = 0; k < batch.profiles.size(); ++k)
      valid_points[static_cast<std::size_t>(batch.first) + k] = batch.profiles[k].valid_count();
  }
  void finish() override { exr_.finish(); }
  std::vector<int> valid_points;

 private:
  ExrSink exr_;
};

// One profile's line (docs/DATASETS.md, "Per profile").
std::string profile_line(const DatasetSpec& spec, const DatasetScene& sc, int i, int valid_points) {
  const Cell& cell = sc.cell;
  const ScannerDesc& scanner = cell.scanner;
  const Workpiece& w = cell.workpieces.front();
  const Pose pose = cell.path.pose_at(i);
  const ProfileTruth t = profile_truth(w, scanner, pose);
  Json j;
  j["shard"] = sc.shard;
  j["scene"] = sc.scene;
  j["profile"] = i;
  j["exr"] = scene_exr_name(sc.shard, sc.scene);
  j["time_s"] = static_cast<double>(i) / scanner.rate_hz;
  j["joint"] = std::string(to_string(sc.joint));
  Json params;
  for (const auto& k : kJointParamNumbers) params[std::string(k.key)] = sc.params.*k.member;
  params["passes"] = sc.params.passes;
  j["params"] = std::move(params);
  j["sensor"] = Json{{"preset", sc.preset},          {"material", sc.material},
                     {"points", scanner.points},      {"fan_deg", scanner.fan_deg},
                     {"min_range_mm", scanner.min_range_mm}, {"max_range_mm", scanner.max_range_mm},
                     {"ideal", scanner.ideal},        {"seed", sc.noise_seed}};
  j["view"] = Json{{"standoff_mm", sc.standoff_mm}, {"tilt_deg", sc.tilt_deg},   {"roll_deg", sc.roll_deg},
                   {"travel_deg", sc.travel_deg},   {"offset_mm", sc.offset_mm}, {"draws", sc.draws}};
  const Eigen::Quaterniond q = rotation_quat(pose);
  const Vec3& p = pose.translation();
  j["pose"] = Json{{"position_mm", {p.x(), p.y(), p.z()}}, {"quaternion_wxyz", {q.w(), q.x(), q.y(), q.z()}}};
  j["valid_points"] = valid_points;
  j["ideal"] = spec.ideal;
  j.update(profile_truth_json(t));
  std::string line = j.dump();
  line += '\n';
  return line;
}

DatasetFile file_info(const fs::path& dir, const std::string& name) {
  DatasetFile f;
  f.name = name;
  f.sha256 = sha256_file(dir / name, &f.bytes);
  return f;
}

Json files_json(const std::vector<DatasetFile>& files) {
  Json a = Json::array();
  for (const DatasetFile& f : files) a.push_back(Json{{"name", f.name}, {"bytes", f.bytes}, {"sha256", f.sha256}});
  return a;
}

void write_file(const fs::path& path, const std::string& text) {
  AtomicFile file(path);
  if (!file.is_open()) throw std::runtime_error("cannot write " + path.string());
  file.stream() << text;
  file.commit();
}

void check_shard_index(const DatasetSpec& spec, int k) {
  if (k < 0 || k >= shard_count(spec))
    throw std::out_of_range("shard " + std::to_string(k) + ": the spec has shards 0 .. " +
                            std::to_string(shard_count(spec) - 1));
}

// The record's files, checked against what write_shard writes; "" if they match.
std::string check_record(const Json& r, const DatasetSpec& spec, int k, ShardInfo& info) {
  if (!r.is_object() || r.value("format", "") != kRecordFormat) return "not a shard record";
  if (r.value("vts_version", "") != version())
    return "written by vts " + r.value("vts_version", std::string("?")) + ", this is " + std::string(version());
  if (r.value("spec_sha256", "") != dataset_spec_sha256(spec)) return "written for another spec";
  if (r.value("shard", -1) != k) return "the record of another shard";
  info.shard = k;
  info.scenes = r.at("scenes").get<int>();
  info.profiles = r.at("profiles").get<std::int64_t>();
  for (const Json& f : r.at("files"))
    info.files.push_back({f.at("name").get<std::string>(), f.at("bytes").get<std::uint64_t>(),
                          f.at("sha256").get<std::string>()});
  std::vector<std::string> expected;
  for (int j = 0; j < spec.scenes_per_shard; ++j) expected.push_back(scene_exr_name(k, j));
  expected.push_back(shard_jsonl_name(k));
  if (info.scenes != spec.scenes_per_shard || info.profiles != profiles_per_shard(spec) ||
      info.files.size() != expected.size())
    return "the record does not list this spec's files";
  for (std::size_t i = 0; i < expected.size(); ++i)
    if (info.files[i].name != expected[i]) return "the record does not list this spec's files";
  return {};
}

}  // namespace

std::string shard_jsonl_name(int shard) { return shard_stem(shard) + ".jsonl"; }
std::string shard_record_name(int shard) { return shard_stem(shard) + ".json"; }
std::string scene_exr_name(int shard, int scene) { return scene_stem(shard, scene) + ".exr"; }

std::string dataset_spec_sha256(const DatasetSpec& spec) { return sha256_hex(dataset_spec_to_yaml(spec)); }

ShardInfo write_shard(const DatasetSpec& spec, int k, const fs::path& out_dir, const DatasetCallbacks& callbacks) {
  check_shard_index(spec, k);
  fs::create_directories(out_dir);
  // A shard being made has no record, whatever was there before.
  fs::remove(out_dir / shard_record_name(k));

  ShardInfo info;
  info.shard = k;
  info.scenes = spec.scenes_per_shard;
  AtomicFile jsonl(out_dir / shard_jsonl_name(k));  // streamed scene by scene, renamed at the end
  if (!jsonl.is_open()) throw std::runtime_error("cannot write " + jsonl.path().string());
  DatasetProgress progress;
  progress.shards_total = 1;
  progress.profiles_total = profiles_per_shard(spec);
  ScanCallbacks scan_callbacks;
  scan_callbacks.cancelled = callbacks.cancelled;
  for (int j = 0; j < spec.scenes_per_shard; ++j) {
    if (callbacks.cancelled && callbacks.cancelled()) throw Cancelled();
    const DatasetScene sc = draw_scene(spec, k, j);
    ScanSpec scan;
    scan.cell = sc.cell;
    scan.scene_label = sc.cell.name;
    scan.source = spec.source;
    scan.seed = sc.noise_seed;
    SceneSink sink(out_dir / scene_exr_name(k, j), spec.compression);
    run_scan_job(scan, sink, scan_callbacks);
    for (int i = 0; i < spec.profiles_per_scene; ++i)
      jsonl.stream() << profile_line(spec, sc, i, sink.valid_points[static_cast<std::size_t>(i)]);
    info.profiles += spec.profiles_per_scene;
    info.files.push_back(file_info(out_dir, scene_exr_name(k, j)));
    progress.profiles_done = info.profiles;
    if (callbacks.progress) callbacks.progress(progress);
  }
  jsonl.commit();
  info.files.push_back(file_info(out_dir, shard_jsonl_name(k)));

  Json record;
  record["format"] = kRecordFormat;
  record["vts_version"] = std::string(version());
  record["spec_sha256"] = dataset_spec_sha256(spec);
  record["shard"] = k;
  record["scenes"] = info.scenes;
  record["profiles"] = info.profiles;
  record["files"] = files_json(info.files);
  write_file(out_dir / shard_record_name(k), record.dump(2) + "\n");
  return info;
}

std::optional<ShardInfo> verified_shard(const DatasetSpec& spec, int k, const fs::path& out_dir, std::string* why) {
  check_shard_index(spec, k);
  auto no = [&](const std::string& reason) -> std::optional<ShardInfo> {
    if (why) *why = shard_stem(k) + ": " + reason;
    return std::nullopt;
  };
  const fs::path record_path = out_dir / shard_record_name(k);
  std::ifstream in(record_path, std::ios::binary);
  if (!in) return no("no record (" + shard_record_name(k) + ")");
  ShardInfo info;
  try {
    const Json record = Json::parse(in);
    if (std::string bad = check_record(record, spec, k, info); !bad.empty()) return no(bad);
  } catch (const Json::exception& e) {
    return no(shard_record_name(k) + " is not a record: " + e.what());
  }
  for (const DatasetFile& f : info.files) {
    std::error_code ec;
    const fs::path path = out_dir / f.name;
    const std::uintmax_t size = fs::file_size(path, ec);
    if (ec) return no(f.name + " is missing");
    if (size != f.bytes)
      return no(f.name + " has " + std::to_string(size) + " bytes, the record " + std::to_string(f.bytes));
    if (sha256_file(path) != f.sha256) return no(f.name + " differs from its recorded SHA-256");
  }
  return info;
}

std::string manifest_json(const DatasetSpec& spec, const std::vector<ShardInfo>& shards) {
  Json m;
  m["format"] = kManifestFormat;
  m["vts_version"] = std::string(version());
  m["spec_sha256"] = dataset_spec_sha256(spec);
  m["spec"] = dataset_spec_to_yaml(spec);
  Json list = Json::array();
  std::int64_t scenes = 0, profiles = 0, files = 0;
  std::uint64_t bytes = 0;
  for (const ShardInfo& s : shards) {
    list.push_back(Json{{"shard", s.shard},
                        {"scenes", s.scenes},
                        {"profiles", s.profiles},
                        {"record", shard_record_name(s.shard)},
                        {"files", files_json(s.files)}});
    scenes += s.scenes;
    profiles += s.profiles;
    files += static_cast<std::int64_t>(s.files.size());
    for (const DatasetFile& f : s.files) bytes += f.bytes;
  }
  m["shards"] = std::move(list);
  m["totals"] = Json{{"shards", shards.size()}, {"scenes", scenes}, {"profiles", profiles}, {"files", files},
                     {"bytes", bytes}};
  return m.dump(2) + "\n";
}

void write_manifest(const DatasetSpec& spec, const std::vector<ShardInfo>& shards, const fs::path& out_dir) {
  if (static_cast<int>(shards.size()) != shard_count(spec))
    throw std::invalid_argument("write_manifest: " + std::to_string(shards.size()) + " shards given, the spec has " +
                                std::to_string(shard_count(spec)));
  fs::create_directories(out_dir);
  write_file(out_dir / kManifestName, manifest_json(spec, shards));
}

DatasetResult run_dataset(const DatasetSpec& spec, const fs::path& out_dir, const DatasetCallbacks& callbacks) {
  const auto start = std::chrono::steady_clock::now();
  fs::create_directories(out_dir);
  DatasetResult result;
  DatasetProgress progress;
  progress.shards_total = shard_count(spec);
  progress.profiles_total = progress.shards_total * profiles_per_shard(spec);
  for (int k = 0; k < shard_count(spec); ++k) {
    if (auto done = verified_shard(spec, k, out_dir)) {
      result.shards.push_back(std::move(*done));
      result.skipped.push_back(k);
      ++progress.shards_skipped;
    } else {
      DatasetCallbacks inner;
      inner.cancelled = callbacks.cancelled;
      const std::int64_t before = progress.profiles_done;
      if (callbacks.progress)
        inner.progress = [&](const DatasetProgress& p) {
          DatasetProgress all = progress;
          all.profiles_done = before + p.profiles_done;
          callbacks.progress(all);
        };
      result.shards.push_back(write_shard(spec, k, out_dir, inner));
      result.written.push_back(k);
      result.profiles_written += result.shards.back().profiles;
    }
    ++progress.shards_done;
    progress.profiles_done += profiles_per_shard(spec);
    if (callbacks.progress) callbacks.progress(progress);
  }
  write_manifest(spec, result.shards, out_dir);
  result.manifest = out_dir / kManifestName;
  result.elapsed_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace vts
