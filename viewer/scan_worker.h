#pragma once
// vts-view's sensor thread: owns the profile source and scans the poses the
// viewer submits, off the window's thread. The raster source's OSMesa context
// then lives on its own thread, so the window's GLX context never has to be
// released for a scan, and scans overlap drawing.
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "sensor/mesh.h"
#include "sensor/pose.h"
#include "sensor/profile.h"
#include "sensor/scanner.h"

namespace vts::viewer {

enum class SourceKind { Raster, Reference };

class ScanWorker {
 public:
  struct Request {
    Pose world_from_sensor = Pose::Identity();
    double time_s = 0.0;
    std::int64_t index = 0;
  };

  ScanWorker();
  ~ScanWorker();  // finishes the scan in progress, drops the rest, joins
  ScanWorker(const ScanWorker&) = delete;
  ScanWorker& operator=(const ScanWorker&) = delete;

  // Scanner, world mesh and source for the scans submitted from now on; the
  // source is built on the worker thread at the next scan. Requests and
  // results from before are dropped.
  void configure(const ScannerDesc& desc, const Mesh& mesh_world, SourceKind kind);
  // Queues scans; they are done in order.
  void submit(const std::vector<Request>& requests);
  // Finished ideal profiles (pose, time and index set), in request order.
  std::vector<Profile> take_results();
  // Submitted scans not yet taken by take_results().
  std::size_t pending() const;
  // Blocks until every submitted scan is finished (or failed).
  void wait_idle();
  // The last failure (source creation or scan), once; empty if none.
  std::string take_error();
  // Wall time of the last batch per profile, ms.
  double last_scan_ms() const;

 private:
  void run();

  mutable std::mutex mutex_;
  std::condition_variable wake_, idle_;
  bool stop_ = false;
  bool busy_ = false;
  std::size_t in_flight_ = 0;  // scans of the batch being done

  // Guarded by mutex_.
  std::uint64_t generation_ = 0;
  ScannerDesc desc_;
  std::shared_ptr<const Mesh> mesh_;
  SourceKind kind_ = SourceKind::Raster;
  std::deque<Request> queue_;
  std::vector<Profile> results_;
  std::string error_;
  double last_scan_ms_ = 0.0;

  std::thread thread_;  // last: started once every member above exists
};

}  // namespace vts::viewer
