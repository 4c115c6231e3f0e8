#pragma once
// vts-view's sensor thread: owns a scan session (pipeline/scan_session.h:
// the profile source and the error model) and scans the poses the viewer
// submits, off the window's thread. The raster source's OSMesa contexts are
// then never made current on the window's thread, so its GLX context never
// has to be released for a scan, and scans overlap drawing.
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "pipeline/scan_session.h"
#include "sensor/camera_image.h"
#include "sensor/mesh.h"
#include "sensor/profile.h"
#include "sensor/scanner.h"

namespace vts::viewer {

class ScanWorker {
 public:
  using Request = ScanRequest;
  // Finished scans in request order: what the sensor gives (the error
  // model's output, or the ideal profile when the scanner is ideal) and the
  // ideal geometric profile; in the camera-image mode (desc.camera_image)
  // also the image the last of them was read from, labelled.
  struct Results {
    std::vector<Profile> output, ideal;
    std::optional<CameraImage> image;
  };

  ScanWorker();
  ~ScanWorker();  // finishes the scan in progress, drops the rest, joins
  ScanWorker(const ScanWorker&) = delete;
  ScanWorker& operator=(const ScanWorker&) = delete;

  // Scanner, world mesh, source and error-model seed for the scans submitted
  // from now on; the session is built on the worker thread at the next scan.
  // Requests and results from before are dropped.
  void configure(const ScannerDesc& desc, const Mesh& mesh_world, SourceKind kind, std::uint64_t seed);
  // Queues scans; they are done in order.
  void submit(const std::vector<Request>& requests);
  // Finished scans (pose, time and index set) since the last call.
  Results take_results();
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
  std::uint64_t seed_ = 0;
  std::deque<Request> queue_;
  Results results_;
  std::string error_;
  double last_scan_ms_ = 0.0;

  std::thread thread_;  // last: started once every member above exists
};

}  // namespace vts::viewer
