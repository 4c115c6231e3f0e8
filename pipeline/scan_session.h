#pragma once
// The scan pipeline for one scanner and one scene, without a path: the main
// profile source (raster emulator or ray-cast reference), optionally the
// Embree reference beside it, and the error model, the batch spread over the
// threads. run_scan_job (pipeline/scan_job.h) drives it along a path; the
// viewer feeds it the poses of its torch. docs/ARCHITECTURE.md shows where it
// sits.
#include <cstdint>
#include <memory>
#include <span>
#include <string_view>
#include <vector>

#include "sensor/camera_image.h"
#include "sensor/error_model.h"
#include "sensor/mesh.h"
#include "sensor/pose.h"
#include "sensor/profile.h"
#include "sensor/profile_source.h"
#include "sensor/scanner.h"

namespace vts {

class RayScene;

enum class SourceKind {
  Raster,     // the OSMesa emulator (render/raster_source.h)
  Reference,  // the Embree ray caster (sensor/reference_source.h)
};
std::string_view to_string(SourceKind kind);  // "raster", "reference"

// A profile source of `kind` over mesh_world (world frame, mm). A raster
// source that cannot get its OpenGL context throws std::runtime_error
// "cannot create the raster source (OSMesa): ...".
std::unique_ptr<ProfileSource> make_source(SourceKind kind, const ScannerDesc& scanner, const Mesh& mesh_world);

// One profile to take: the laser's pose, its time stamp and its index in the
// run (the error model's draws are keyed by it, so the same index gives the
// same profile whatever the batch or thread).
struct ScanRequest {
  Pose world_from_sensor = Pose::Identity();  // laser frame in the world
  double time_s = 0.0;
  std::int64_t index = 0;
};

// One batch's profiles, entry k for request k, each stamped with its
// request's pose, time and index. The vectors keep their size and buffers
// from batch to batch (no allocation once grown).
struct ScanResults {
  std::vector<Profile> ideal;         // the main source's geometric profiles
  std::vector<Profile> measured;      // through the error model; empty when the scanner is ideal
  std::vector<Profile> ideal_ref;     // the reference's, when the session has one
  std::vector<Profile> measured_ref;  // its measured ones (same draws), when it has one and a model
  // Image mode (scanner.camera_image) with keep_images: the camera image
  // request k's profile was read from, labelled (sensor/camera_image.h).
  std::vector<CameraImage> images;

  // What the sensor gives for request k: measured, or ideal with the error
  // model off.
  std::span<const Profile> output() const { return measured.empty() ? ideal : measured; }
  std::span<const Profile> output_ref() const { return measured_ref.empty() ? ideal_ref : measured_ref; }
};

class ScanSession {
 public:
  // Builds the sources over mesh_world: `main`, and with `with_reference` and
  // a raster main source the Embree reference beside it (a reference main
  // source is its own reference). scanner.ideal switches the error model
  // off; `seed` seeds its draws. Throws as make_source.
  ScanSession(const ScannerDesc& scanner, const Mesh& mesh_world, SourceKind main, bool with_reference,
              std::uint64_t seed);
  ~ScanSession();
  ScanSession(const ScanSession&) = delete;
  ScanSession& operator=(const ScanSession&) = delete;

  // Image mode (scanner.camera_image, not ideal): profiles come from the
  // camera image (render/camera_renderer.h, sensor/camera_image.h) instead
  // of the error model; with keep_images the images are returned too.
  void keep_images(bool keep) { keep_images_ = keep; }
  bool image_mode() const { return scanner_.camera_image && !scanner_.ideal; }

  // Scans every request into `out` (resized to requests.size()). Not
  // thread-safe: one batch at a time per session.
  void scan(std::span<const ScanRequest> requests, ScanResults& out);

  const ScannerDesc& scanner() const { return scanner_; }
  SourceKind main_kind() const { return main_kind_; }
  bool has_reference_source() const { return reference_ != nullptr; }
  std::uint64_t seed() const { return seed_; }
  // The error model's counters over every profile scanned so far, of the
  // main source and of the reference (docs/CLI.md, vts scan's output).
  ScanState counts() const;
  ScanState reference_counts() const;

 private:
  ScannerDesc scanner_;
  SourceKind main_kind_;
  std::uint64_t seed_;
  std::unique_ptr<ProfileSource> main_, reference_;
  std::vector<Pose> poses_;
  std::vector<ScanState> states_, states_ref_;  // per part of a batch: scratch and counters
  // Image mode: the mesh (renderers are made on first use, one per part),
  // the Embree scene for the laser's bounce, and each part's worker.
  struct ImageWorker;
  Mesh mesh_;
  std::unique_ptr<RayScene> ray_scene_;
  std::vector<std::unique_ptr<ImageWorker>> image_workers_;
  bool keep_images_ = false;
  void scan_images(std::span<const ScanRequest> requests, ScanResults& out);
};

}  // namespace vts
