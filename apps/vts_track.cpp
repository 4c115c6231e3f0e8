#include "apps/vts_track.h"

#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "apps/scan.h"
#include "sensor/profile_csv.h"
#include "sensor/profile_exr.h"
#include "sensor/scene_file.h"
#include "tracker/tracker.h"

namespace vts::apps {
namespace {

namespace fs = std::filesystem;
namespace tk = vts::tracker;
using Json = nlohmann::ordered_json;

struct TrackOptions {
  std::string input;
  std::string out;
  std::string joint;
  std::string params;
  bool truth = false;
  // Overrides, raw text ("" = not given).
  std::string split_threshold, split_interval, min_segment, merge_gap, merge_angle;
  std::string outlier_threshold, surface_tol, angle, gap, upper_thickness;
  bool no_outliers = false;
};

struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

[[noreturn]] void bad_option(const std::string& option, const std::string& value, const std::string& why) {
  throw InputError(option + " = '" + value + "': " + why);
}

std::optional<double> to_number(const std::string& text) {
  std::string_view t = text;
  if (!t.empty() && t.front() == '+') t.remove_prefix(1);
  double v = 0.0;
  const auto r = std::from_chars(t.data(), t.data() + t.size(), v);
  if (t.empty() || r.ec != std::errc() || r.ptr != t.data() + t.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

std::optional<long long> to_integer(const std::string& text) {
  std::string_view t = text;
  if (!t.empty() && t.front() == '+') t.remove_prefix(1);
  long long v = 0;
  const auto r = std::from_chars(t.data(), t.data() + t.size(), v);
  if (t.empty() || r.ec != std::errc() || r.ptr != t.data() + t.size()) return std::nullopt;
  return v;
}

// Limits of one numeric parameter, shared by the option and the file readers.
struct Limit {
  double lo, hi;
  bool lo_open = false;  // lo itself excluded
  std::string text() const {
    char b[96];
    if (hi == INFINITY) std::snprintf(b, sizeof b, "%s %g", lo_open ? ">" : ">=", lo);
    else std::snprintf(b, sizeof b, "from %g to %g", lo, hi);
    return b;
  }
  bool ok(double v) const { return (lo_open ? v > lo : v >= lo) && v <= hi; }
};
constexpr double kInf = INFINITY;

// --params FILE: YAML mirroring TrackerParams (docs/CLI.md). Every error
// names the file, the line and the field's path.
class ParamsReader {
 public:
  ParamsReader(std::string file, tk::TrackerParams& p, std::optional<tk::JointType>& joint)
      : file_(std::move(file)), p_(p), joint_(joint) {}

  void read() {
    YAML::Node root;
    try {
      std::ifstream in(file_);
      if (!in) throw InputError(file_ + ": cannot open file");
      root = YAML::Load(in);
    } catch (const YAML::Exception& e) {
      throw InputError(file_ + ":" + std::to_string(e.mark.line + 1) + ": " + e.msg);
    }
    if (root.IsNull()) return;  // an empty file changes nothing
    if (!root.IsMap()) fail(root, "", "expected a map of parameters (docs/CLI.md)");
    map(root, "", [&](const std::string& key, const YAML::Node& v, const std::string& path) {
      if (key == "joint") {
        const auto j = tk::joint_type_from_string(scalar(v, path));
        if (!j) fail(v, path, "'" + v.Scalar() + "' is not a joint; expected fillet, corner, lap, butt or vgroove");
        joint_ = *j;
      } else if (key == "surface_tol_mm") {
        number(v, path, p_.surface_tol_mm, {0, kInf, true});
      } else if (key == "max_joint_width_mm") {
        number(v, path, p_.max_joint_width_mm, {0, kInf, true});
      } else if (key == "square_edges") {
        boolean(v, path, p_.square_edges);
      } else if (key == "segmentation") {
        segmentation(v, path);
      } else if (key == "fillet") {
        auto& f = p_.fillet;
        map(v, path, [&](const std::string& k, const YAML::Node& x, const std::string& q) {
          if (k == "angle_deg") range(x, q, f.angle_deg);
          else if (k == "gap_mm") range(x, q, f.gap_mm);
          else if (k == "web") {
            const std::string s = scalar(x, q);
            if (s == "auto") f.web = tk::WebSide::Auto;
            else if (s == "first") f.web = tk::WebSide::First;
            else if (s == "second") f.web = tk::WebSide::Second;
            else fail(x, q, "'" + s + "' is not auto, first or second");
          } else return false;
          return true;
        }, "angle_deg, gap_mm, web");
      } else if (key == "corner") {
        auto& c = p_.corner;
        map(v, path, [&](const std::string& k, const YAML::Node& x, const std::string& q) {
          if (k == "angle_deg") range(x, q, c.angle_deg);
          else if (k == "gap_mm") range(x, q, c.gap_mm);
          else return false;
          return true;
        }, "angle_deg, gap_mm");
      } else if (key == "lap") {
        auto& l = p_.lap;
        map(v, path, [&](const std::string& k, const YAML::Node& x, const std::string& q) {
          if (k == "step_mm") range(x, q, l.step_mm);
          else if (k == "gap_mm") range(x, q, l.gap_mm);
          else if (k == "angle_deg") range(x, q, l.angle_deg);
          else if (k == "max_plate_angle_deg") number(x, q, l.max_plate_angle_deg, {0, 90});
          else if (k == "upper_thickness_mm") number(x, q, l.upper_thickness_mm, {0, kInf});
          else return false;
          return true;
        }, "step_mm, gap_mm, angle_deg, max_plate_angle_deg, upper_thickness_mm");
      } else if (key == "butt") {
        auto& b = p_.butt;
        map(v, path, [&](const std::string& k, const YAML::Node& x, const std::string& q) {
          if (k == "gap_mm") range(x, q, b.gap_mm);
          else if (k == "mismatch_mm") range(x, q, b.mismatch_mm);
          else if (k == "max_plate_angle_deg") number(x, q, b.max_plate_angle_deg, {0, 90});
          else return false;
          return true;
        }, "gap_mm, mismatch_mm, max_plate_angle_deg");
      } else if (key == "vgroove") {
        auto& g = p_.vgroove;
        map(v, path, [&](const std::string& k, const YAML::Node& x, const std::string& q) {
          if (k == "angle_deg") range(x, q, g.angle_deg);
          else if (k == "gap_mm") range(x, q, g.gap_mm);
          else if (k == "mismatch_mm") range(x, q, g.mismatch_mm);
          else if (k == "depth_mm") range(x, q, g.depth_mm);
          else if (k == "min_bevel_points") integer(x, q, g.min_bevel_points, {2, 4096});
          else return false;
          return true;
        }, "angle_deg, gap_mm, mismatch_mm, depth_mm, min_bevel_points");
      } else {
        return false;
      }
      return true;
    }, "joint, surface_tol_mm, max_joint_width_mm, square_edges, segmentation, fillet, corner, lap, butt, vgroove");
  }

 private:
  std::string file_;
  tk::TrackerParams& p_;
  std::optional<tk::JointType>& joint_;

  static int line_of(const YAML::Node& n) { return n.Mark().line >= 0 ? n.Mark().line + 1 : 0; }

  [[noreturn]] void fail(int line, const std::string& path, const std::string& msg) const {
    throw InputError(file_ + ":" + std::to_string(line) + ": " + (path.empty() ? "" : path + ": ") + msg);
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

  // Calls f(key, value, path) for every entry; f returns false for an unknown key.
  template <class F>
  void map(const YAML::Node& n, const std::string& path, F&& f, const char* allowed) {
    if (!n.IsMap()) fail(n, path, "expected a map, got " + describe(n));
    std::vector<std::string> seen;
    for (const auto& kv : n) {
      const int line = line_of(kv.first);
      if (!kv.first.IsScalar()) fail(line, path, "keys must be plain names");
      const std::string key = kv.first.Scalar();
      const std::string sub = path.empty() ? key : path + "." + key;
      if (std::find(seen.begin(), seen.end(), key) != seen.end()) fail(line, sub, "duplicate key");
      seen.push_back(key);
      // Values are reported at their key's line (a null value has no mark of its own).
      YAML::Node value = kv.second;
      if (!f(key, value, sub)) fail(line, sub, std::string("unknown key (expected one of: ") + allowed + ")");
    }
  }

  std::string scalar(const YAML::Node& n, const std::string& path) const {
    if (!n.IsScalar()) fail(n, path, "expected a value, got " + describe(n));
    return n.Scalar();
  }
  void number(const YAML::Node& n, const std::string& path, double& out, Limit lim) const {
    const std::string s = scalar(n, path);
    const auto v = to_number(s);
    if (!v) fail(n, path, "expected a number, got '" + s + "'");
    if (!lim.ok(*v)) fail(n, path, "'" + s + "' is out of range: expected " + lim.text());
    out = *v;
  }
  void integer(const YAML::Node& n, const std::string& path, int& out, Limit lim) const {
    const std::string s = scalar(n, path);
    const auto v = to_integer(s);
    if (!v) fail(n, path, "expected an integer, got '" + s + "'");
    if (!lim.ok(static_cast<double>(*v))) fail(n, path, "'" + s + "' is out of range: expected " + lim.text());
    out = static_cast<int>(*v);
  }
  void boolean(const YAML::Node& n, const std::string& path, bool& out) const {
    const std::string s = scalar(n, path);
    if (s == "true") out = true;
    else if (s == "false") out = false;
    else fail(n, path, "expected true or false, got '" + s + "'");
  }
  // [min, max]
  void range(const YAML::Node& n, const std::string& path, tk::Range& out) const {
    if (!n.IsSequence() || n.size() != 2) fail(n, path, "expected [min, max], got " + describe(n));
    double lo = 0, hi = 0;
    number(n[0], path, lo, {-kInf, kInf});
    number(n[1], path, hi, {-kInf, kInf});
    if (lo > hi) fail(n, path, "min " + n[0].Scalar() + " is greater than max " + n[1].Scalar());
    out = {lo, hi};
  }

  void segmentation(const YAML::Node& v, const std::string& path) {
    auto& s = p_.segmentation;
    map(v, path, [&](const std::string& k, const YAML::Node& x, const std::string& q) {
      if (k == "roi_first") integer(x, q, s.roi_first, {0, 4095});
      else if (k == "roi_last") integer(x, q, s.roi_last, {-1, 4095});
      else if (k == "ray_origin_yz") {
        if (!x.IsSequence() || x.size() != 2) fail(x, q, "expected [y, z] in mm, got " + describe(x));
        double y = 0, z = 0;
        number(x[0], q, y, {-kInf, kInf});
        number(x[1], q, z, {-kInf, kInf});
        s.ray_origin_yz = tk::Vec2(y, z);
      } else if (k == "outliers") {
        auto& o = s.outliers;
        map(x, q, [&](const std::string& k2, const YAML::Node& y, const std::string& q2) {
          if (k2 == "enabled") boolean(y, q2, o.enabled);
          else if (k2 == "max_cluster_points") integer(y, q2, o.max_cluster_points, {1, 64});
          else if (k2 == "threshold_mm") number(y, q2, o.threshold_mm, {0, kInf, true});
          else if (k2 == "support_points") integer(y, q2, o.support_points, {1, 64});
          else if (k2 == "support_tol_mm") number(y, q2, o.support_tol_mm, {0, kInf, true});
          else return false;
          return true;
        }, "enabled, max_cluster_points, threshold_mm, support_points, support_tol_mm");
      } else if (k == "segments") {
        auto& g = s.segments;
        map(x, q, [&](const std::string& k2, const YAML::Node& y, const std::string& q2) {
          if (k2 == "split_threshold_mm") number(y, q2, g.split_threshold_mm, {0, kInf, true});
          else if (k2 == "split_interval") integer(y, q2, g.split_interval, {1, 4096});
          else if (k2 == "min_segment_points") integer(y, q2, g.min_segment_points, {2, 4096});
          else if (k2 == "max_merge_gap_points") integer(y, q2, g.max_merge_gap_points, {0, 4096});
          else if (k2 == "max_merge_angle_deg") number(y, q2, g.max_merge_angle_deg, {0, 90});
          else if (k2 == "max_merge_offset_mm") number(y, q2, g.max_merge_offset_mm, {0, kInf});
          else if (k2 == "break_min_mm") number(y, q2, g.break_min_mm, {0, kInf});
          else if (k2 == "break_ratio") number(y, q2, g.break_ratio, {1, kInf});
          else if (k2 == "fit_tol_mm") number(y, q2, g.fit_tol_mm, {0, kInf});
          else return false;
          return true;
        }, "split_threshold_mm, split_interval, min_segment_points, max_merge_gap_points, max_merge_angle_deg, "
           "max_merge_offset_mm, break_min_mm, break_ratio, fit_tol_mm");
      } else {
        return false;
      }
      return true;
    }, "roi_first, roi_last, ray_origin_yz, outliers, segments");
  }
};

double option_number(const std::string& option, const std::string& text, Limit lim, const char* unit) {
  const auto v = to_number(text);
  if (!v) bad_option(option, text, std::string("expected a number in ") + unit);
  if (!lim.ok(*v)) bad_option(option, text, "out of range: expected " + lim.text() + " " + unit);
  return *v;
}
int option_integer(const std::string& option, const std::string& text, Limit lim) {
  const auto v = to_integer(text);
  if (!v || !lim.ok(static_cast<double>(*v))) bad_option(option, text, "expected an integer " + lim.text());
  return static_cast<int>(*v);
}
tk::Range option_range(const std::string& option, const std::string& text, const char* unit) {
  const std::size_t comma = text.find(',');
  const auto lo = comma == std::string::npos ? std::nullopt : to_number(text.substr(0, comma));
  const auto hi = comma == std::string::npos ? std::nullopt : to_number(text.substr(comma + 1));
  if (!lo || !hi) bad_option(option, text, std::string("expected MIN,MAX in ") + unit);
  if (*lo > *hi) bad_option(option, text, "MIN is greater than MAX");
  return {*lo, *hi};
}

// The joint of a recording's scene, if the file says. A mesh workpiece says
// only when its scene named the joint (`joint:`), and gives no thickness; its
// mesh file is not read.
std::optional<vts::JointType> scene_joint(const ProfileRecording& rec, double* thickness_mm) {
  if (rec.info.scene_text.empty()) return std::nullopt;
  try {
    const Cell cell = parse_scene(rec.info.scene_text, rec.info.scene_name, MeshFiles::Skip);
    if (cell.workpieces.empty()) return std::nullopt;
    const vts::Workpiece& w = cell.workpieces.front();
    if (!w.has_joint()) return std::nullopt;
    *thickness_mm = w.is_mesh() ? 0.0 : w.params.thickness_mm;
    return w.type;
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

std::optional<tk::JointType> tracker_joint(vts::JointType t) {
  switch (t) {
    case vts::JointType::Fillet: return tk::JointType::Fillet;
    case vts::JointType::Corner: return tk::JointType::Corner;
    case vts::JointType::Lap: return tk::JointType::Lap;
    case vts::JointType::Butt: return tk::JointType::Butt;
    case vts::JointType::VGroove: return tk::JointType::VGroove;
    default: return std::nullopt;
  }
}

// Micrometre-rounded mm value, or null when not measured.
Json num(double v) {
  if (!std::isfinite(v)) return nullptr;
  const double r = std::round(v * 1e6) / 1e6;
  return r == 0.0 ? 0.0 : r;  // no "-0.0"
}

Json to_json(std::int64_t index, const tk::TrackResult& r) {
  Json j;
  j["profile"] = index;
  j["joint"] = std::string(tk::to_string(r.joint));
  j["status"] = std::string(tk::to_string(r.status));
  if (r.status != tk::TrackStatus::Ok) j["reason"] = r.reason;
  Json bps = Json::array();
  for (int i = 0; i < tk::kMaxBreakPoints; ++i) {
    if (!r.break_points[i]) continue;
    bps.push_back(Json{{"name", "B" + std::to_string(i)},
                       {"meaning", std::string(tk::break_point_name(r.joint, i))},
                       {"y", num(r.break_points[i]->x())},
                       {"z", num(r.break_points[i]->y())}});
  }
  j["break_points"] = bps;
  j["track_point"] = r.track_point ? Json{{"y", num(r.track_point->x())}, {"z", num(r.track_point->y())}} : Json();
  j["gap_mm"] = num(r.gap_mm);
  j["gap_paper_mm"] = num(r.gap_paper_mm);
  j["angle_deg"] = num(r.angle_deg);
  j["mismatch_mm"] = num(r.mismatch_mm);
  j["step_mm"] = num(r.step_mm);
  j["depth_mm"] = num(r.depth_mm);
  j["area_mm2"] = num(r.area_mm2);
  j["edge_uncertainty_mm"] = num(r.edge_uncertainty_mm);
  j["valid_points"] = r.valid_points;
  j["outliers"] = r.outliers;
  Json segs = Json::array();
  for (const auto& s : r.segments) {
    Json line = s.points >= 2 ? Json{{"ny", num(s.line.n.x())}, {"nz", num(s.line.n.y())}, {"c", num(s.line.c)}}
                              : Json();
    segs.push_back(Json{{"first", s.first_col},
                        {"last", s.last_col},
                        {"points", s.points},
                        {"line", line},
                        {"rms_mm", num(s.rms_mm)}});
  }
  j["segments"] = segs;
  return j;
}

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

int run_track(const TrackOptions& o) {
  // Everything is read and checked before anything is written.
  tk::TrackerParams params;
  std::optional<tk::JointType> joint;
  if (!o.joint.empty()) {
    joint = tk::joint_type_from_string(o.joint);
    if (!joint) bad_option("--joint", o.joint, "unknown joint; expected fillet, corner, lap, butt or vgroove");
  }
  std::optional<tk::JointType> file_joint;
  if (!o.params.empty()) {
    try {
      ParamsReader(o.params, params, file_joint).read();
    } catch (const InputError& e) {
      throw InputError(std::string("--params: ") + e.what());
    }
  }
  auto& seg = params.segmentation.segments;
  if (!o.split_threshold.empty())
    seg.split_threshold_mm = option_number("--split-threshold", o.split_threshold, {0, kInf, true}, "mm");
  if (!o.split_interval.empty()) seg.split_interval = option_integer("--split-interval", o.split_interval, {1, 4096});
  if (!o.min_segment.empty())
    seg.min_segment_points = option_integer("--min-segment", o.min_segment, {2, 4096});
  if (!o.merge_gap.empty()) seg.max_merge_gap_points = option_integer("--merge-gap", o.merge_gap, {0, 4096});
  if (!o.merge_angle.empty())
    seg.max_merge_angle_deg = option_number("--merge-angle", o.merge_angle, {0, 90}, "degrees");
  if (!o.outlier_threshold.empty())
    params.segmentation.outliers.threshold_mm =
        option_number("--outlier-threshold", o.outlier_threshold, {0, kInf, true}, "mm");
  if (o.no_outliers) params.segmentation.outliers.enabled = false;
  if (!o.surface_tol.empty())
    params.surface_tol_mm = option_number("--surface-tol", o.surface_tol, {0, kInf, true}, "mm");
  std::optional<double> thickness;
  if (!o.upper_thickness.empty())
    thickness = option_number("--upper-thickness", o.upper_thickness, {0, kInf}, "mm");

  // The input.
  const std::string ext = lower(fs::path(o.input).extension().string());
  std::vector<Profile> profiles;
  std::optional<vts::JointType> from_scene;
  double scene_thickness = 0.0;
  if (ext == ".csv") {
    if (o.truth)
      throw InputError("--truth: " + o.input + " is a CSV file; only EXR files recorded with the error model carry "
                       "ground truth");
    try {
      profiles = read_profile_csv(o.input);
    } catch (const CsvError& e) {
      throw InputError(e.what());
    }
  } else if (ext == ".exr") {
    ProfileRecording rec;
    try {
      rec = read_profile_exr(o.input);
    } catch (const ExrError& e) {
      throw InputError(e.what());
    }
    if (o.truth && !rec.info.error_model)
      throw InputError("--truth: " + o.input +
                       " has no ground truth channels (true.y, true.z, true.valid: written only when the error "
                       "model is on)");
    from_scene = scene_joint(rec, &scene_thickness);
    profiles = std::move(rec.profiles);
    if (o.truth)
      for (Profile& p : profiles) {
        p.y_mm = p.true_y_mm;
        p.z_mm = p.true_z_mm;
        p.valid = p.true_valid;
      }
  } else {
    throw InputError(o.input + ": unknown file type '" + fs::path(o.input).extension().string() +
                     "': expected .exr (vts profile EXR) or .csv");
  }

  // Joint: --joint, else the params file's, else the recording's scene, else fillet.
  if (!joint) joint = file_joint;
  bool joint_from_scene = false;
  if (!joint && from_scene) {
    joint = tracker_joint(*from_scene);
    joint_from_scene = joint.has_value();
  }
  params.joint = joint.value_or(tk::JointType::Fillet);
  if (thickness) params.lap.upper_thickness_mm = *thickness;
  else if (joint_from_scene && params.joint == tk::JointType::Lap && params.lap.upper_thickness_mm == 0.0)
    params.lap.upper_thickness_mm = scene_thickness;
  if (!o.angle.empty() || !o.gap.empty()) {
    tk::Range* angle = nullptr;
    tk::Range* gap = nullptr;
    switch (params.joint) {
      case tk::JointType::Fillet: angle = &params.fillet.angle_deg, gap = &params.fillet.gap_mm; break;
      case tk::JointType::Corner: angle = &params.corner.angle_deg, gap = &params.corner.gap_mm; break;
      case tk::JointType::Lap: angle = &params.lap.angle_deg, gap = &params.lap.gap_mm; break;
      case tk::JointType::Butt: gap = &params.butt.gap_mm; break;
      case tk::JointType::VGroove: angle = &params.vgroove.angle_deg, gap = &params.vgroove.gap_mm; break;
    }
    if (!o.angle.empty()) {
      if (!angle) bad_option("--angle", o.angle, "the butt template has no angle range");
      *angle = option_range("--angle", o.angle, "degrees");
    }
    if (!o.gap.empty()) *gap = option_range("--gap", o.gap, "mm");
  }

  // The output: a temporary file renamed at the end, so a failed run leaves none.
  fs::path out_path, tmp_path;
  std::ofstream file;
  if (!o.out.empty()) {
    out_path = fs::absolute(o.out).lexically_normal();
    std::error_code ec;
    if (fs::is_directory(out_path, ec)) bad_option("--out", o.out, "is a directory, expected a file name");
    const fs::path dir = out_path.parent_path();
    if (!fs::is_directory(dir, ec)) bad_option("--out", o.out, "directory '" + dir.string() + "' does not exist");
    tmp_path = out_path;
    tmp_path += ".tmp-" + std::to_string(::getpid());
    file.open(tmp_path, std::ios::binary | std::ios::trunc);
    if (!file) throw std::runtime_error("cannot create " + tmp_path.string());
  }
  std::ostream& out = o.out.empty() ? std::cout : file;

  tk::Tracker tracker(params);
  tk::TrackResult result;
  std::string line;
  for (const Profile& p : profiles) {
    tracker.track(tk::ProfileView{p.y_mm, p.z_mm, p.valid}, result);
    line = to_json(p.index, result).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
    line += '\n';
    out.write(line.data(), static_cast<std::streamsize>(line.size()));
  }
  out.flush();
  if (!o.out.empty()) {
    file.close();
    std::error_code ec;
    if (!file) {
      fs::remove(tmp_path, ec);
      throw std::runtime_error("cannot write " + out_path.string());
    }
    fs::rename(tmp_path, out_path, ec);
    if (ec) {
      fs::remove(tmp_path, ec);
      throw std::runtime_error("cannot rename onto " + out_path.string() + ": " + ec.message());
    }
  } else if (!std::cout) {
    throw std::runtime_error("cannot write to stdout");
  }
  return cli::kExitOk;
}

}  // namespace

CLI::App* add_track_command(CLI::App& app, int& exit_code) {
  auto o = std::make_shared<TrackOptions>();
  CLI::App* cmd = app.add_subcommand(
      "track",
      "Run the seam tracker on every profile of a vts EXR or a CSV file; write one JSON object per "
      "profile (JSON Lines) to stdout or --out");
  cmd->option_defaults()->always_capture_default(false);
  cmd->add_option("file", o->input, "Profiles: a vts profile EXR (.exr) or CSV with header profile,y,z[,valid] (.csv)")
      ->required()
      ->type_name("FILE");
  cmd->add_option("--out", o->out, "Write the JSON Lines here instead of stdout (written whole or not at all)")
      ->type_name("FILE");
  cmd->add_option("--joint", o->joint,
                  "Joint template: fillet, corner, lap, butt, vgroove. Default: the --params file's joint, "
                  "else the joint of the EXR's scene, else fillet")
      ->type_name("TYPE");
  cmd->add_option("--params", o->params, "Tracker parameters, YAML (docs/CLI.md); options below override it")
      ->type_name("FILE");
  cmd->add_flag("--truth", o->truth,
                "EXR recorded with the error model: track the ideal points (true.y, true.z, true.valid) "
                "instead of the measured ones");
  cmd->add_option("--split-threshold", o->split_threshold, "Split threshold t_split, mm (> 0; default 0.4)")
      ->type_name("MM");
  cmd->add_option("--split-interval", o->split_interval, "Split interval s_int, points (>= 1; default 2)")
      ->type_name("N");
  cmd->add_option("--min-segment", o->min_segment, "Minimum segment size s_min, points (>= 2; default 8)")
      ->type_name("N");
  cmd->add_option("--merge-gap", o->merge_gap, "Maximum merge gap g_max, points (>= 0; default 10)")
      ->type_name("N");
  cmd->add_option("--merge-angle", o->merge_angle, "Maximum merge angle, degrees (0..90; default 15)")
      ->type_name("DEG");
  cmd->add_option("--outlier-threshold", o->outlier_threshold,
                  "Outlier cluster threshold, mm (> 0; default 0.3)")
      ->type_name("MM");
  cmd->add_flag("--no-outliers", o->no_outliers, "Skip outlier elimination (step 1)");
  cmd->add_option("--surface-tol", o->surface_tol,
                  "How far a point may lie off a fitted surface and still count as on it, mm (> 0; default "
                  "0.02; raise it for noisy profiles)")
      ->type_name("MM");
  cmd->add_option("--angle", o->angle, "Accept range of the joint's angle, degrees (not for butt)")
      ->type_name("MIN,MAX");
  cmd->add_option("--gap", o->gap, "Accept range of the joint's gap, mm")->type_name("MIN,MAX");
  cmd->add_option("--upper-thickness", o->upper_thickness,
                  "Lap: upper plate thickness, mm (gap from the step when the edge face is hidden; default: "
                  "from the EXR's scene, else unknown)")
      ->type_name("MM");
  cmd->callback([o, &exit_code] {
    try {
      exit_code = run_track(*o);
    } catch (const InputError& e) {
      std::cout.flush();
      std::cerr << "vts track: " << e.what() << "\n";
      exit_code = cli::kExitUsage;
    }
  });
  return cmd;
}

}  // namespace vts::apps
