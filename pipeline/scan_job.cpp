#include "pipeline/scan_job.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <vector>

#include "sensor/scene_file.h"

namespace vts {
namespace {

// `p` as written; `ideal` and `ideal_ref` the two sources' ideal profiles
// (the reference check compares geometry, before the error model).
void add(ScanStats& s, const Profile& p, const Profile& ideal, const Profile* ideal_ref) {
  ++s.profiles;
  s.samples += p.size();
  for (int i = 0; i < p.size(); ++i) {
    if (!p.valid[i]) continue;
    ++s.valid;
    s.range_sum_mm += p.range_mm[i];
  }
  if (!ideal_ref) return;
  const Profile& ref = *ideal_ref;
  int disagreements = 0;
  for (int i = 0; i < ideal.size(); ++i) {
    if (ideal.valid[i] && ref.valid[i]) {
      ++s.both_valid;
      s.max_diff_mm = std::max(s.max_diff_mm, double(std::abs(ideal.range_mm[i] - ref.range_mm[i])));
      s.shadow_disagreements += ideal.camera_visible[i] != ref.camera_visible[i];
    } else if (ideal.valid[i] != ref.valid[i]) {
      ++disagreements;
    }
  }
  s.hit_miss += disagreements;
  s.max_hit_miss_per_profile = std::max(s.max_hit_miss_per_profile, disagreements);
}

}  // namespace

ProfileFileInfo scan_file_info(const ScanSpec& spec) {
  ProfileFileInfo info;
  info.scanner = spec.cell.scanner;
  info.scene_name = spec.scene_label.empty() ? spec.cell.name : spec.scene_label;
  info.scene_text = scene_to_yaml(spec.cell);
  info.profiles = spec.cell.path.profiles;
  info.has_reference = spec.with_reference;
  info.error_model = !spec.cell.scanner.ideal;
  info.seed = spec.seed;
  return info;
}

ScanStats run_scan_job(const ScanSpec& spec, ScanSink& sink, const ScanCallbacks& callbacks) {
  const Cell& cell = spec.cell;
  const std::int64_t n = cell.path.profiles;
  // Sources first: a GL failure must not leave anything behind.
  ScanSession session(cell.scanner, cell.mesh(), spec.source, spec.with_reference, spec.seed);
  sink.begin(scan_file_info(spec));

  const auto start = std::chrono::steady_clock::now();
  const int batch = std::max(1, spec.batch_profiles);
  std::vector<ScanRequest> requests;
  ScanResults results;
  ScanStats stats;
  for (std::int64_t first = 0; first < n; first += batch) {
    if (callbacks.cancelled && callbacks.cancelled()) throw Cancelled();
    const std::int64_t count = std::min<std::int64_t>(batch, n - first);
    requests.resize(static_cast<std::size_t>(count));
    for (std::int64_t k = 0; k < count; ++k)
      requests[k] = {cell.path.pose_at(first + k), static_cast<double>(first + k) / cell.scanner.rate_hz, first + k};
    session.scan(requests, results);

    ScanBatch out{first, results.output(), {}};
    if (spec.with_reference) out.reference = session.has_reference_source() ? results.output_ref() : out.profiles;
    sink.write(out);
    for (std::int64_t k = 0; k < count; ++k)
      add(stats, out.profiles[k], results.ideal[k], session.has_reference_source() ? &results.ideal_ref[k] : nullptr);
    stats.error_model = session.counts();
    stats.error_model_ref = session.reference_counts();
    stats.elapsed_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (callbacks.progress) callbacks.progress(first + count, n, stats);
  }
  sink.finish();
  stats.elapsed_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return stats;
}

}  // namespace vts
