#pragma once
// One scene of a dataset, drawn from its spec (dataset/spec.h). Every draw is
// a hash of (spec.seed, shard, scene, attempt, the quantity's name) mapped to
// [0, 1) by hand (no std distribution: theirs are implementation-defined),
// so a scene is the same on every machine, worker and thread count, and a
// quantity added later does not move the others' draws.
//
// The joint type, the sensor preset, the material and the error model's seed
// are drawn once per scene; the dimensions and the view are drawn again
// (attempt 1, 2, ...) while validate() refuses the workpiece or the path
// leaves the seam, at most kMaxSceneDraws times.
#include <cstdint>
#include <stdexcept>
#include <string>

#include "dataset/spec.h"
#include "sensor/cell.h"

namespace vts {

inline constexpr int kMaxSceneDraws = 1000;
// The laser plane must cut the seam at least this far from the workpiece's
// ends at the path's first and last profile.
inline constexpr double kSeamMarginMm = 20.0;

struct DatasetScene {
  int shard = 0, scene = 0;
  JointType joint = JointType::Fillet;
  JointParams params;
  std::string preset, material;
  double standoff_mm = 0.0, tilt_deg = 0.0, roll_deg = 0.0, travel_deg = 0.0, offset_mm = 0.0;
  std::uint64_t noise_seed = 0;  // the error model's seed
  int draws = 1;                 // dimension draws it took (the refused ones redrawn)
  // The workpiece (joint frame = world), the scanner and the path: profile i
  // at path.pose_at(i). Named "shard-KKKKK-scene-JJJJ".
  Cell cell;
};

// No valid scene in kMaxSceneDraws draws: the message names the shard,
// scene, joint and the last refusal (the field and value).
struct DatasetDrawError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

DatasetScene draw_scene(const DatasetSpec& spec, int shard, int scene);

// Trial draws of spec.joints[joint] (its own key, not any scene's): how many
// of `tries` give a valid scene, and the last refusal. parse_dataset_spec
// refuses a joint with too few.
struct ProbeResult {
  int valid = 0;
  std::string last_refusal;
};
ProbeResult probe_joint(const DatasetSpec& spec, std::size_t joint, int tries);

// "shard-00003", "shard-00003-scene-0012"
std::string shard_stem(int shard);
std::string scene_stem(int shard, int scene);

}  // namespace vts
