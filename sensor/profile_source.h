#pragma once
// The one interface over the raster emulator (render/) and the ray-cast
// reference (sensor/), so exporter, viewer, tracker and tests can take either.
#include <span>
#include <stdexcept>
#include <string_view>

#include "sensor/profile.h"
#include "sensor/scanner.h"

namespace vts {

class ProfileSource {
 public:
  virtual ~ProfileSource() = default;
  // Scans one profile with the laser at world_from_sensor. `out` is resized to
  // scanner().points; reusing the same Profile avoids allocation.
  virtual void scan(const Pose& world_from_sensor, Profile& out) = 0;
  // Scans poses.size() profiles; out.size() must equal poses.size(). Sources
  // that can batch override this.
  virtual void scan_batch(std::span<const Pose> poses, std::span<Profile> out) {
    for (std::size_t i = 0; i < poses.size(); ++i) scan(poses[i], out[i]);
  }
  // Sources built with a moving part (make_reference_source's `moving`):
  // puts it where the rigid `motion` (world) takes its mesh as given, for
  // the scans that follow. Others throw std::logic_error.
  virtual void move_part(const Pose& /*motion*/) {
    throw std::logic_error("this profile source has no moving part");
  }
  virtual const ScannerDesc& scanner() const = 0;
  virtual std::string_view kind() const = 0;  // "raster" or "reference"
};

}  // namespace vts
