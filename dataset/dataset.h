#pragma once
// Labelled profile datasets (docs/DATASETS.md): `vts dataset`, and what the
// Python package and a Dask front-end call. A dataset is shard_count(spec)
// shards; shard k is a pure function of (spec, k): write_shard writes the
// same bytes for it on any machine running the same build, in any worker,
// with any thread limit, so shards can be made in any order, by any number
// of processes, and made again.
//
// Shard k's files in the output directory (KKKKK = k, JJJJ = the scene):
//   shard-KKKKK-scene-JJJJ.exr  one profile EXR per scene (docs/EXR_FORMAT.md),
//                               its header holding that scene
//   shard-KKKKK.jsonl           one JSON line per profile: the scene's draws,
//                               the pose and the joint's truth in the sensor frame
//   shard-KKKKK.json            the shard's record, written last: every file's
//                               size and SHA-256; a shard without it is not made
// and manifest.json for the whole dataset (run_dataset, write_manifest).
// Every file is written under a temporary name and renamed when complete.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "dataset/scene.h"
#include "dataset/spec.h"

namespace vts {

struct DatasetFile {
  std::string name;  // in the output directory
  std::uint64_t bytes = 0;
  std::string sha256;  // 64 lowercase hex digits
  bool operator==(const DatasetFile&) const = default;
};

struct ShardInfo {
  int shard = 0;
  int scenes = 0;
  std::int64_t profiles = 0;
  std::vector<DatasetFile> files;  // the scenes' EXRs in order, then the JSONL (not the record)
  bool operator==(const ShardInfo&) const = default;
};

struct DatasetProgress {
  int shards_total = 0;
  int shards_done = 0;     // made or found complete
  int shards_skipped = 0;  // of them, found complete (resumed)
  std::int64_t profiles_total = 0;
  std::int64_t profiles_done = 0;  // in the shards done and the scenes done of the shard in hand
};

struct DatasetCallbacks {
  // After each scene written and each shard found complete; on the calling thread.
  std::function<void(const DatasetProgress&)> progress;
  // Polled before each scene and each scan batch: true stops the run with
  // vts::Cancelled (pipeline/scan_job.h); the shard in hand has no record.
  std::function<bool()> cancelled;
};

// "shard-00003.jsonl", "shard-00003.json", "shard-00003-scene-0012.exr"
std::string shard_jsonl_name(int shard);
std::string shard_record_name(int shard);
std::string scene_exr_name(int shard, int scene);
inline constexpr const char* kManifestName = "manifest.json";

// SHA-256 of dataset_spec_to_yaml(spec): what records and the manifest name
// the spec by.
std::string dataset_spec_sha256(const DatasetSpec& spec);

// Makes shard k (0 <= k < shard_count(spec)) in out_dir (created if
// missing): its record first removed, then each scene drawn (draw_scene),
// scanned by run_scan_job into its EXR, the JSONL, and the record. Throws
// std::out_of_range for a bad k, DatasetDrawError, vts::Cancelled, or what
// the scan and the files throw; the shard then has no record.
ShardInfo write_shard(const DatasetSpec& spec, int k, const std::filesystem::path& out_dir,
                      const DatasetCallbacks& callbacks = {});

// Shard k if it is complete: its record names this spec (by SHA-256) and
// this vts version, lists the files write_shard writes, and each of them is
// there with the size and SHA-256 recorded. Otherwise nullopt, and *why (if
// given) says what is missing or differs.
std::optional<ShardInfo> verified_shard(const DatasetSpec& spec, int k, const std::filesystem::path& out_dir,
                                        std::string* why = nullptr);

// manifest.json: the spec in canonical form and its SHA-256, the vts
// version, every shard's files with sizes and checksums, and the totals.
// `shards` in shard order, one per shard.
std::string manifest_json(const DatasetSpec& spec, const std::vector<ShardInfo>& shards);
// Writes it to out_dir/manifest.json (whole or not at all).
void write_manifest(const DatasetSpec& spec, const std::vector<ShardInfo>& shards,
                    const std::filesystem::path& out_dir);

struct DatasetResult {
  std::vector<ShardInfo> shards;  // all of them, in order
  std::vector<int> written;       // made by this run
  std::vector<int> skipped;       // found complete (resumed)
  std::int64_t profiles_written = 0;
  double elapsed_s = 0.0;         // wall time of the run
  std::filesystem::path manifest;
};

// Makes every shard not found complete (verified_shard), in order, then the
// manifest. A run stopped part way leaves complete shards with records; the
// next run resumes from them.
DatasetResult run_dataset(const DatasetSpec& spec, const std::filesystem::path& out_dir,
                          const DatasetCallbacks& callbacks = {});

}  // namespace vts
