#include "pipeline/scan_session.h"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "common/parallel.h"
#include "render/camera_renderer.h"
#include "render/raster_source.h"
#include "sensor/ray_scene.h"
#include "sensor/reference_source.h"

namespace vts {

std::string_view to_string(SourceKind kind) { return kind == SourceKind::Raster ? "raster" : "reference"; }

std::unique_ptr<ProfileSource> make_source(SourceKind kind, const ScannerDesc& scanner, const Mesh& mesh_world) {
  if (kind == SourceKind::Reference) return make_reference_source(scanner, mesh_world);
  try {
    return make_raster_source(scanner, mesh_world);
  } catch (const std::exception& e) {
    throw std::runtime_error(std::string("cannot create the raster source (OSMesa): ") + e.what());
  }
}

ScanSession::ScanSession(const ScannerDesc& scanner, const Mesh& mesh_world, SourceKind main,
                         bool with_reference, std::uint64_t seed)
    : scanner_(scanner), main_kind_(main), seed_(seed) {
  main_ = make_source(main, scanner, mesh_world);
  if (with_reference && main == SourceKind::Raster) reference_ = make_source(SourceKind::Reference, scanner, mesh_world);
  if (image_mode()) {
    mesh_ = mesh_world;
    ray_scene_ = std::make_unique<RayScene>(mesh_world, "camera image");
  }
}

// One part's renderer (its own OpenGL context) and scratch.
struct ScanSession::ImageWorker {
  std::unique_ptr<CameraRenderer> renderer;
  RadianceImage radiance;
  LaserPaths paths;
  CameraImage image;
  stripe::PeakResult peaks;
};

ScanSession::~ScanSession() = default;

void ScanSession::scan_images(std::span<const ScanRequest> requests, ScanResults& out) {
  const std::size_t count = requests.size();
  out.images.resize(keep_images_ ? count : 0);
  const std::size_t parts = std::clamp<std::size_t>(count, 1, static_cast<std::size_t>(thread_limit()));
  while (image_workers_.size() < parts) image_workers_.push_back(std::make_unique<ImageWorker>());
  parallel_for(parts, [&](std::size_t t) {
    ImageWorker& w = *image_workers_[t];
    if (!w.renderer) {
      try {
        w.renderer = std::make_unique<CameraRenderer>(scanner_, mesh_);
      } catch (const std::runtime_error& e) {
        throw std::runtime_error(std::string("cannot create the camera-image renderer (OSMesa): ") + e.what());
      }
    }
    for (std::size_t k = count * t / parts, end = count * (t + 1) / parts; k < end; ++k) {
      const ScanRequest& r = requests[k];
      CameraImage& image = keep_images_ ? out.images[k] : w.image;
      w.renderer->render(r.world_from_sensor, w.radiance);
      trace_laser_paths(scanner_, *ray_scene_, r.world_from_sensor, w.paths);
      form_image(scanner_, w.radiance, w.paths, seed_, r.index, image);
      detect_stripe(scanner_, image, w.peaks);
      profile_from_peaks(scanner_, image, w.peaks, out.ideal[k], out.measured[k]);
      if (reference_) profile_from_peaks(scanner_, image, w.peaks, out.ideal_ref[k], out.measured_ref[k]);
    }
  });
}

void ScanSession::scan(std::span<const ScanRequest> requests, ScanResults& out) {
  const std::size_t count = requests.size();
  const bool model = !scanner_.ideal;
  poses_.resize(count);
  for (std::size_t k = 0; k < count; ++k) poses_[k] = requests[k].world_from_sensor;
  out.ideal.resize(count);
  out.measured.resize(model ? count : 0);
  out.ideal_ref.resize(reference_ ? count : 0);
  out.measured_ref.resize(reference_ && model ? count : 0);
  if (!image_mode() || !keep_images_) out.images.clear();  // none left from an earlier scan into `out`
  // Profiles [first, end) from both sources, stamped with their requests'
  // pose, time and index.
  auto scan_range = [&](std::size_t first, std::size_t end) {
    const std::span<const Pose> poses = std::span<const Pose>(poses_).subspan(first, end - first);
    main_->scan_batch(poses, std::span<Profile>(out.ideal).subspan(first, end - first));
    if (reference_) reference_->scan_batch(poses, std::span<Profile>(out.ideal_ref).subspan(first, end - first));
    for (std::size_t k = first; k < end; ++k)
      for (Profile* p : {&out.ideal[k], reference_ ? &out.ideal_ref[k] : nullptr}) {
        if (!p) continue;
        p->world_from_sensor = requests[k].world_from_sensor;
        p->time_s = requests[k].time_s;
        p->index = requests[k].index;
      }
  };
  if (image_mode()) {
    scan_range(0, count);
    if (model && count > 0) scan_images(requests, out);
    return;
  }
  // Each part scans its profiles (with both sources) and applies the error
  // model to them at once: one wait per batch instead of two, and the model
  // reads profiles still in cache. The draws are keyed by profile index, so
  // both sources see the same ones and how a batch is split changes nothing;
  // each part has its own state (scratch and counters, summed by counts()).
  // A raster source called inside a parallel loop does not split its part
  // again (RasterSource::scan_batch). Parts of 128 profiles, at most four a
  // thread (each keeps its own scratch, so a caller's huge batch does not
  // multiply it).
  const std::size_t parts =
      std::clamp<std::size_t>(count / 128, 1, 4 * static_cast<std::size_t>(thread_limit()));
  while (states_.size() < parts) {
    states_.emplace_back().seed = seed_;
    states_ref_.emplace_back().seed = seed_;
  }
  parallel_for(parts, [&](std::size_t t) {
    const std::size_t first = count * t / parts, end = count * (t + 1) / parts;
    scan_range(first, end);
    if (!model) return;
    for (std::size_t k = first; k < end; ++k) {
      apply_error_model(scanner_, out.ideal[k], states_[t], out.measured[k]);
      if (reference_) apply_error_model(scanner_, out.ideal_ref[k], states_ref_[t], out.measured_ref[k]);
    }
  });
}

ScanState ScanSession::counts() const {
  ScanState total;
  total.seed = seed_;
  for (const ScanState& s : states_) add_counts(total, s);
  return total;
}

ScanState ScanSession::reference_counts() const {
  ScanState total;
  total.seed = seed_;
  for (const ScanState& s : states_ref_) add_counts(total, s);
  return total;
}

}  // namespace vts
