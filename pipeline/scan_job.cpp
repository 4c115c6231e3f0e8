#include "pipeline/scan_job.h"

#include "sensor/camera_image_file.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <chrono>
#include <future>
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
  // In locals: stored into `s` at every point, they made the loop reload
  // the profile's data pointers each time. The same additions in the same
  // order.
  const int n = p.size();
  const std::uint8_t* valid = p.valid.data();
  const float* range = p.range_mm.data();
  std::int64_t count = 0;
  double sum = s.range_sum_mm;
  for (int i = 0; i < n; ++i) {
    if (!valid[i]) continue;
    ++count;
    sum += range[i];
  }
  s.valid += count;
  s.range_sum_mm = sum;
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
  if (!spec.images_dir.empty()) {
    if (!session.image_mode())
      throw std::invalid_argument("images: the camera images exist only in image mode (--camera-image)");
    std::error_code ec;
    std::filesystem::create_directories(spec.images_dir, ec);
    if (ec) throw std::runtime_error("cannot create " + spec.images_dir.string() + ": " + ec.message());
    session.keep_images(true);
  }
  sink.begin(scan_file_info(spec));

  const auto start = std::chrono::steady_clock::now();
  const int batch = std::max(1, spec.batch_profiles);
  // Two batches in flight: while the sink takes batch k on this thread (an
  // EXR's compression and writing), batch k + 1 is scanned on a helper
  // thread whose parallel loops share the thread pool with the
  // compression's tasks, so neither stage waits for the other's serial
  // parts. The sink still sees the batches in order, on this thread.
  std::array<std::vector<ScanRequest>, 2> requests;
  std::array<ScanResults, 2> results;
  auto check_cancelled = [&] {
    if (callbacks.cancelled && callbacks.cancelled()) throw Cancelled();
  };
  auto scan_async = [&](std::int64_t first, int slot) {
    const std::int64_t count = std::min<std::int64_t>(batch, n - first);
    std::vector<ScanRequest>& req = requests[slot];
    req.resize(static_cast<std::size_t>(count));
    for (std::int64_t k = 0; k < count; ++k)
      req[k] = {cell.path.pose_at(first + k), static_cast<double>(first + k) / cell.scanner.rate_hz, first + k};
    return std::async(std::launch::async, [&session, &req, &out = results[slot]] { session.scan(req, out); });
  };
  ScanStats stats;
  // Declared after what its task uses: an exception leaves it first, and its
  // destructor waits for the task.
  std::future<void> pending;
  // Polled once per batch, before it is written (before batch 0 is
  // scanned): a job cancelled after m batches has written m, as before the
  // two stages overlapped; the batch scanned ahead is dropped.
  if (n > 0) {
    check_cancelled();
    pending = scan_async(0, 0);
  }
  for (std::int64_t first = 0, k = 0; first < n; first += batch, ++k) {
    if (k > 0) check_cancelled();
    pending.get();
    // The counters include batch k, as the helper thread is idle now.
    stats.error_model = session.counts();
    stats.error_model_ref = session.reference_counts();
    const int slot = static_cast<int>(k % 2);
    if (first + batch < n) pending = scan_async(first + batch, 1 - slot);
    const ScanResults& r = results[slot];
    const std::int64_t count = static_cast<std::int64_t>(requests[slot].size());
    ScanBatch out{first, r.output(), {}};
    if (spec.with_reference) out.reference = session.has_reference_source() ? r.output_ref() : out.profiles;
    sink.write(out);
    for (const CameraImage& image : r.images) write_camera_image(spec.images_dir, image);
    for (std::int64_t i = 0; i < count; ++i)
      add(stats, out.profiles[i], r.ideal[i], session.has_reference_source() ? &r.ideal_ref[i] : nullptr);
    stats.elapsed_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (callbacks.progress) callbacks.progress(first + count, n, stats);
  }
  sink.finish();
  stats.elapsed_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return stats;
}

}  // namespace vts
