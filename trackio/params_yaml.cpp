#include "trackio/params_yaml.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <charconv>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <vector>

namespace vts::trackio {
namespace {

namespace tk = vts::tracker;
constexpr double kInf = INFINITY;

// One line per parameter: key path, limits (numbers and integers), field. A
// new TrackerParams field the file should set is one more line here; its
// section and the "expected one of" lists follow from the paths.
#define VTS_PARAM(path, limit, member) \
  ParamField { path, limit, [](ParamsFile& f) -> FieldRef { return &f.member; } }
const ParamField kFields[] = {
    VTS_PARAM("joint", {}, joint),
    VTS_PARAM("surface_tol_mm", (Limit{0, kInf, true}), params.surface_tol_mm),
    VTS_PARAM("max_joint_width_mm", (Limit{0, kInf, true}), params.max_joint_width_mm),
    VTS_PARAM("square_edges", {}, params.square_edges),
    VTS_PARAM("hidden_face_deg", (Limit{0, 45}), params.hidden_face_deg),
    VTS_PARAM("segmentation.roi_first", (Limit{0, 4095}), params.segmentation.roi_first),
    VTS_PARAM("segmentation.roi_last", (Limit{-1, 4095}), params.segmentation.roi_last),
    VTS_PARAM("segmentation.ray_origin_yz", {}, params.segmentation.ray_origin_yz),
    VTS_PARAM("segmentation.outliers.enabled", {}, params.segmentation.outliers.enabled),
    VTS_PARAM("segmentation.outliers.max_cluster_points", (Limit{1, 64}), params.segmentation.outliers.max_cluster_points),
    VTS_PARAM("segmentation.outliers.threshold_mm", (Limit{0, kInf, true}), params.segmentation.outliers.threshold_mm),
    VTS_PARAM("segmentation.outliers.support_points", (Limit{1, 64}), params.segmentation.outliers.support_points),
    VTS_PARAM("segmentation.outliers.support_tol_mm", (Limit{0, kInf, true}), params.segmentation.outliers.support_tol_mm),
    VTS_PARAM("segmentation.segments.split_threshold_mm", (Limit{0, kInf, true}), params.segmentation.segments.split_threshold_mm),
    VTS_PARAM("segmentation.segments.split_interval", (Limit{1, 4096}), params.segmentation.segments.split_interval),
    VTS_PARAM("segmentation.segments.min_segment_points", (Limit{2, 4096}), params.segmentation.segments.min_segment_points),
    VTS_PARAM("segmentation.segments.max_merge_gap_points", (Limit{0, 4096}), params.segmentation.segments.max_merge_gap_points),
    VTS_PARAM("segmentation.segments.max_merge_angle_deg", (Limit{0, 90}), params.segmentation.segments.max_merge_angle_deg),
    VTS_PARAM("segmentation.segments.max_merge_offset_mm", (Limit{0, kInf}), params.segmentation.segments.max_merge_offset_mm),
    VTS_PARAM("segmentation.segments.break_min_mm", (Limit{0, kInf}), params.segmentation.segments.break_min_mm),
    VTS_PARAM("segmentation.segments.break_ratio", (Limit{1, kInf}), params.segmentation.segments.break_ratio),
    VTS_PARAM("segmentation.segments.fit_tol_mm", (Limit{0, kInf}), params.segmentation.segments.fit_tol_mm),
    VTS_PARAM("fillet.angle_deg", {}, params.fillet.angle_deg),
    VTS_PARAM("fillet.gap_mm", {}, params.fillet.gap_mm),
    VTS_PARAM("fillet.web", {}, params.fillet.web),
    VTS_PARAM("fillet.curved_plates", {}, params.fillet.curved_plates),
    VTS_PARAM("fillet.curve_window_mm", (Limit{0, kInf, true}), params.fillet.curve_window_mm),
    VTS_PARAM("fillet.curve_t", (Limit{0, kInf, true}), params.fillet.curve_t),
    VTS_PARAM("fillet.min_curve_radius", (Limit{0, kInf, true}), params.fillet.min_curve_radius),
    VTS_PARAM("fillet.curve_rms_sigma", (Limit{0, kInf, true}), params.fillet.curve_rms_sigma),
    VTS_PARAM("corner.angle_deg", {}, params.corner.angle_deg),
    VTS_PARAM("corner.gap_mm", {}, params.corner.gap_mm),
    VTS_PARAM("lap.step_mm", {}, params.lap.step_mm),
    VTS_PARAM("lap.gap_mm", {}, params.lap.gap_mm),
    VTS_PARAM("lap.angle_deg", {}, params.lap.angle_deg),
    VTS_PARAM("lap.max_plate_angle_deg", (Limit{0, 90}), params.lap.max_plate_angle_deg),
    VTS_PARAM("lap.upper_thickness_mm", (Limit{0, kInf}), params.lap.upper_thickness_mm),
    VTS_PARAM("butt.gap_mm", {}, params.butt.gap_mm),
    VTS_PARAM("butt.mismatch_mm", {}, params.butt.mismatch_mm),
    VTS_PARAM("butt.max_plate_angle_deg", (Limit{0, 90}), params.butt.max_plate_angle_deg),
    VTS_PARAM("vgroove.angle_deg", {}, params.vgroove.angle_deg),
    VTS_PARAM("vgroove.gap_mm", {}, params.vgroove.gap_mm),
    VTS_PARAM("vgroove.mismatch_mm", {}, params.vgroove.mismatch_mm),
    VTS_PARAM("vgroove.depth_mm", {}, params.vgroove.depth_mm),
    VTS_PARAM("vgroove.min_bevel_points", (Limit{2, 4096}), params.vgroove.min_bevel_points),
    VTS_PARAM("groove.vgroove_fill", {}, params.groove.vgroove_fill),
    VTS_PARAM("groove.mismatch_mm", {}, params.groove.mismatch_mm),
    VTS_PARAM("groove.top_width_mm", {}, params.groove.top_width_mm),
    VTS_PARAM("groove.depth_mm", {}, params.groove.depth_mm),
    VTS_PARAM("groove.bevel_wall_deg", {}, params.groove.bevel_wall_deg),
    VTS_PARAM("groove.u_wall_deg", {}, params.groove.u_wall_deg),
    VTS_PARAM("groove.square_wall_deg", {}, params.groove.square_wall_deg),
    VTS_PARAM("groove.min_wall_points", (Limit{2, 4096}), params.groove.min_wall_points),
    VTS_PARAM("groove.max_notch_mm", (Limit{0, kInf}), params.groove.max_notch_mm),
    VTS_PARAM("noise.sigma_mm", (Limit{0, kInf}), params.noise.sigma_mm),
    VTS_PARAM("noise.adapt", {}, params.noise.adapt),
    VTS_PARAM("confidence.window_mm", (Limit{0, kInf, true}), params.confidence.window_mm),
    VTS_PARAM("confidence.distinct_mm", (Limit{0, kInf, true}), params.confidence.distinct_mm),
    VTS_PARAM("confidence.hidden_prior", (Limit{0, 1, true}), params.confidence.hidden_prior),
    VTS_PARAM("confidence.temperature", (Limit{0, kInf, true}), params.confidence.temperature),
    VTS_PARAM("confidence.min_confidence", (Limit{0, 1}), params.confidence.min_confidence),
    VTS_PARAM("confidence.unexplained_points", (Limit{0, 4096}), params.confidence.unexplained_points),
    VTS_PARAM("confidence.unexplained_share", (Limit{0, 1}), params.confidence.unexplained_share),
    VTS_PARAM("confidence.max_plate_rms_sigma", (Limit{0, kInf, true}), params.confidence.max_plate_rms_sigma),
    VTS_PARAM("confidence.track_interval_mm", (Limit{0, kInf}), params.confidence.track_interval_mm),
};
#undef VTS_PARAM

// Walks the document over the field table. Every error names the file, the
// line and the key's path.
class Reader {
 public:
  Reader(std::string_view name, ParamsFile& into) : name_(name), into_(into) {}

  void read(std::string_view text) {
    YAML::Node root;
    try {
      root = YAML::Load(std::string(text));
    } catch (const YAML::Exception& e) {
      throw ParamsError(name_ + ":" + std::to_string(e.mark.line + 1) + ": " + e.msg);
    }
    if (root.IsNull()) return;  // an empty file changes nothing
    if (!root.IsMap()) fail(root, "", "expected a map of parameters (docs/CLI.md)");
    section(root, "");
  }

 private:
  static int line_of(const YAML::Node& n) { return n.Mark().line >= 0 ? n.Mark().line + 1 : 0; }

  [[noreturn]] void fail(int line, const std::string& path, const std::string& msg) const {
    throw ParamsError(name_ + ":" + std::to_string(line) + ": " + (path.empty() ? "" : path + ": ") + msg);
  }
  [[noreturn]] void fail(const YAML::Node& n, const std::string& path, const std::string& msg) const {
    fail(line_of(n), path, msg);
  }

  static std::string describe(const YAML::Node& n) {
    if (n.IsScalar()) return "'" + n.Scalar() + "'";
    if (n.IsSequence()) return "a list";
    if (n.IsMap()) return "a map";
    return "nothing";
  }

  // The keys a map at `path` may hold, in table order: a field's own key or
  // the first key of the section it lies in.
  static std::vector<std::string> keys_under(const std::string& path) {
    const std::string prefix = path.empty() ? "" : path + ".";
    std::vector<std::string> keys;
    for (const ParamField& f : kFields) {
      if (!f.path.starts_with(prefix)) continue;
      std::string_view rest = f.path.substr(prefix.size());
      std::string key(rest.substr(0, rest.find('.')));
      if (std::find(keys.begin(), keys.end(), key) == keys.end()) keys.push_back(std::move(key));
    }
    return keys;
  }

  void section(const YAML::Node& n, const std::string& path) {
    if (!n.IsMap()) fail(n, path, "expected a map, got " + describe(n));
    const std::vector<std::string> allowed = keys_under(path);
    std::vector<std::string> seen;
    for (const auto& kv : n) {
      const int line = line_of(kv.first);
      if (!kv.first.IsScalar()) fail(line, path, "keys must be plain names");
      const std::string key = kv.first.Scalar();
      const std::string sub = path.empty() ? key : path + "." + key;
      if (std::find(seen.begin(), seen.end(), key) != seen.end()) fail(line, sub, "duplicate key");
      seen.push_back(key);
      const YAML::Node value = kv.second;
      if (const ParamField* f = find_param(sub)) {
        leaf(value, sub, *f);
      } else if (std::find(allowed.begin(), allowed.end(), key) != allowed.end()) {
        section(value, sub);
      } else {
        std::string list;
        for (const std::string& k : allowed) list += (list.empty() ? "" : ", ") + k;
        fail(line, sub, "unknown key (expected one of: " + list + ")");
      }
    }
  }

  void leaf(const YAML::Node& n, const std::string& path, const ParamField& f) {
    std::visit([&](auto* out) { set(n, path, f.limit, *out); }, f.field(into_));
  }

  std::string scalar(const YAML::Node& n, const std::string& path) const {
    if (!n.IsScalar()) fail(n, path, "expected a value, got " + describe(n));
    return n.Scalar();
  }
  void set(const YAML::Node& n, const std::string& path, Limit lim, double& out) const {
    const std::string s = scalar(n, path);
    const auto v = to_number(s);
    if (!v) fail(n, path, "expected a number, got '" + s + "'");
    if (!lim.ok(*v)) fail(n, path, "'" + s + "' is out of range: expected " + lim.text());
    out = *v;
  }
  void set(const YAML::Node& n, const std::string& path, Limit lim, int& out) const {
    const std::string s = scalar(n, path);
    const auto v = to_integer(s);
    if (!v) fail(n, path, "expected an integer, got '" + s + "'");
    if (!lim.ok(static_cast<double>(*v))) fail(n, path, "'" + s + "' is out of range: expected " + lim.text());
    out = static_cast<int>(*v);
  }
  void set(const YAML::Node& n, const std::string& path, Limit, bool& out) const {
    const std::string s = scalar(n, path);
    if (s == "true") out = true;
    else if (s == "false") out = false;
    else fail(n, path, "expected true or false, got '" + s + "'");
  }
  void set(const YAML::Node& n, const std::string& path, Limit, tk::Range& out) const {
    if (!n.IsSequence() || n.size() != 2) fail(n, path, "expected [min, max], got " + describe(n));
    double lo = 0, hi = 0;
    set(n[0], path, Limit{}, lo);
    set(n[1], path, Limit{}, hi);
    if (lo > hi) fail(n, path, "min " + n[0].Scalar() + " is greater than max " + n[1].Scalar());
    out = {lo, hi};
  }
  void set(const YAML::Node& n, const std::string& path, Limit, tk::Vec2& out) const {
    if (!n.IsSequence() || n.size() != 2) fail(n, path, "expected [y, z] in mm, got " + describe(n));
    double y = 0, z = 0;
    set(n[0], path, Limit{}, y);
    set(n[1], path, Limit{}, z);
    out = tk::Vec2(y, z);
  }
  void set(const YAML::Node& n, const std::string& path, Limit, std::optional<tk::JointType>& out) const {
    const auto j = tk::joint_type_from_string(scalar(n, path));
    if (!j) fail(n, path, "'" + n.Scalar() + "' is not a joint; expected fillet, corner, lap, butt, vgroove, bevel, ugroove or jgroove");
    out = *j;
  }
  void set(const YAML::Node& n, const std::string& path, Limit, tk::WebSide& out) const {
    const std::string s = scalar(n, path);
    if (s == "auto") out = tk::WebSide::Auto;
    else if (s == "first") out = tk::WebSide::First;
    else if (s == "second") out = tk::WebSide::Second;
    else fail(n, path, "'" + s + "' is not auto, first or second");
  }

  std::string name_;
  ParamsFile& into_;
};

}  // namespace

std::optional<double> to_number(std::string_view t) {
  if (!t.empty() && t.front() == '+') t.remove_prefix(1);
  double v = 0.0;
  const auto r = std::from_chars(t.data(), t.data() + t.size(), v);
  if (t.empty() || r.ec != std::errc() || r.ptr != t.data() + t.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

std::optional<long long> to_integer(std::string_view t) {
  if (!t.empty() && t.front() == '+') t.remove_prefix(1);
  long long v = 0;
  const auto r = std::from_chars(t.data(), t.data() + t.size(), v);
  if (t.empty() || r.ec != std::errc() || r.ptr != t.data() + t.size()) return std::nullopt;
  return v;
}

std::string Limit::text() const {
  char b[96];
  if (hi == INFINITY) std::snprintf(b, sizeof b, "%s %g", lo_open ? ">" : ">=", lo);
  else std::snprintf(b, sizeof b, "from %g to %g", lo, hi);
  return b;
}

std::span<const ParamField> param_fields() { return kFields; }

const ParamField* find_param(std::string_view path) {
  for (const ParamField& f : kFields)
    if (f.path == path) return &f;
  return nullptr;
}

std::string_view unit_of(std::string_view path) {
  if (path.ends_with("_mm")) return "mm";
  if (path.ends_with("_deg")) return "degrees";
  return "";
}

void read_params(std::string_view text, std::string_view name, ParamsFile& into) { Reader(name, into).read(text); }

void read_params_file(const std::filesystem::path& file, ParamsFile& into) {
  std::ifstream in(file);
  if (!in) throw ParamsError(file.string() + ": cannot open file");
  std::ostringstream text;
  text << in.rdbuf();
  read_params(text.str(), file.string(), into);
}

}  // namespace vts::trackio
