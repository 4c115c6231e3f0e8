#include "dataset/scene.h"

#include <cmath>
#include <cstdio>
#include <numbers>
#include <sstream>
#include <string_view>

#include "sensor/presets.h"
#include "sensor/yaml_io.h"

namespace vts {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
constexpr std::uint64_t kGolden = 0x9e3779b97f4a7c15ULL;

// SplitMix64's finaliser: a bijective 64-bit mix with full avalanche.
constexpr std::uint64_t mix(std::uint64_t z) {
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

// FNV-1a: a quantity's name as part of its draw's key.
constexpr std::uint64_t name_key(std::string_view name) {
  std::uint64_t h = 0xcbf29ce484222325ULL;
  for (const char c : name) h = (h ^ static_cast<unsigned char>(c)) * 0x100000001b3ULL;
  return h;
}

// Draws keyed by a path of integers (seed, shard, scene, attempt) and each
// quantity's name: counter-based, no state.
class Draws {
 public:
  explicit Draws(std::uint64_t key) : key_(key) {}
  static Draws root(std::uint64_t seed, std::string_view domain) { return Draws(mix(seed ^ name_key(domain))); }
  Draws child(std::uint64_t i) const { return Draws(mix(key_ ^ mix(kGolden * (i + 1)))); }

  std::uint64_t bits(std::string_view what) const { return mix(key_ ^ name_key(what)); }
  // [0, 1), 53 bits.
  double unit(std::string_view what) const { return static_cast<double>(bits(what) >> 11) * 0x1.0p-53; }
  double in(const Range& r, std::string_view what) const {
    return r.min == r.max ? r.min : r.min + unit(what) * (r.max - r.min);
  }
  // An integer of [min, max] (the range's ends are integers).
  int integer(const Range& r, std::string_view what) const {
    const double span = r.max - r.min + 1.0;
    return static_cast<int>(r.min + std::min(r.max - r.min, std::floor(unit(what) * span)));
  }

 private:
  std::uint64_t key_;
};

// The item a draw u in [0, 1) falls on, by weight (zero weights never).
template <class T>
const T& pick(const std::vector<T>& items, double u) {
  double total = 0.0;
  for (const T& t : items) total += t.weight;
  double x = u * total;
  const T* last = nullptr;
  for (const T& t : items) {
    if (t.weight <= 0.0) continue;
    if (x < t.weight) return t;
    x -= t.weight;
    last = &t;
  }
  return *last;  // rounding at the top end
}

std::string fmt(double v) { return yaml_io::num(v); }

// One attempt at the scene's dimensions and view: fills `out` and returns
// "" when they are usable, else why not.
std::string try_scene(const DatasetSpec& spec, const JointDraw& jd, const SensorDraw& sd, const MaterialDraw& md,
                      const Draws& d, DatasetScene& out) {
  JointParams p = default_params(jd.type);
  for (std::size_t i = 0; i < std::size(kJointParamNumbers); ++i)
    p.*kJointParamNumbers[i].member = d.in(jd.numbers[i], kJointParamNumbers[i].key);
  p.passes = d.integer(jd.passes, "passes");
  if (std::string why = validate(jd.type, p); !why.empty()) return why;

  out.joint = jd.type;
  out.params = p;
  out.preset = sd.preset;
  out.material = md.name;
  out.standoff_mm = d.in(sd.standoff_mm, "standoff_mm");
  out.tilt_deg = d.in(spec.view.tilt_deg, "tilt_deg");
  out.roll_deg = d.in(spec.view.roll_deg, "roll_deg");
  out.travel_deg = d.in(spec.view.travel_deg, "travel_deg");
  out.offset_mm = d.in(spec.view.offset_mm, "offset_mm");

  Cell& cell = out.cell;
  cell.name = scene_stem(out.shard, out.scene);
  cell.workpieces = {build_workpiece(jd.type, p)};
  const Workpiece& w = cell.workpieces.front();
  cell.scanner = *sensor_preset(sd.preset);
  apply_material(cell.scanner, md.name);
  cell.scanner.ideal = spec.ideal;

  // The aim point: the track point (the root; a groove's B3) midway along
  // the path, moved across the view; the view turned about the seam; then
  // the sensor leaning along the seam about its laser line and turned about
  // its optical axis.
  const Vec2 aim = is_groove(jd.type) ? w.truth.track_yz : w.truth.root_yz;
  const Vec3 view = Eigen::AngleAxisd(out.tilt_deg * kDeg, Vec3::UnitX()) * default_view_direction(w);
  const Vec3 across = view.cross(Vec3::UnitX()).normalized();
  const double run = (spec.profiles_per_scene - 1) * spec.step_mm;
  const Vec3 target = Vec3(0.5 * (p.length_mm - run), aim.x(), aim.y()) + out.offset_mm * across;
  Pose start = sensor_pose_looking_at(target, view, out.standoff_mm, Vec3::UnitX());
  start.rotate(Eigen::AngleAxisd(out.travel_deg * kDeg, Vec3::UnitY()));
  start.rotate(Eigen::AngleAxisd(out.roll_deg * kDeg, Vec3::UnitZ()));
  cell.path.start = start;
  cell.path.direction = Vec3::UnitX();
  cell.path.step_mm = spec.step_mm;
  cell.path.profiles = spec.profiles_per_scene;

  for (const int i : {0, spec.profiles_per_scene - 1}) {
    const Pose pose = cell.path.pose_at(i);
    const Vec2 cut = w.in_sensor_frame(pose, aim);
    const double x = (pose * Vec3(0.0, cut.x(), cut.y())).x();
    if (!(x >= kSeamMarginMm && x <= p.length_mm - kSeamMarginMm))
      return "the laser plane cuts the seam at x = " + fmt(x) + " mm, not " + fmt(kSeamMarginMm) +
             " mm or more from both ends (length_mm = " + fmt(p.length_mm) + ", path " + fmt(run) +
             " mm, standoff_mm = " + fmt(out.standoff_mm) + ", travel_deg = " + fmt(out.travel_deg) +
             ", roll_deg = " + fmt(out.roll_deg) + ")";
  }
  return {};
}

}  // namespace

std::string shard_stem(int shard) {
  char b[32];
  std::snprintf(b, sizeof b, "shard-%05d", shard);
  return b;
}

std::string scene_stem(int shard, int scene) {
  char b[48];
  std::snprintf(b, sizeof b, "-scene-%04d", scene);
  return shard_stem(shard) + b;
}

DatasetScene draw_scene(const DatasetSpec& spec, int shard, int scene) {
  const Draws d = Draws::root(spec.seed, "vts dataset").child(static_cast<std::uint64_t>(shard)).child(
      static_cast<std::uint64_t>(scene));
  const JointDraw& jd = pick(spec.joints, d.unit("joint"));
  const SensorDraw& sd = pick(spec.sensors, d.unit("sensor"));
  const MaterialDraw& md = pick(spec.materials, d.unit("material"));
  DatasetScene s;
  s.shard = shard;
  s.scene = scene;
  s.noise_seed = d.bits("noise_seed");
  std::string why;
  for (int a = 0; a < kMaxSceneDraws; ++a) {
    why = try_scene(spec, jd, sd, md, d.child(static_cast<std::uint64_t>(a)), s);
    if (why.empty()) {
      s.draws = a + 1;
      return s;
    }
  }
  throw DatasetDrawError(scene_stem(shard, scene) + ": no valid " + std::string(to_string(jd.type)) + " in " +
                         std::to_string(kMaxSceneDraws) + " draws from joints." + std::string(to_string(jd.type)) +
                         " (the last: " + why + ")");
}

ProbeResult probe_joint(const DatasetSpec& spec, std::size_t joint, int tries) {
  const Draws d = Draws::root(spec.seed, "vts dataset probe").child(joint);
  ProbeResult r;
  DatasetScene s;
  for (int t = 0; t < tries; ++t) {
    const Draws dt = d.child(static_cast<std::uint64_t>(t));
    const std::string why = try_scene(spec, spec.joints[joint], pick(spec.sensors, dt.unit("sensor")),
                                      pick(spec.materials, dt.unit("material")), dt, s);
    if (why.empty()) ++r.valid;
    else r.last_refusal = why;
  }
  return r;
}

}  // namespace vts
