#pragma once
// A dataset spec (docs/DATASETS.md): what `vts dataset` draws its scenes
// from. A scene is one workpiece of a randomly chosen joint with random
// dimensions, seen by a randomly chosen sensor preset and material from a
// random pose, scanned along a short path; a shard is scenes_per_shard
// scenes, and every draw is a function of (seed, shard, scene) alone
// (dataset/scene.h).
#include <array>
#include <cstdint>
#include <filesystem>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>

#include "pipeline/scan_session.h"
#include "sensor/profile_exr.h"
#include "sensor/workpiece.h"

namespace vts {

// what() reads "FILE:LINE: FIELD: message" (line 1-based; 0 when the whole
// file is meant), like a scene file's SceneError.
struct DatasetSpecError : std::runtime_error {
  DatasetSpecError(const std::string& file, int line, const std::string& field, const std::string& message);
  std::string file, field;
  int line = 0;
};

// A closed interval drawn from uniformly; min == max is a fixed value.
struct Range {
  double min = 0.0, max = 0.0;
  bool operator==(const Range&) const = default;
};

// The joints a spec may draw: every joint the tracker reads (not the plate).
inline constexpr JointType kDatasetJoints[] = {JointType::Fillet,  JointType::Corner, JointType::Lap,
                                               JointType::Butt,    JointType::VGroove, JointType::Bevel,
                                               JointType::UGroove, JointType::JGroove};

// One joint type: how often it is drawn, and a range for each of its
// dimensions (unset ones: the joint's default_params, fixed).
struct JointDraw {
  JointType type = JointType::Fillet;
  double weight = 1.0;                                           // relative; 0: never drawn
  std::array<Range, std::size(kJointParamNumbers)> numbers{};    // in kJointParamNumbers' order
  Range passes;                                                  // integers (grooves: beads laid)
  bool operator==(const JointDraw&) const = default;
};

// One sensor preset (sensor/presets.h) and the standoffs it is used at: the
// distance from the laser to the aim point on the seam along the optical
// axis (before the travel angle leans it).
struct SensorDraw {
  std::string preset;
  double weight = 1.0;
  Range standoff_mm;  // default: the middle of min_range_mm .. min(max_range_mm, 3 min_range_mm)
  bool operator==(const SensorDraw&) const = default;
};

struct MaterialDraw {
  std::string name;  // a material preset (sensor/presets.h)
  double weight = 1.0;
  bool operator==(const MaterialDraw&) const = default;
};

// How the sensor looks at the seam (docs/DATASETS.md, "View").
struct ViewDraw {
  Range tilt_deg;    // the view turned about the seam (work angle); the laser plane stays square to it
  Range roll_deg;    // the sensor turned about its optical axis: the laser line crosses the seam obliquely
  Range travel_deg;  // the sensor leaning along the seam (lead + / lag -), about its laser line
  Range offset_mm;   // the aim point moved across the seam, perpendicular to the view
  bool operator==(const ViewDraw&) const = default;
};

inline constexpr int kMaxShards = 1'000'000;
inline constexpr int kMaxScenesPerShard = 100'000;
inline constexpr int kMaxProfilesPerScene = 100'000;

struct DatasetSpec {
  std::uint64_t seed = 0;
  int shards = 1;
  int scenes_per_shard = 1;
  int profiles_per_scene = 1;
  double step_mm = 0.5;  // path step along the seam between a scene's profiles
  SourceKind source = SourceKind::Raster;
  bool ideal = false;    // true: the error model off (ideal geometric profiles)
  ExrCompression compression = ExrCompression::Zip;  // the scenes' EXRs (every method lossless)
  // In kDatasetJoints' order, sensor_preset_names()' and material_names()'
  // order: the order of the draws, whatever the order in the file.
  std::vector<JointDraw> joints;
  std::vector<SensorDraw> sensors;
  std::vector<MaterialDraw> materials;
  ViewDraw view;
  bool operator==(const DatasetSpec&) const = default;
};

// Reads a spec; every error is a DatasetSpecError naming the file, line,
// field and value: YAML syntax, an unknown or duplicate key, a wrong type,
// min > max, an unknown joint, preset or material, counts out of range, all
// weights zero, and a joint whose ranges give (almost) no valid workpiece
// (validate(), or a path that leaves the seam) in trial draws.
DatasetSpec parse_dataset_spec(const std::string& yaml_text, const std::string& file_name);
DatasetSpec load_dataset_spec(const std::filesystem::path& path);

// The canonical form: every field written, joints, sensors and materials in
// the fixed order, numbers in their shortest exact form; what a manifest
// stores. parse_dataset_spec(dataset_spec_to_yaml(s), f) == s.
std::string dataset_spec_to_yaml(const DatasetSpec& spec);

// The profiles a spec makes: shards x scenes_per_shard x profiles_per_scene.
int shard_count(const DatasetSpec& spec);
std::int64_t profiles_per_shard(const DatasetSpec& spec);

}  // namespace vts
