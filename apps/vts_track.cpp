#include "apps/vts_track.h"

#include <array>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "apps/cli.h"
#include "common/atomic_file.h"
#include "pipeline/track_input.h"
#include "pipeline/track_recording.h"
#include "tracker/tracker.h"
#include "trackio/params_yaml.h"

namespace vts::apps {
namespace {

namespace fs = std::filesystem;
namespace tk = vts::tracker;
using trackio::Limit;
using trackio::to_number;

// The options that set one tracker parameter, in --help order: the option,
// the parameter's key in the --params file (whose limits it shares), the
// value's name (none: a flag, which sets a true/false parameter to false),
// and the help text.
struct ParamOption {
  const char* option;
  const char* path;
  const char* type_name;
  const char* help;
};
constexpr ParamOption kParamOptions[] = {
    {"--split-threshold", "segmentation.segments.split_threshold_mm", "MM",
     "Split threshold t_split, mm (> 0; default 0.4)"},
    {"--split-interval", "segmentation.segments.split_interval", "N", "Split interval s_int, points (>= 1; default 2)"},
    {"--min-segment", "segmentation.segments.min_segment_points", "N",
     "Minimum segment size s_min, points (>= 2; default 8)"},
    {"--merge-gap", "segmentation.segments.max_merge_gap_points", "N",
     "Maximum merge gap g_max, points (>= 0; default 10)"},
    {"--merge-angle", "segmentation.segments.max_merge_angle_deg", "DEG",
     "Maximum merge angle, degrees (0..90; default 15)"},
    {"--outlier-threshold", "segmentation.outliers.threshold_mm", "MM",
     "Outlier cluster threshold, mm (> 0; default 0.3)"},
    {"--no-outliers", "segmentation.outliers.enabled", nullptr, "Skip outlier elimination (step 1)"},
    {"--surface-tol", "surface_tol_mm", "MM",
     "How far a point may lie off a fitted surface and still count as on it, mm (> 0; default 0.02; raise it for "
     "noisy profiles)"},
};
constexpr std::size_t kParamOptionCount = std::size(kParamOptions);

struct TrackOptions {
  std::string input, out, joint, params;
  bool truth = false;
  bool independent = false;  // each profile alone, not the sequence (tracker/follower.h)
  bool fill = false;         // v-groove: beads are laid in it (GrooveParams::vgroove_fill)
  std::string travel;        // --travel MM: travel per profile without poses (CSV)
  struct Value {
    std::string text;  // "" = not given
    bool flag = false;
  };
  std::array<Value, kParamOptionCount> values;
  std::string angle, gap, upper_thickness;
};

struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

[[noreturn]] void bad_option(const std::string& option, const std::string& value, const std::string& why) {
  throw InputError(option + " = '" + value + "': " + why);
}

double option_number(const std::string& option, const std::string& text, Limit lim, std::string_view unit) {
  const auto v = to_number(text);
  const std::string u(unit);
  if (!v) bad_option(option, text, "expected a number in " + u);
  if (!lim.ok(*v)) bad_option(option, text, "out of range: expected " + lim.text() + " " + u);
  return *v;
}

// One of kParamOptions given on the command line, into `file`.
void apply_option(const ParamOption& o, const TrackOptions::Value& v, trackio::ParamsFile& file) {
  const trackio::ParamField& f = *trackio::find_param(o.path);
  const auto field = f.field(file);
  if (!o.type_name) {
    if (v.flag) *std::get<bool*>(field) = false;
  } else if (v.text.empty()) {
  } else if (auto* i = std::get_if<int*>(&field)) {
    const auto n = trackio::to_integer(v.text);
    if (!n || !f.limit.ok(static_cast<double>(*n))) bad_option(o.option, v.text, "expected an integer " + f.limit.text());
    **i = static_cast<int>(*n);
  } else {
    *std::get<double*>(field) = option_number(o.option, v.text, f.limit, trackio::unit_of(o.path));
  }
}

tk::Range option_range(const std::string& option, const std::string& text, const char* unit) {
  const std::size_t comma = text.find(',');
  const auto lo = comma == std::string::npos ? std::nullopt : to_number(text.substr(0, comma));
  const auto hi = comma == std::string::npos ? std::nullopt : to_number(text.substr(comma + 1));
  if (!lo || !hi) bad_option(option, text, std::string("expected MIN,MAX in ") + unit);
  if (*lo > *hi) bad_option(option, text, "MIN is greater than MAX");
  return {*lo, *hi};
}

int run_track(const TrackOptions& o) {
  // The options and the recording's header are read and checked before anything is written.
  std::optional<tk::JointType> joint;
  if (!o.joint.empty()) {
    joint = tk::joint_type_from_string(o.joint);
    if (!joint) bad_option("--joint", o.joint,
                 "unknown joint; expected fillet, corner, lap, butt, vgroove, bevel, ugroove or jgroove");
  }
  trackio::ParamsFile file;
  if (!o.params.empty()) {
    try {
      trackio::read_params_file(o.params, file);
    } catch (const trackio::ParamsError& e) {
      throw InputError(std::string("--params: ") + e.what());
    }
  }
  for (std::size_t k = 0; k < kParamOptionCount; ++k) apply_option(kParamOptions[k], o.values[k], file);
  tk::TrackerParams& params = file.params;
  if (o.fill) params.groove.vgroove_fill = true;
  if (!o.upper_thickness.empty())
    params.lap.upper_thickness_mm =
        option_number("--upper-thickness", o.upper_thickness, trackio::find_param("lap.upper_thickness_mm")->limit, "mm");

  // The input.
  if (o.truth && recording_format(o.input) == RecordingFormat::Csv)
    throw InputError("--truth: " + o.input + " is a CSV file; only EXR files recorded with the error model carry "
                     "ground truth");
  std::optional<TrackInputReader> reader;
  try {
    reader.emplace(o.input);
  } catch (const TrackInputError& e) {
    throw InputError(e.what());
  }
  const TrackInputInfo& input = reader->info();
  if (o.truth && !input.has_truth)
    throw InputError("--truth: " + o.input +
                     " has no ground truth channels (true.y, true.z, true.valid: written only when the error "
                     "model is on)");
  if (o.truth) reader->use_truth();

  // Joint: --joint, else the params file's, else the recording's scene, else fillet.
  if (!joint) joint = file.joint;
  const bool joint_from_scene = !joint && input.scene_joint;
  if (!joint) joint = input.scene_joint;
  params.joint = joint.value_or(tk::JointType::Fillet);
  if (o.upper_thickness.empty() && joint_from_scene && params.joint == tk::JointType::Lap &&
      params.lap.upper_thickness_mm == 0.0)
    params.lap.upper_thickness_mm = input.scene_thickness_mm;
  // --angle and --gap set the joint's ranges, as its template's
  // JOINT.angle_deg and JOINT.gap_mm in a parameter file do.
  const std::string joint_key(tk::to_string(params.joint));
  if (!o.angle.empty()) {
    const trackio::ParamField* angle = trackio::find_param(joint_key + ".angle_deg");
    if (!angle) bad_option("--angle", o.angle, "the butt template has no angle range");
    *std::get<tk::Range*>(angle->field(file)) = option_range("--angle", o.angle, "degrees");
  }
  if (!o.gap.empty())
    *std::get<tk::Range*>(trackio::find_param(joint_key + ".gap_mm")->field(file)) =
        option_range("--gap", o.gap, "mm");
  TrackRecordingOptions tracking;
  tracking.independent = o.independent;
  if (!o.travel.empty())
    tracking.follow.travel_per_profile_mm = option_number("--travel", o.travel, Limit{0.0, INFINITY, false}, "mm");

  // The output: a temporary file renamed at the end, so a failed run leaves none.
  std::optional<AtomicFile> out_file;
  if (!o.out.empty()) {
    const fs::path out_path = fs::absolute(o.out).lexically_normal();
    std::error_code ec;
    if (fs::is_directory(out_path, ec)) bad_option("--out", o.out, "is a directory, expected a file name");
    const fs::path dir = out_path.parent_path();
    if (!fs::is_directory(dir, ec)) bad_option("--out", o.out, "directory '" + dir.string() + "' does not exist");
    out_file.emplace(out_path);
    if (!out_file->is_open()) throw std::runtime_error("cannot create " + out_file->temp_path().string());
  }
  std::ostream& out = out_file ? out_file->stream() : std::cout;
  // The recording is read as it is tracked: bad profiles further on throw
  // after some lines were written; the temporary file then goes.
  try {
    track_recording(*reader, params, tracking, [&out](const std::string& line) {
      out.write(line.data(), static_cast<std::streamsize>(line.size()));
    });
  } catch (const TrackInputError& e) {
    throw InputError(e.what());
  }
  out.flush();
  if (out_file) out_file->commit();
  else if (!std::cout) throw std::runtime_error("cannot write to stdout");
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
                  "Joint template: fillet, corner, lap, butt, vgroove, bevel, ugroove, jgroove. Default: the --params file's joint, "
                  "else the joint of the EXR's scene, else fillet")
      ->type_name("TYPE");
  cmd->add_option("--params", o->params, "Tracker parameters, YAML (docs/CLI.md); options below override it")
      ->type_name("FILE");
  cmd->add_flag("--independent", o->independent,
                "Read each profile alone; by default the profiles are a sequence along one seam: once the "
                "joint is found, each profile is searched only near where it is predicted (docs/JOINTS.md)");
  cmd->add_flag("--fill", o->fill,
                "V-groove: beads are laid in it (multi-pass): read the last bead's surface as the groove's "
                "bottom (the fill: remaining depth and area, the next bead's toes), not as a tack weld "
                "over the root (docs/JOINTS.md \"Grooves and fill\")");
  cmd->add_option("--travel", o->travel,
                  "CSV: travel of the sensor along the seam per profile, mm (>= 0; default 1; EXR files "
                  "carry the sensor's pose per profile)")
      ->type_name("MM");
  cmd->add_flag("--truth", o->truth,
                "EXR recorded with the error model: track the ideal points (true.y, true.z, true.valid) "
                "instead of the measured ones");
  for (std::size_t k = 0; k < kParamOptionCount; ++k) {
    const ParamOption& p = kParamOptions[k];
    if (p.type_name) cmd->add_option(p.option, o->values[k].text, p.help)->type_name(p.type_name);
    else cmd->add_flag(p.option, o->values[k].flag, p.help);
  }
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
