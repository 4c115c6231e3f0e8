#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <charconv>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <limits>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "apps/scan.h"
#include "render/raster_source.h"
#include "sensor/cell.h"
#include "sensor/error_model.h"
#include "sensor/presets.h"
#include "sensor/profile_exr.h"
#include "sensor/reference_source.h"
#include "sensor/scene_file.h"

namespace vts::cli {
namespace {

namespace fs = std::filesystem;

std::string names_list() {
  std::string s;
  for (const auto& n : builtin_cell_names()) s += (s.empty() ? "" : ", ") + n;
  return s;
}

[[noreturn]] void bad(const std::string& option, const std::string& value, const std::string& why) {
  throw UsageError(option + " = '" + value + "': " + why);
}

double parse_number(const std::string& option, const std::string& text, const char* unit) {
  const std::string expected = std::string("expected a number") + (*unit ? " in " : "") + unit;
  if (text.empty() || std::isspace(static_cast<unsigned char>(text.front()))) bad(option, text, expected);
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(text.c_str(), &end);
  if (end != text.c_str() + text.size()) bad(option, text, expected);
  if (!std::isfinite(v)) bad(option, text, "must be a finite number");
  return v;
}

double parse_positive(const std::string& option, const std::string& text, const char* unit) {
  const double v = parse_number(option, text, unit);
  if (v <= 0.0) bad(option, text, std::string("must be > 0 ") + unit);
  return v;
}

long long parse_integer(const std::string& option, const std::string& text, long long lo,
                        long long hi) {
  const std::string range = "an integer from " + std::to_string(lo) + " to " + std::to_string(hi);
  std::string t = text;
  if (!t.empty() && t.front() == '+') t.erase(0, 1);
  long long v = 0;
  const auto r = std::from_chars(t.data(), t.data() + t.size(), v);
  if (r.ec == std::errc::result_out_of_range) bad(option, text, "out of range: expected " + range);
  if (r.ec != std::errc() || r.ptr != t.data() + t.size()) bad(option, text, "expected " + range);
  if (v < lo || v > hi) bad(option, text, "out of range: expected " + range);
  return v;
}

std::uint64_t parse_seed(const std::string& option, const std::string& text) {
  std::uint64_t v = 0;
  const auto r = std::from_chars(text.data(), text.data() + text.size(), v);
  if (r.ec != std::errc() || r.ptr != text.data() + text.size())
    bad(option, text, "expected an unsigned 64-bit integer (0 .. 18446744073709551615)");
  return v;
}

Vec3 parse_vec3(const std::string& option, const std::string& text, const char* unit) {
  std::vector<std::string> parts;
  std::size_t pos = 0;
  while (true) {
    const std::size_t comma = text.find(',', pos);
    parts.push_back(text.substr(pos, comma - pos));
    if (comma == std::string::npos) break;
    pos = comma + 1;
  }
  const std::string expected =
      std::string("expected three comma-separated numbers X,Y,Z") + (*unit ? " in " : "") + unit;
  if (parts.size() != 3) bad(option, text, expected + ", got " + std::to_string(parts.size()));
  Vec3 v;
  for (int i = 0; i < 3; ++i) {
    char* end = nullptr;
    const std::string& p = parts[i];
    const double x = p.empty() ? 0.0 : std::strtod(p.c_str(), &end);
    if (p.empty() || std::isspace(static_cast<unsigned char>(p.front())) ||
        end != p.c_str() + p.size())
      bad(option, text, expected + " ('" + p + "' is not a number)");
    if (!std::isfinite(x)) bad(option, text, "must be finite numbers");
    v[i] = x;
  }
  return v;
}

// File-name-safe version of a cell name for the default output file.
std::string file_stem_for(const std::string& name) {
  std::string s = name;
  for (char& c : s)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' || c == '.')) c = '_';
  if (s.empty() || s == "." || s == "..") s = "scan";
  return s;
}

// Everything run_scan needs, checked.
struct ScanPlan {
  Cell cell;
  std::string scene_label;  // cell name or scene file path
  fs::path out;             // absolute
  bool main_is_reference = false;
  bool with_reference = false;
  std::uint64_t seed = 0;
};

ScanPlan plan_scan(const ScanOptions& o) {
  ScanPlan plan;
  if (!o.scene.empty()) {
    try {
      plan.cell = load_scene(o.scene);
    } catch (const SceneError& e) {
      throw UsageError(std::string("--scene: ") + e.what());
    }
    plan.scene_label = o.scene;
  } else {
    const std::string name = o.cell.empty() ? std::string(kDefaultCell) : o.cell;
    auto cell = builtin_cell(name);
    if (!cell) bad("--cell", name, "unknown cell; valid names: " + names_list() + " (see `vts cells`)");
    plan.cell = std::move(*cell);
    plan.scene_label = name;
  }
  Cell& cell = plan.cell;
  ScannerDesc& scanner = cell.scanner;
  ScanPath& path = cell.path;

  // The sensor preset replaces the sensor fields (the scene's material,
  // tool_from_laser and ideal flag stay); then the material; then the
  // individual overrides below.
  if (!o.sensor.empty()) {
    const auto preset = sensor_preset(o.sensor);
    if (!preset)
      bad("--sensor", o.sensor,
          "unknown sensor; valid names: " + join_names(sensor_preset_names()) +
              " (see `vts sensors`)");
    set_sensor_fields(scanner, *preset);
  }
  if (!o.material.empty() && !apply_material(scanner, o.material))
    bad("--material", o.material,
        "unknown material; valid names: " + join_names(material_names()) + " (see `vts sensors`)");
  if (o.ideal) scanner.ideal = true;

  if (!o.standoff.empty()) {
    if (!o.scene.empty())
      bad("--standoff", o.standoff,
          "only applies to built-in cells (--cell); a scene file sets its own path "
          "(path.standoff_mm or path.start)");
    const double standoff = parse_positive("--standoff", o.standoff, "mm");
    const ScanPath derived = default_path(cell.workpieces.front(), standoff);
    path.start = derived.start;
    path.direction = derived.direction;
  }
  if (!o.rate.empty()) scanner.rate_hz = parse_positive("--rate", o.rate, "Hz");
  if (!o.points.empty())
    scanner.points = static_cast<int>(parse_integer("--points", o.points, kMinPoints, kMaxPoints));
  if (!o.direction.empty()) {
    const Vec3 d = parse_vec3("--direction", o.direction, "");
    if (d.norm() < 1e-12) bad("--direction", o.direction, "must not be the zero vector");
    path.direction = d.normalized();
  }
  if (!o.start.empty()) path.start.translation() = parse_vec3("--start", o.start, "mm");
  if (!o.step.empty() && !o.speed.empty())
    throw UsageError("--step and --speed: give one of them, not both");
  if (!o.step.empty()) path.step_mm = parse_positive("--step", o.step, "mm");
  if (!o.speed.empty())
    path.step_mm = parse_positive("--speed", o.speed, "mm/s") / scanner.rate_hz;
  if (!std::isfinite(path.step_mm) || path.step_mm <= 0.0)
    throw UsageError("--speed / --rate: the step speed / rate is not a usable distance");
  if (!o.profiles.empty())
    path.profiles = static_cast<int>(
        parse_integer("--profiles", o.profiles, 1, std::numeric_limits<int>::max()));
  plan.seed = o.seed.empty() ? 0 : parse_seed("--seed", o.seed);

  if (const std::string why = validate(scanner); !why.empty())
    throw UsageError("scanner: " + why);

  const std::string source = o.source.empty() ? "raster" : o.source;
  if (source != "raster" && source != "reference")
    bad("--source", o.source, "expected 'raster' or 'reference'");
  plan.main_is_reference = source == "reference";
  plan.with_reference = o.reference;

  fs::path out = o.out.empty() ? fs::path(file_stem_for(cell.name) + ".exr") : fs::path(o.out);
  std::error_code ec;
  out = fs::absolute(out, ec);
  if (ec) bad("--out", o.out, "cannot make an absolute path: " + ec.message());
  out = out.lexically_normal();
  if (out.filename().empty()) bad("--out", o.out, "names a directory, expected a file name");
  if (fs::is_directory(out, ec)) bad("--out", out.string(), "is a directory, expected a file name");
  // Missing directories are created by the writer; an existing non-directory
  // in the way is a bad value, not a runtime failure.
  for (fs::path dir = out.parent_path(); !dir.empty(); dir = dir.parent_path()) {
    if (fs::exists(dir, ec)) {
      if (!fs::is_directory(dir, ec))
        bad("--out", o.out, "'" + dir.string() + "' exists and is not a directory");
      break;
    }
    if (dir == dir.root_path()) break;
  }
  plan.out = out;
  return plan;
}

// The signal that interrupted the scan (SIGINT or SIGTERM), 0 while running.
volatile std::sig_atomic_t g_interrupted = 0;
extern "C" void on_interrupt(int sig) { g_interrupted = sig; }

struct Interrupted : std::runtime_error {
  explicit Interrupted(int sig) : std::runtime_error("interrupted"), signal(sig) {}
  int signal;
};

// Progress on stderr: every second on a terminal (one line, rewritten); in a
// log only for long runs, every 5 s, one line each. Nothing in between.
class Progress {
 public:
  explicit Progress(int total) : total_(total), tty_(isatty(STDERR_FILENO) == 1) {
    start_ = last_ = std::chrono::steady_clock::now();
  }
  void update(int done) {
    const auto now = std::chrono::steady_clock::now();
    const double interval = tty_ ? 1.0 : 5.0;
    if (std::chrono::duration<double>(now - last_).count() < interval) return;
    last_ = now;
    print(done, now);
  }
  // Completes a line already on the terminal with the final count.
  void done(int done) {
    if (!printed_ || !tty_) return;
    print(done, std::chrono::steady_clock::now());
    std::cerr << '\n';
  }
  double elapsed_s() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }

 private:
  void print(int done, std::chrono::steady_clock::time_point now) {
    const double t = std::chrono::duration<double>(now - start_).count();
    char line[160];
    std::snprintf(line, sizeof line, "scan: %d/%d profiles (%.1f%%), %.0f profiles/s", done, total_,
                  100.0 * done / total_, t > 0 ? done / t : 0.0);
    if (tty_)
      std::cerr << '\r' << line << "\x1b[K" << std::flush;
    else
      std::cerr << line << std::endl;
    printed_ = true;
  }

  int total_;
  bool tty_;
  bool printed_ = false;
  std::chrono::steady_clock::time_point start_, last_;
};

struct Stats {
  std::int64_t samples = 0, valid = 0;
  double range_sum_mm = 0.0;
  std::int64_t both_valid = 0, hit_miss = 0, shadow_disagreements = 0;
  double max_diff_mm = 0.0;
  int max_hit_miss_per_profile = 0;

  // `p` as written; `ideal` and `ideal_ref` the two sources' ideal profiles
  // (the reference check compares geometry, before the error model).
  void add(const Profile& p, const Profile& ideal, const Profile* ideal_ref) {
    samples += p.size();
    for (int i = 0; i < p.size(); ++i) {
      if (!p.valid[i]) continue;
      ++valid;
      range_sum_mm += p.range_mm[i];
    }
    if (!ideal_ref) return;
    const Profile& ref = *ideal_ref;
    int disagreements = 0;
    for (int i = 0; i < ideal.size(); ++i) {
      if (ideal.valid[i] && ref.valid[i]) {
        ++both_valid;
        max_diff_mm = std::max(max_diff_mm, double(std::abs(ideal.range_mm[i] - ref.range_mm[i])));
        shadow_disagreements += ideal.camera_visible[i] != ref.camera_visible[i];
      } else if (ideal.valid[i] != ref.valid[i]) {
        ++disagreements;
      }
    }
    hit_miss += disagreements;
    max_hit_miss_per_profile = std::max(max_hit_miss_per_profile, disagreements);
  }
};

int execute(const ScanPlan& plan) {
  const Cell& cell = plan.cell;
  const ScanPath& path = cell.path;
  const int n = path.profiles;

  // Sources first: a GL failure must not leave anything on disk.
  const Mesh mesh = cell.mesh();
  std::unique_ptr<ProfileSource> main_source, ref_source;
  if (plan.main_is_reference) {
    main_source = make_reference_source(cell.scanner, mesh);
  } else {
    try {
      main_source = make_raster_source(cell.scanner, mesh);
    } catch (const std::exception& e) {
      throw std::runtime_error(std::string("cannot create the raster source (OSMesa): ") + e.what());
    }
  }
  // With --source reference the main channels already hold the reference.
  if (plan.with_reference && !plan.main_is_reference)
    ref_source = make_reference_source(cell.scanner, mesh);

  ProfileFileInfo info;
  info.scanner = cell.scanner;
  info.scene_name = plan.scene_label;
  info.scene_text = scene_to_yaml(cell);
  info.profiles = n;
  info.has_reference = plan.with_reference;
  info.error_model = !cell.scanner.ideal;
  info.seed = plan.seed;

  // SIGINT and SIGTERM stop the scan between batches; the writer's
  // destructor then removes its temporary file, so nothing appears under the
  // output name.
  g_interrupted = 0;
  struct RestoreSignals {
    using Handler = void (*)(int);
    Handler old_int = std::signal(SIGINT, on_interrupt);
    Handler old_term = std::signal(SIGTERM, on_interrupt);
    ~RestoreSignals() {
      std::signal(SIGINT, old_int);
      std::signal(SIGTERM, old_term);
    }
  } restore;

  ProfileExrWriter writer(plan.out, info);
  // A batch: the raster source splits it over its workers (one OpenGL
  // context each), the error model runs on as many threads, then the rows
  // are written in order. Memory stays bounded by the batch, whatever n is.
  constexpr int kBatch = 512;
  const int threads = static_cast<int>(std::clamp(std::thread::hardware_concurrency(), 1u, 16u));
  std::vector<Pose> poses;
  // Ideal profiles from the sources, measured ones from the error model. The
  // draws are keyed by profile index, so both sources see the same ones, and
  // splitting a batch over threads changes nothing.
  std::vector<Profile> main(kBatch), ref(ref_source ? kBatch : 0);
  std::vector<Profile> measured(kBatch), measured_ref(ref_source ? kBatch : 0);
  std::vector<ScanState> states(threads), states_ref(threads);
  for (ScanState& s : states) s.seed = plan.seed;
  for (ScanState& s : states_ref) s.seed = plan.seed;
  const bool model = !cell.scanner.ideal;
  Stats stats;
  Progress progress(n);
  for (int first = 0; first < n; first += kBatch) {
    if (g_interrupted) throw Interrupted(g_interrupted);
    const int count = std::min(kBatch, n - first);
    poses.resize(count);
    for (int k = 0; k < count; ++k) poses[k] = path.pose_at(first + k);
    main_source->scan_batch(poses, std::span(main.data(), count));
    if (ref_source) ref_source->scan_batch(poses, std::span(ref.data(), count));
    for (int k = 0; k < count; ++k) {
      const std::int64_t i = first + k;
      for (Profile* p : {&main[k], ref_source ? &ref[k] : nullptr}) {
        if (!p) continue;
        p->world_from_sensor = poses[k];
        p->time_s = static_cast<double>(i) / cell.scanner.rate_hz;
        p->index = i;
      }
    }
    if (model) {
      auto run = [&](int t, int begin, int end) {
        for (int k = begin; k < end; ++k) {
          apply_error_model(cell.scanner, main[k], states[t], measured[k]);
          if (ref_source) apply_error_model(cell.scanner, ref[k], states_ref[t], measured_ref[k]);
        }
      };
      const int parts = std::clamp(count / 64, 1, threads);
      std::vector<std::jthread> helpers;
      for (int t = 1; t < parts; ++t)
        helpers.emplace_back(run, t, count * t / parts, count * (t + 1) / parts);
      run(0, 0, count / parts);
    }
    for (int k = 0; k < count; ++k) {
      const Profile* out = model ? &measured[k] : &main[k];
      const Profile* reference = nullptr;
      if (plan.with_reference)
        reference = ref_source ? (model ? &measured_ref[k] : &ref[k]) : out;
      writer.write(*out, reference);
      stats.add(*out, main[k], ref_source ? &ref[k] : nullptr);
    }
    progress.update(first + count);
  }
  ScanState state, state_ref;
  state.seed = state_ref.seed = plan.seed;
  for (const ScanState& s : states) add_counts(state, s);
  for (const ScanState& s : states_ref) add_counts(state_ref, s);
  writer.finish();
  progress.done(n);

  const double t = progress.elapsed_s();
  std::printf("wrote %d profiles x %d points to %s\n", n, cell.scanner.points, plan.out.c_str());
  std::printf("%s: %.1f%% of %lld samples valid, mean range %.3f mm; %.2f s (%.0f profiles/s)\n",
              plan.main_is_reference ? "reference" : "raster",
              stats.samples ? 100.0 * stats.valid / stats.samples : 0.0,
              static_cast<long long>(stats.samples),
              stats.valid ? stats.range_sum_mm / stats.valid : 0.0, t, t > 0 ? n / t : 0.0);
  if (model) {
    auto ll = [](std::int64_t v) { return static_cast<long long>(v); };
    std::printf(
        "error model (%s, %s, seed %llu): of %lld lit points %lld measured; lost: %lld camera "
        "shadow, %lld outside the region, %lld grazing, %lld outside the image, %lld dropouts; "
        "outliers: %lld shiny, %lld rough\n",
        cell.scanner.name.c_str(), cell.scanner.material.c_str(),
        static_cast<unsigned long long>(plan.seed), ll(state.lit), ll(state.measured),
        ll(state.shadowed), ll(state.outside_roi), ll(state.grazing), ll(state.outside_image),
        ll(state.dropouts), ll(state.shiny_outliers), ll(state.rough_outliers));
  }
  if (ref_source)
    std::printf(
        "reference check (ideal profiles): max |range - ref.range| = %.6f mm over %lld samples "
        "valid in both; %lld hit/miss disagreements (at most %d in one profile); %lld camera "
        "shadow disagreements\n",
        stats.max_diff_mm, static_cast<long long>(stats.both_valid),
        static_cast<long long>(stats.hit_miss), stats.max_hit_miss_per_profile,
        static_cast<long long>(stats.shadow_disagreements));
  std::fflush(stdout);
  return kExitOk;
}

}  // namespace

CLI::App* add_scan_command(CLI::App& app, ScanOptions& o) {
  CLI::App* scan = app.add_subcommand(
      "scan",
      "Scan a cell along its path and write the profiles to an EXR file.\n"
      "Profile i is taken at start + i * step * direction (orientation fixed), at time i / rate.");
  scan->option_defaults()->always_capture_default(false);

  auto* cell = scan->add_option("--cell", o.cell,
                                "Built-in cell to scan (list: `vts cells`): fillet, corner, lap, butt, "
                                "vgroove, plate, static-A .. static-F. Default: static-B")
                   ->type_name("NAME");
  auto* scene = scan->add_option("--scene", o.scene,
                                 "Scene file to scan instead of a built-in cell (YAML, "
                                 "docs/SCENE_FORMAT.md)")
                    ->type_name("FILE");
  cell->excludes(scene);
  scene->excludes(cell);

  scan->add_option("--start", o.start,
                   "Sensor (laser origin) position at profile 0, mm, world frame; the path's "
                   "sensor orientation is kept. Negative values: --start=-10,0,80")
      ->type_name("X,Y,Z");
  scan->add_option("--direction", o.direction,
                   "Travel direction, world frame (normalised, must not be zero); the sensor "
                   "orientation is kept")
      ->type_name("X,Y,Z");
  auto* step = scan->add_option("--step", o.step, "Distance between profiles along --direction, mm (> 0)")
                   ->type_name("MM");
  auto* speed = scan->add_option("--speed", o.speed,
                                 "Travel speed, mm/s (> 0): step = speed / rate (rate from --rate, "
                                 "else the cell's scanner)")
                    ->type_name("MM_PER_S");
  step->excludes(speed);
  speed->excludes(step);
  scan->add_option("--rate", o.rate,
                   "Profile rate, Hz (> 0): sets scanner.rate_hz; profile i is stamped "
                   "time = i / rate s")
      ->type_name("HZ");
  scan->add_option("--profiles", o.profiles, "Number of profiles (rows in the file), >= 1")
      ->type_name("N");
  scan->add_option("--standoff", o.standoff,
                   "Built-in cells only: re-derive the path's start and direction at this "
                   "distance, mm, from the laser origin to the seam root along the optical axis")
      ->type_name("MM");
  scan->add_option("--points", o.points, "Points (columns) per profile, 16..4096")->type_name("N");
  scan->add_option("--seed", o.seed,
                   "Seed of the sensor error model's random draws, unsigned 64-bit integer "
                   "(default 0); the same seed gives the same file, byte for byte")
      ->type_name("S");
  scan->add_option("--sensor", o.sensor,
                   "Sensor preset (list: `vts sensors`): mspot (default), lps-2048-short, "
                   "lps-1280-mid. Replaces the cell's or scene's sensor fields")
      ->type_name("NAME");
  scan->add_option("--material", o.material,
                   "Surface material preset: matte-steel (default), shiny-steel, aluminium, rough, "
                   "lambertian (see `vts sensors`)")
      ->type_name("NAME");
  scan->add_flag("--ideal", o.ideal,
                 "Error model off: write the ideal geometric profiles (no camera, noise, "
                 "quantization, shadow, outliers or dropouts)");
  scan->add_option("--out", o.out,
                   "Output profile file (EXR, docs/EXR_FORMAT.md). Default: <cell name>.exr in "
                   "the current directory")
      ->type_name("FILE.exr");
  scan->add_flag("--reference", o.reference,
                 "Also scan with the Embree ray-cast reference and store it in the ref.* channels");
  scan->add_option("--source", o.source,
                   "Which source fills the main channels: raster (OSMesa emulator, default) or "
                   "reference (Embree ray caster)")
      ->type_name("raster|reference");
  return scan;
}

// One line per mesh workpiece on stderr: what its file held (docs/SCENE_FORMAT.md).
static void report_mesh_workpieces(const Cell& cell) {
  for (std::size_t i = 0; i < cell.workpieces.size(); ++i) {
    const MeshLoadStats& s = cell.workpieces[i].mesh_stats;
    if (!cell.workpieces[i].is_mesh()) continue;
    std::cerr << "vts scan: workpieces[" << i << "]: mesh " << s.file << ": " << s.triangles_kept
              << " triangles, " << s.skipped_degenerate << " degenerate skipped, " << s.open_edges
              << " open edges\n";
  }
}

int run_scan(const ScanOptions& opts) {
  const ScanPlan plan = plan_scan(opts);  // throws UsageError; nothing created yet
  report_mesh_workpieces(plan.cell);
  try {
    return execute(plan);
  } catch (const Interrupted& e) {
    std::cerr << (isatty(STDERR_FILENO) == 1 ? "\n" : "") << "vts scan: interrupted by "
              << (e.signal == SIGTERM ? "SIGTERM" : "SIGINT") << "; nothing was written to "
              << plan.out.string() << "\n";
    // The shell's convention: 128 + the signal number (130 SIGINT, 143 SIGTERM).
    return 128 + e.signal;
  }
}

}  // namespace vts::cli
