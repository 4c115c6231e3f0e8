#include "viewer/scan_worker.h"

#include <chrono>
#include <exception>
#include <span>
#include <utility>


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

void ScanWorker::configure(const ScannerDesc& desc, const Mesh& mesh_world, SourceKind kind, std::uint64_t seed) {
  {
    std::lock_guard lock(mutex_);
    ++generation_;
    desc_ = desc;
    mesh_ = std::make_shared<const Mesh>(mesh_world);
    kind_ = kind;
    seed_ = seed;
    queue_.clear();
    results_ = {};
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

ScanWorker::Results ScanWorker::take_results() {
  std::lock_guard lock(mutex_);
  return std::exchange(results_, {});
}

std::size_t ScanWorker::pending() const {
  std::lock_guard lock(mutex_);
  return queue_.size() + results_.output.size() + in_flight_;
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
  std::unique_ptr<ScanSession> session;
  std::uint64_t session_generation = 0;
  std::vector<Request> batch;
  ScanResults scanned;

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
    const std::uint64_t seed = seed_;
    busy_ = true;
    in_flight_ = n;
    lock.unlock();

    std::string error;
    const auto t0 = std::chrono::steady_clock::now();
    try {
      if (!session || session_generation != generation) {
        session.reset();  // one set of OSMesa contexts at a time
        session = std::make_unique<ScanSession>(desc, *mesh, kind, false, seed);
        session->keep_images(session->image_mode());
        session_generation = generation;
      }
      session->scan(batch, scanned);
    } catch (const std::exception& e) {
      error = e.what();
      session.reset();
    }
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count() /
        static_cast<double>(n);

    lock.lock();
    busy_ = false;
    in_flight_ = 0;
    if (generation == generation_) {
      if (error.empty()) {
        const std::span<const Profile> output = scanned.output();
        results_.output.insert(results_.output.end(), output.begin(), output.end());
        results_.ideal.insert(results_.ideal.end(), scanned.ideal.begin(), scanned.ideal.end());
        if (!scanned.images.empty()) results_.image = std::move(scanned.images.back());
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
  // The session (and its OSMesa contexts) goes with this thread.
  session.reset();
}

}  // namespace vts::viewer
