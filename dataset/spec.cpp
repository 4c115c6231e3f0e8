#include "dataset/spec.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <sstream>
#include <system_error>

#include "dataset/scene.h"
#include "sensor/presets.h"
#include "sensor/yaml_io.h"

namespace vts {
namespace {

using yaml_io::Field;
using yaml_io::num;

// Trial draws per joint at parse time, and how many must give a usable
// scene: with 5 % valid, a scene fails its kMaxSceneDraws draws with
// probability 0.95^1000 (about 1e-22).
constexpr int kProbeDraws = 200;
constexpr int kProbeValid = 10;

constexpr double kMaxTiltDeg = 60.0, kMaxRollDeg = 45.0, kMaxTravelDeg = 45.0;

std::string range_text(const Range& r) {
  return r.min == r.max ? num(r.min) : "[" + num(r.min) + ", " + num(r.max) + "]";
}

// The default standoff: the middle of the near part of the depth of field,
// min_range .. min(max_range, 3 min_range): 80 mm for mspot and
// lps-2048-short, 200 mm for lps-1280-mid.
Range default_standoff(const ScannerDesc& d) {
  const double mid = 0.5 * (d.min_range_mm + std::min(d.max_range_mm, 3.0 * d.min_range_mm));
  return {mid, mid};
}

std::vector<std::string> joint_names() {
  std::vector<std::string> names;
  for (const JointType t : kDatasetJoints) names.emplace_back(to_string(t));
  return names;
}

class SpecParser : public yaml_io::Reader {
 public:
  using Reader::Reader;

  DatasetSpec spec(const YAML::Node& root) const {
    if (root.IsNull()) fail(1, "", "empty spec (expected a map with shards, scenes_per_shard, profiles_per_scene)");
    const Map m(*this, Field{root, "", 1},
                {"seed", "shards", "scenes_per_shard", "profiles_per_scene", "step_mm", "source", "ideal", "compression",
                 "joints", "sensors", "materials", "view"});
    DatasetSpec s;
    if (auto x = m.get("seed")) s.seed = seed(*x);
    s.shards = count(m.require("shards"), "shards", kMaxShards);
    s.scenes_per_shard = count(m.require("scenes_per_shard"), "scenes_per_shard", kMaxScenesPerShard);
    s.profiles_per_scene = count(m.require("profiles_per_scene"), "profiles_per_scene", kMaxProfilesPerScene);
    if (auto x = m.get("step_mm")) {
      s.step_mm = number(*x);
      if (s.step_mm <= 0.0) fail(*x, "step_mm = " + num(s.step_mm) + ": must be > 0");
    }
    if (auto x = m.get("source")) {
      const std::string name = string(*x);
      if (name == "raster") s.source = SourceKind::Raster;
      else if (name == "reference") s.source = SourceKind::Reference;
      else fail(*x, "source = '" + name + "': expected raster or reference");
    }
    if (auto x = m.get("ideal")) s.ideal = boolean(*x);
    if (auto x = m.get("compression")) {
      const std::string name = string(*x);
      const auto method = exr_compression_from_string(name);
      if (!method) fail(*x, "compression = '" + name + "': expected one of " + join_names(exr_compression_names()));
      s.compression = *method;
    }
    std::vector<int> joint_lines(std::size(kDatasetJoints), m.self().line());
    const auto jf = m.get("joints");
    if (jf) joint_lines.assign(joint_lines.size(), jf->line());
    s.joints = joints(jf, joint_lines);
    s.sensors = sensors(m.get("sensors"));
    s.materials = materials(m.get("materials"));
    if (auto x = m.get("view")) s.view = view(*x);
    for (std::size_t j = 0; j < s.joints.size(); ++j) {
      if (s.joints[j].weight <= 0.0) continue;
      const ProbeResult r = probe_joint(s, j, kProbeDraws);
      if (r.valid < kProbeValid)
        fail(joint_lines[j], "joints." + std::string(to_string(s.joints[j].type)),
             "only " + std::to_string(r.valid) + " of " + std::to_string(kProbeDraws) +
                 " trial draws give a usable scene; narrow the ranges (the last refused: " + r.last_refusal + ")");
    }
    return s;
  }

 private:
  void raise(int line, const std::string& field, const std::string& msg) const override {
    throw DatasetSpecError(file_, line, field, msg);
  }

  std::uint64_t seed(const Field& f) const {
    std::string s = scalar_text(f, "an unsigned integer");
    if (!s.empty() && s.front() == '+') s.erase(0, 1);
    std::uint64_t v = 0;
    const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
    if (r.ec != std::errc() || r.ptr != s.data() + s.size())
      fail(f, "seed = '" + f.node.Scalar() + "': expected an integer 0 .. 18446744073709551615");
    return v;
  }

  int count(const Field& f, const char* key, int max) const {
    const long long v = integer(f);
    if (v < 1 || v > max)
      fail(f, std::string(key) + " = " + std::to_string(v) + ": must be between 1 and " + std::to_string(max));
    return static_cast<int>(v);
  }

  double weight(const Field& f) const {
    const double w = number(f);
    if (w < 0.0) fail(f, "weight = " + num(w) + ": must be >= 0");
    return w;
  }

  // A number (fixed) or [min, max].
  Range range(const Field& f) const {
    if (!f.node.IsSequence()) {
      const double v = number(f);
      return {v, v};
    }
    if (f.node.size() != 2) fail(f, "expected a number or [min, max], got " + yaml_io::describe(f.node));
    const Range r{number(Field{f.node[0], f.path + "[0]", 0, f.line()}),
                  number(Field{f.node[1], f.path + "[1]", 0, f.line()})};
    if (r.min > r.max) fail(f, range_text(r) + ": min must not exceed max");
    return r;
  }

  Range bounded(const Field& f, double lo, double hi, const char* unit) const {
    const Range r = range(f);
    if (r.min < lo || r.max > hi)
      fail(f, range_text(r) + ": must lie within [" + num(lo) + ", " + num(hi) + "]" + unit);
    return r;
  }

  Range positive(const Field& f) const {
    const Range r = range(f);
    if (r.min <= 0.0) fail(f, range_text(r) + ": must be > 0");
    return r;
  }

  // The map's keys before Map checks them, so an unknown name reads as one.
  void known_names(const Field& f, const std::vector<std::string>& names, const char* what, const char* see) const {
    if (!f.node.IsMap()) return;
    for (const auto& kv : f.node) {
      if (!kv.first.IsScalar()) continue;
      const std::string n = kv.first.Scalar();
      if (std::find(names.begin(), names.end(), n) == names.end())
        fail(kv.first.Mark().line + 1, f.path + "." + n,
             "unknown " + std::string(what) + " '" + n + "' (expected one of: " + yaml_io::join(names) + see + ")");
    }
  }

  // A list of names, or a map name -> entry; `each` reads one entry (its
  // field, or nullopt for a bare name in a list) into the slot for the name.
  template <class Each>
  void entries(const Field& f, const std::vector<std::string>& names, const char* what, const char* see,
               Each each) const {
    if (f.node.IsSequence()) {
      std::vector<std::string> seen;
      for (std::size_t i = 0; i < f.node.size(); ++i) {
        const Field item{f.node[i], f.path + "[" + std::to_string(i) + "]", 0, f.line()};
        const std::string n = string(item);
        if (std::find(names.begin(), names.end(), n) == names.end())
          fail(item, "unknown " + std::string(what) + " '" + n + "' (expected one of: " + yaml_io::join(names) + see +
                         ")");
        if (std::find(seen.begin(), seen.end(), n) != seen.end()) fail(item, "'" + n + "' given twice");
        seen.push_back(n);
        each(n, std::optional<Field>{}, item.line());
      }
      return;
    }
    if (!f.node.IsMap()) fail(f, "expected a map or a list of names, got " + yaml_io::describe(f.node));
    known_names(f, names, what, see);
    const Map m(*this, f, names);
    for (const auto& [n, field] : m.entries()) each(n, std::optional<Field>(field), field.line());
  }

  template <class T>
  void require_weight(const Field& f, const std::vector<T>& items) const {
    double total = 0.0;
    for (const T& t : items) total += t.weight;
    if (!(total > 0.0)) fail(f, "every weight is 0: nothing to draw");
  }

  std::vector<JointDraw> joints(const std::optional<Field>& f, std::vector<int>& lines) const {
    std::vector<JointDraw> all;
    for (const JointType t : kDatasetJoints) {
      JointDraw d;
      d.type = t;
      const JointParams p = default_params(t);
      for (std::size_t i = 0; i < std::size(kJointParamNumbers); ++i) {
        const double v = p.*kJointParamNumbers[i].member;
        d.numbers[i] = {v, v};
      }
      d.passes = {double(p.passes), double(p.passes)};
      all.push_back(d);
    }
    if (!f) return all;
    for (JointDraw& d : all) d.weight = 0.0;  // only the joints listed
    entries(*f, joint_names(), "joint", "", [&](const std::string& name, const std::optional<Field>& e, int line) {
      const std::size_t j = static_cast<std::size_t>(
          std::find(std::begin(kDatasetJoints), std::end(kDatasetJoints), *joint_type_from_string(name)) -
          std::begin(kDatasetJoints));
      lines[j] = line;
      JointDraw& d = all[j];
      d.weight = 1.0;
      if (!e || e->node.IsNull()) return;
      if (!e->node.IsMap()) {
        d.weight = weight(*e);
        return;
      }
      std::vector<std::string> allowed = {"weight"};
      for (const auto& k : kJointParamNumbers) allowed.emplace_back(k.key);
      allowed.emplace_back("passes");
      const Map jm(*this, *e, allowed);
      if (auto x = jm.get("weight")) d.weight = weight(*x);
      for (std::size_t i = 0; i < std::size(kJointParamNumbers); ++i)
        if (auto x = jm.get(kJointParamNumbers[i].key)) d.numbers[i] = range(*x);
      if (auto x = jm.get("passes")) {
        d.passes = range(*x);
        if (d.passes.min != std::floor(d.passes.min) || d.passes.max != std::floor(d.passes.max))
          fail(*x, "passes = " + range_text(d.passes) + ": expected integers");
      }
    });
    require_weight(*f, all);
    return all;
  }

  std::vector<SensorDraw> sensors(const std::optional<Field>& f) const {
    std::vector<SensorDraw> all;
    for (const std::string& name : sensor_preset_names())
      all.push_back({name, 0.0, default_standoff(*sensor_preset(name))});
    if (!f) {
      all.front().weight = 1.0;  // mspot
      return all;
    }
    entries(*f, sensor_preset_names(), "sensor preset", "; see `vts sensors`",
            [&](const std::string& name, const std::optional<Field>& e, int) {
              SensorDraw& d = *std::find_if(all.begin(), all.end(), [&](const auto& s) { return s.preset == name; });
              d.weight = 1.0;
              if (!e || e->node.IsNull()) return;
              if (!e->node.IsMap()) {
                d.weight = weight(*e);
                return;
              }
              const Map sm(*this, *e, {"weight", "standoff_mm"});
              if (auto x = sm.get("weight")) d.weight = weight(*x);
              if (auto x = sm.get("standoff_mm")) d.standoff_mm = positive(*x);
            });
    require_weight(*f, all);
    return all;
  }

  std::vector<MaterialDraw> materials(const std::optional<Field>& f) const {
    std::vector<MaterialDraw> all;
    for (const std::string& name : material_names()) all.push_back({name, name == kDefaultMaterial ? 1.0 : 0.0});
    if (!f) return all;
    for (MaterialDraw& d : all) d.weight = 0.0;
    entries(*f, material_names(), "material", "; see `vts sensors`",
            [&](const std::string& name, const std::optional<Field>& e, int) {
              MaterialDraw& d = *std::find_if(all.begin(), all.end(), [&](const auto& m) { return m.name == name; });
              d.weight = !e || e->node.IsNull() ? 1.0 : weight(*e);
            });
    require_weight(*f, all);
    return all;
  }

  ViewDraw view(const Field& f) const {
    const Map m(*this, f, {"tilt_deg", "roll_deg", "travel_deg", "offset_mm"});
    ViewDraw v;
    if (auto x = m.get("tilt_deg")) v.tilt_deg = bounded(*x, -kMaxTiltDeg, kMaxTiltDeg, " deg");
    if (auto x = m.get("roll_deg")) v.roll_deg = bounded(*x, -kMaxRollDeg, kMaxRollDeg, " deg");
    if (auto x = m.get("travel_deg")) v.travel_deg = bounded(*x, -kMaxTravelDeg, kMaxTravelDeg, " deg");
    if (auto x = m.get("offset_mm")) v.offset_mm = range(*x);
    return v;
  }
};

}  // namespace

DatasetSpecError::DatasetSpecError(const std::string& file_, int line_, const std::string& field_,
                                   const std::string& message)
    : std::runtime_error(yaml_io::error_text(file_, line_, field_, message)), file(file_), field(field_), line(line_) {}

DatasetSpec parse_dataset_spec(const std::string& yaml_text, const std::string& file_name) {
  const SpecParser parser(file_name);
  const YAML::Node root = parser.load(yaml_text);
  try {
    return parser.spec(root);
  } catch (const YAML::Exception& e) {
    throw DatasetSpecError(file_name, e.mark.line + 1, "", std::string("YAML error: ") + e.what());
  }
}

DatasetSpec load_dataset_spec(const std::filesystem::path& path) {
  const SpecParser parser(path.string());
  return parse_dataset_spec(parser.read_file(path, "spec"), path.string());
}

std::string dataset_spec_to_yaml(const DatasetSpec& s) {
  std::ostringstream o;
  o << "# vts dataset spec (docs/DATASETS.md)\n";
  o << "seed: " << s.seed << "\n";
  o << "shards: " << s.shards << "\n";
  o << "scenes_per_shard: " << s.scenes_per_shard << "\n";
  o << "profiles_per_scene: " << s.profiles_per_scene << "\n";
  o << "step_mm: " << num(s.step_mm) << "\n";
  o << "source: " << to_string(s.source) << "\n";
  o << "ideal: " << (s.ideal ? "true" : "false") << "\n";
  // Only when not the default, so that a spec without it keeps its text (and hash).
  if (s.compression != ExrCompression::Zip) o << "compression: " << to_string(s.compression) << "\n";
  o << "joints:\n";
  for (const JointDraw& j : s.joints) {
    o << "  " << to_string(j.type) << ":\n";
    o << "    weight: " << num(j.weight) << "\n";
    for (std::size_t i = 0; i < std::size(kJointParamNumbers); ++i)
      o << "    " << kJointParamNumbers[i].key << ": " << range_text(j.numbers[i]) << "\n";
    o << "    passes: " << range_text(j.passes) << "\n";
  }
  o << "sensors:\n";
  for (const SensorDraw& d : s.sensors) {
    o << "  " << d.preset << ":\n";
    o << "    weight: " << num(d.weight) << "\n";
    o << "    standoff_mm: " << range_text(d.standoff_mm) << "\n";
  }
  o << "materials:\n";
  for (const MaterialDraw& m : s.materials) o << "  " << m.name << ": " << num(m.weight) << "\n";
  o << "view:\n";
  o << "  tilt_deg: " << range_text(s.view.tilt_deg) << "\n";
  o << "  roll_deg: " << range_text(s.view.roll_deg) << "\n";
  o << "  travel_deg: " << range_text(s.view.travel_deg) << "\n";
  o << "  offset_mm: " << range_text(s.view.offset_mm) << "\n";
  return o.str();
}

int shard_count(const DatasetSpec& spec) { return spec.shards; }

std::int64_t profiles_per_shard(const DatasetSpec& spec) {
  return static_cast<std::int64_t>(spec.scenes_per_shard) * spec.profiles_per_scene;
}

}  // namespace vts
