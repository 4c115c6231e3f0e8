#include "viewer/scan_worker.h"

#include <chrono>
#include <exception>
#include <span>

#include "render/raster_source.h"
#include "sensor/profile_source.h"
#include "sensor/reference_source.h"

namespace vts::viewer {
namespace {
// Scans taken from the queue at once: large enough to amortise a source's
// per-call overhead, small enough that results come back steadily.
constexpr std::size_t kMaxBatch = 16;
}  // namespace

ScanWorker::ScanWorker() { thread_ = std::thread([this] { run(); }); }

ScanWorker::~ScanWorker() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
    queue_.clear();
  }
  wake_.notify_all();
  thread_.join();
}

void ScanWorker::configure(const ScannerDesc& desc, const Mesh& mesh_world, SourceKind kind) {
  {
    std::lock_guard lock(mutex_);
    ++generation_;
    desc_ = desc;
    mesh_ = std::make_shared<const Mesh>(mesh_world);
    kind_ = kind;
    queue_.clear();
    results_.clear();
  }
  wake_.notify_all();
}

void ScanWorker::submit(const std::vector<Request>& requests) {
  if (requests.empty()) return;
  {
    std::lock_guard lock(mutex_);
    queue_.insert(queue_.end(), requests.begin(), requests.end());
  }
  wake_.notify_all();
}

std::vector<Profile> ScanWorker::take_results() {
  std::lock_guard lock(mutex_);
  std::vector<Profile> out;
  out.swap(results_);
  return out;
}

std::size_t ScanWorker::pending() const {
  std::lock_guard lock(mutex_);
  return queue_.size() + results_.size() + in_flight_;
}

void ScanWorker::wait_idle() {
  std::unique_lock lock(mutex_);
  idle_.wait(lock, [&] { return stop_ || (queue_.empty() && !busy_); });
}

std::string ScanWorker::take_error() {
  std::lock_guard lock(mutex_);
  std::string e;
  e.swap(error_);
  return e;
}

double ScanWorker::last_scan_ms() const {
  std::lock_guard lock(mutex_);
  return last_scan_ms_;
}

void ScanWorker::run() {
  std::unique_ptr<ProfileSource> source;
  std::uint64_t source_generation = 0;
  std::vector<Pose> poses;
  std::vector<Profile> profiles;
  std::vector<Request> batch;

  std::unique_lock lock(mutex_);
  while (true) {
    wake_.wait(lock, [&] { return stop_ || !queue_.empty(); });
    if (stop_) break;

    const std::uint64_t generation = generation_;
    const std::size_t n = std::min(queue_.size(), kMaxBatch);
    batch.assign(queue_.begin(), queue_.begin() + static_cast<std::ptrdiff_t>(n));
    queue_.erase(queue_.begin(), queue_.begin() + static_cast<std::ptrdiff_t>(n));
    const ScannerDesc desc = desc_;
    const std::shared_ptr<const Mesh> mesh = mesh_;
    const SourceKind kind = kind_;
    busy_ = true;
    in_flight_ = n;
    lock.unlock();

    std::string error;
    const auto t0 = std::chrono::steady_clock::now();
    try {
      if (!source || source_generation != generation) {
        source.reset();  // one OSMesa context at a time
        source = kind == SourceKind::Raster ? make_raster_source(desc, *mesh)
                                            : make_reference_source(desc, *mesh);
        source_generation = generation;
      }
      poses.resize(n);
      profiles.resize(n);
      for (std::size_t i = 0; i < n; ++i) poses[i] = batch[i].world_from_sensor;
      source->scan_batch(poses, std::span(profiles.data(), n));
      for (std::size_t i = 0; i < n; ++i) {
        profiles[i].world_from_sensor = batch[i].world_from_sensor;
        profiles[i].time_s = batch[i].time_s;
        profiles[i].index = batch[i].index;
      }
    } catch (const std::exception& e) {
      error = e.what();
      source.reset();
    }
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count() /
        static_cast<double>(n);

    lock.lock();
    busy_ = false;
    in_flight_ = 0;
    if (generation == generation_) {
      if (error.empty()) {
        for (std::size_t i = 0; i < n; ++i) results_.push_back(std::move(profiles[i]));
        last_scan_ms_ = ms;
      } else {
        error_ = error;
        queue_.clear();
      }
    }
    idle_.notify_all();
  }
  busy_ = false;
  idle_.notify_all();
  lock.unlock();
  // The source (and its OSMesa context) goes with this thread.
  source.reset();
}

}  // namespace vts::viewer
