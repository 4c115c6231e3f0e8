#pragma once
// vts-view --sim [--scenario NAME]: the run of `vts sim --source reference`
// for the same seed, sensor and material, or of a scenario (docs/SIM.md;
// pipeline/sim_run.h, pipeline/scenario.h), computed up front; the viewer
// then drives the torch through the TCP's poses on its own clock, draws the
// arm when the run has one, and scans live.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "sensor/cell.h"
#include "tracker/master.h"
#include "viewer/app.h"

namespace vts::viewer {

struct SimView {
  // The box cell as the run built it (a mesh workpiece: a bowed wall and
  // tack welds included) and one line-only workpiece per seam; the scanner
  // as the run used it.
  std::shared_ptr<const Cell> cell;
  std::vector<tracker::MasterSample> samples;  // the master's cycles
  std::vector<Pose> tcp;                       // where the TCP really was at each
  std::vector<std::vector<Vec3>> seam_paths;   // curved seams' truth
  // The arm's links (empty for a perfect robot) and their poses per sample.
  std::vector<App::Attachment> arm_links;
  std::vector<std::vector<Pose>> arm_poses;
  double dt_s = 0.05;   // one cycle, s
  std::string summary;  // one status line
  std::string label = "sim-box";
};

// `seed` seeds the workpiece's displacement and the error model, as in `vts
// sim`; sensor and material are preset names (empty: the defaults). With a
// scenario (a built-in name or a file), its set-up instead. Throws
// std::runtime_error for an unknown scenario or a bad file.
SimView run_sim_for_view(std::uint64_t seed, const std::string& sensor, const std::string& material, bool ideal,
                         const std::string& scenario = {});

// The index of the sample shown at simulated time t.
std::size_t sample_at(const SimView& view, double t);

}  // namespace vts::viewer
