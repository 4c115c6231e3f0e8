#pragma once
// The paper's dynamic experiment (docs/SIM.md) as one call: the box cell
// displaced from its nominal pose, the virtual sensor (or a recording of
// one) behind the sensor interface, the master welding both seams, and the
// tracking error against the true seams; with its outputs as text and
// figures. `vts sim` and `vts-view --sim` run it.
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "pipeline/scan_session.h"
#include "plot/plot.h"
#include "robot/arm.h"
#include "sensor/cell.h"
#include "sensor/profile.h"
#include "sensor/profile_exr.h"
#include "sensor/scanner.h"
#include "sensor/sim_cell.h"
#include "sensor/virtual_sensor.h"
#include "tracker/master.h"
#include "trackio/result_json.h"

namespace vts {

inline constexpr double kDefaultSimSpeedMmS = 10.0;

struct SimSpec {
  SimCellParams cell;      // the box and its displacement (cell.seed); standoff_mm for the scanner
  ScannerDesc scanner;     // the sensor; its mount (tool_from_laser) comes from the cell
  double speed_mm_s = kDefaultSimSpeedMmS;  // weld and search speed
  SourceKind source = SourceKind::Raster;
  std::uint64_t seed = 1;  // the error model's draws
  // Not empty: the master runs on this recording (the profiles.exr of an
  // earlier run) instead of the virtual sensor, at the recording's rate.
  std::filesystem::path replay;
  // The robot (robot::make_robot: "perfect" or an arm preset) and the seed
  // of the arm's absolute-accuracy errors (0: none). An arm moves between
  // poses at kArmMoveSpeedMmS and settles kArmSettleS.
  std::string robot = "perfect";
  std::uint64_t robot_seed = 0;
  tracker::MasterParams::Weave weave;
  // The program's first search margin (mm); empty: enough for the cell's
  // largest displacement (sim_master_params).
  std::optional<double> search_margin_mm;
  // Also run the same program open loop (no sensor) and report its errors.
  bool open_loop = true;
};
inline constexpr double kArmMoveSpeedMmS = 100.0;
inline constexpr double kArmSettleS = 0.3;

struct SimRun {
  SimCell cell;
  ScannerDesc scanner;      // as run: the cell's mount, the recording's rate on a replay
  std::string source_name;  // "raster", "reference" or "replay"
  tracker::MasterResult result;
  std::vector<SeamMetrics> metrics;  // per seam
  std::int64_t profiles = 0;         // taken by the sensor
  std::string robot;                 // its name
  std::string robot_fault;           // why the robot stopped; empty if it did not
  std::vector<Pose> actual_tcp;      // where the TCP really was at each of result.samples
  // An arm: as built, where it stands, its torch, and its joints at each of
  // result.samples (for drawing it); empty for a perfect robot.
  struct ArmTrace {
    robot::ArmModel as_built;
    Pose world_from_base = Pose::Identity();
    Pose flange_from_tool = Pose::Identity();
    std::vector<robot::Joints> joints;
  };
  std::optional<ArmTrace> arm;
  // The same program open loop: its samples, the TCP, the metrics and a fault.
  tracker::MasterResult open_loop;
  std::vector<Pose> open_loop_tcp;
  std::vector<SeamMetrics> open_loop_metrics;
  std::string open_loop_fault;

  // Both seams welded to their ends without a failure.
  bool completed() const;
  double sim_time_s() const;
  double offset_mm() const;     // actual workpiece pose from the nominal one
  double rotation_deg() const;
};

// The experiment's set-up without its master: the cell, the sensor unit
// (tracker + sequence) over the virtual sensor or the recording, and the
// master's parameters. run_sim and `vts serve` (server/host.h) build it
// alike. `record` sees every measured profile the virtual sensor takes (not
// on a replay). Throws std::invalid_argument ("scanner: ...") for an unusable
// scanner, ExrError for a bad recording, and as make_source.
struct SimRig {
  SimRun run;  // cell, scanner and source_name set; no result yet
  std::unique_ptr<ProfileSource> source;  // empty on a replay
  std::unique_ptr<tracker::SensorUnit> sensor;
  VirtualProfileStream* head = nullptr;  // the virtual sensor inside `sensor` (null on a replay)
  tracker::MasterParams master;
};
SimRig make_sim_rig(const SimSpec& spec, const std::function<void(const Profile&)>& record = {});

// A cell of `vts cells` or a scene file under the robot, as `vts serve`
// hosts it: the cell's scanner mounted on the torch as in the box cell (the
// laser plane kCellLookaheadMm ahead of the TCP along tool x, the laser's
// origin back along the torch axis by the cell path's standoff: the
// distance from its first pose to the seam), and the sensor unit set for
// the joint of the cell's first workpiece that has one. Throws
// std::invalid_argument when no workpiece has a joint the tracker knows, as
// make_source otherwise.
inline constexpr double kCellLookaheadMm = 50.0;
struct CellRig {
  Cell cell;
  int workpiece = 0;      // the tracked one, index into cell.workpieces
  ScannerDesc scanner;    // the cell's, with tool_from_laser set
  double standoff_mm = 0.0;
  std::string source_name;
  std::unique_ptr<ProfileSource> source;
  std::unique_ptr<tracker::SensorUnit> sensor;
};
CellRig make_cell_rig(const Cell& cell, SourceKind source, std::uint64_t seed);

// Runs the experiment (make_sim_rig, the master, the evaluation); throws as
// make_sim_rig.
SimRun run_sim(const SimSpec& spec, const std::function<void(const Profile&)>& record = {});

// timeseries.csv (docs/SIM.md): time, torch pose, true seam point, errors.
std::string sim_timeseries_csv(const SimRun& run);
// tracking_error.png: lateral and vertical error along each seam.
plot::Canvas sim_error_figure(const SimRun& run);
// One seam's metrics as `vts sim --json` prints them.
trackio::Json seam_metrics_json(const SeamMetrics& m, int index);
// The run's summary as `vts sim --json` prints it (without out_dir): the
// set-up, the robot, the times (wall_time_s: the whole command's, the
// simulation's), `completed`, and per seam the metrics with the open
// loop's beside them ("open_loop").
trackio::Json sim_summary_json(const SimSpec& spec, const SimRun& run, double wall_time_s, double sim_wall_time_s);

// Profiles spooled to a scratch file as they are taken (an EXR needs its row
// count up front), then written as one EXR; the scratch file goes with it.
class ProfileSpool {
 public:
  explicit ProfileSpool(const std::filesystem::path& path);
  ~ProfileSpool();
  ProfileSpool(const ProfileSpool&) = delete;
  ProfileSpool& operator=(const ProfileSpool&) = delete;
  void add(const Profile& p);
  int count() const { return count_; }
  // info.profiles is set to count().
  void write_exr(const std::filesystem::path& exr, ProfileFileInfo info);

 private:
  std::filesystem::path path_;
  std::ofstream out_;
  int count_ = 0;
  int points_ = 0;
};

}  // namespace vts
