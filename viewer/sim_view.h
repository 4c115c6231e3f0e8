#pragma once
// vts-view --sim: the run of `vts sim --source reference` for the same seed,
// sensor and material (docs/SIM.md; pipeline/sim_run.h), computed up front;
// the viewer then drives the torch through the master's poses on its own
// clock and scans live.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "sensor/cell.h"
#include "tracker/master.h"

namespace vts::viewer {

struct SimView {
  // The box cell shown as two workpieces, one per seam, so that both seams
  // are drawn; the scanner as the run used it.
  std::shared_ptr<const Cell> cell;
  std::vector<tracker::MasterSample> samples;  // the master's cycles
  double dt_s = 0.05;                          // one cycle, s
  std::string summary;                         // one status line
};

// `seed` seeds the workpiece's displacement and the error model, as in `vts
// sim`; sensor and material are preset names (empty: the defaults).
SimView run_sim_for_view(std::uint64_t seed, const std::string& sensor, const std::string& material, bool ideal);

}  // namespace vts::viewer
