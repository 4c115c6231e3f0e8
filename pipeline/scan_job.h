#pragma once
// A scan job: one call that scans a cell along its path in batches, through
// the main source, optionally the reference beside it, and the error model,
// and streams the profiles to a sink (an EXR file, memory, a network stream),
// reporting progress and statistics through callbacks; cancellable.
// `vts scan` and `vts static` run it, as do the front-ends to come (the
// Python package, `vts dataset`, `vts serve`); docs/ARCHITECTURE.md.
//
// The sink is called on the caller's thread, batch after batch, while the
// next batch is scanned on a helper thread (the two stages overlap; their
// parallel work shares the thread limit's pool). No signal handling here: a front-end maps its signals (or a client's
// `cancel`) to ScanCallbacks::cancelled.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <span>
#include <stdexcept>
#include <string>

#include "pipeline/scan_session.h"
#include "sensor/cell.h"
#include "sensor/error_model.h"
#include "sensor/profile_exr.h"

namespace vts {

// What a job scans: fixed for its run (MuJoCo's mjModel to the job's mjData).
struct ScanSpec {
  // The scene (workpieces), the scanner (scanner.ideal switches the error
  // model off) and the path: profile i at path.pose_at(i), time i / rate_hz.
  Cell cell;
  std::string scene_label;  // names the scene in outputs (vts.scene); empty: cell.name
  SourceKind source = SourceKind::Raster;  // fills the main profiles
  bool with_reference = false;  // also the Embree reference beside them, and the check of the two
  std::uint64_t seed = 0;       // the error model's draws
  int batch_profiles = 512;     // profiles per batch: memory is bounded by it
  // Image mode (cell.scanner.camera_image): also write each profile's camera
  // image and its labels here (sensor/camera_image_file.h); empty: none.
  std::filesystem::path images_dir;
};

// One batch as the job hands it to a sink: profiles first .. first + n - 1
// in order, as the sensor gives them (measured, or ideal with the error
// model off), and with a reference the reference's beside them (the main
// profiles themselves when the main source is the reference).
struct ScanBatch {
  std::int64_t first = 0;
  std::span<const Profile> profiles;
  std::span<const Profile> reference;  // empty without a reference
};

// Where the profiles go. begin() comes after the sources exist (so a GL
// failure leaves nothing behind), finish() after the last batch; a job that
// fails or is cancelled destroys the sink without finish().
class ScanSink {
 public:
  virtual ~ScanSink() = default;
  // What is coming: scanner, scene, row count, channels (as an EXR header).
  virtual void begin(const ProfileFileInfo& info) = 0;
  virtual void write(const ScanBatch& batch) = 0;
  virtual void finish() = 0;
};

// What `vts scan` reports (docs/CLI.md, "Output"), over the profiles so far.
struct ScanStats {
  std::int64_t profiles = 0;
  // The profiles as written.
  std::int64_t samples = 0, valid = 0;
  double range_sum_mm = 0.0;
  // The check of the main source's ideal profiles against the reference's
  // (with a reference source beside a raster one).
  std::int64_t both_valid = 0, hit_miss = 0, shadow_disagreements = 0;
  double max_diff_mm = 0.0;
  int max_hit_miss_per_profile = 0;
  // The error model's counters, main source and reference.
  ScanState error_model, error_model_ref;
  double elapsed_s = 0.0;  // wall time since the first batch started

  double valid_percent() const { return samples ? 100.0 * static_cast<double>(valid) / samples : 0.0; }
  double mean_range_mm() const { return valid ? range_sum_mm / static_cast<double>(valid) : 0.0; }
  double profiles_per_s() const { return elapsed_s > 0 ? static_cast<double>(profiles) / elapsed_s : 0.0; }
};

struct ScanCallbacks {
  // After each batch has gone to the sink: profiles done, of total.
  std::function<void(std::int64_t done, std::int64_t total, const ScanStats& so_far)> progress;
  // Polled before each batch; true stops the job: run_scan_job throws
  // Cancelled and the sink is not finished.
  std::function<bool()> cancelled;
};

struct Cancelled : std::runtime_error {
  Cancelled() : std::runtime_error("scan cancelled") {}
};

// The header a job's output carries (scanner, scene as YAML, rows, channels,
// seed); what ScanSink::begin receives.
ProfileFileInfo scan_file_info(const ScanSpec& spec);

// Runs the job to the end and returns its statistics. Throws
// std::invalid_argument for an unusable scanner, std::runtime_error when a
// source cannot be built, Cancelled, or what the sink throws.
ScanStats run_scan_job(const ScanSpec& spec, ScanSink& sink, const ScanCallbacks& callbacks = {});

}  // namespace vts
