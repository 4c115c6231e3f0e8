#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <limits>
#include <string>

#include "apps/vts_scan.h"
#include "pipeline/scan_job.h"
#include "pipeline/sinks.h"
#include "sensor/cell.h"
#include "sensor/presets.h"

namespace vts::cli {
namespace {

namespace fs = std::filesystem;

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
  ScanSpec spec;
  fs::path out;  // absolute
  ExrCompression compression = ExrCompression::Zip;
};

ScanPlan plan_scan(const ScanOptions& o) {
  ScanPlan plan;
  ScanSpec& spec = plan.spec;
  NamedCell named = load_cell(o.cell, o.scene);
  spec.cell = std::move(named.cell);
  spec.scene_label = std::move(named.label);
  Cell& cell = spec.cell;
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
  if (o.camera_image) {
    if (o.ideal) bad("--camera-image", "", "cannot be combined with --ideal (the image has no ideal mode)");
    scanner.camera_image = true;
  }
  if (!o.images.empty()) {
    if (!scanner.camera_image) bad("--images", o.images, "needs --camera-image (the images are its)");
    spec.images_dir = o.images;
  }

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
  spec.seed = o.seed.empty() ? 0 : parse_seed("--seed", o.seed);

  if (const std::string why = validate(scanner); !why.empty())
    throw UsageError("scanner: " + why);

  spec.source = parse_source("--source", o.source.empty() ? "raster" : o.source);
  spec.with_reference = o.reference;
  if (!o.compression.empty()) {
    const auto compression = exr_compression_from_string(o.compression);
    if (!compression)
      bad("--compression", o.compression, "unknown compression; valid: " + join_names(exr_compression_names()));
    plan.compression = *compression;
  }

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
  apply_thread_limit(o.threads);
  return plan;
}

void report(const ScanPlan& plan, const ScanStats& stats) {
  const ScanSpec& spec = plan.spec;
  const ScannerDesc& scanner = spec.cell.scanner;
  const int n = spec.cell.path.profiles;
  const double t = stats.elapsed_s;
  std::printf("wrote %d profiles x %d points to %s\n", n, scanner.points, plan.out.c_str());
  std::printf("%s: %.1f%% of %lld samples valid, mean range %.3f mm; %.2f s (%.0f profiles/s)\n",
              std::string(to_string(spec.source)).c_str(), stats.valid_percent(),
              static_cast<long long>(stats.samples), stats.mean_range_mm(), t, t > 0 ? n / t : 0.0);
  auto ll = [](std::int64_t v) { return static_cast<long long>(v); };
  if (!scanner.ideal && scanner.camera_image) {
    std::printf("camera image (%s, %s, seed %llu): profiles read from the rendered stripe, peaks by %s, %s%s%s\n",
                scanner.name.c_str(), scanner.material.c_str(), static_cast<unsigned long long>(spec.seed),
                scanner.peak_method.c_str(), scanner.peak_policy.c_str(),
                spec.images_dir.empty() ? "" : "; images and labels in ", spec.images_dir.string().c_str());
  } else if (!scanner.ideal) {
    const ScanState& s = stats.error_model;
    std::printf(
        "error model (%s, %s, seed %llu): of %lld lit points %lld measured; lost: %lld camera "
        "shadow, %lld outside the region, %lld grazing, %lld outside the image, %lld dropouts; "
        "outliers: %lld shiny, %lld rough\n",
        scanner.name.c_str(), scanner.material.c_str(), static_cast<unsigned long long>(spec.seed), ll(s.lit),
        ll(s.measured), ll(s.shadowed), ll(s.outside_roi), ll(s.grazing), ll(s.outside_image), ll(s.dropouts),
        ll(s.shiny_outliers), ll(s.rough_outliers));
  }
  if (spec.with_reference && spec.source == SourceKind::Raster)
    std::printf(
        "reference check (ideal profiles): max |range - ref.range| = %.6f mm over %lld samples "
        "valid in both; %lld hit/miss disagreements (at most %d in one profile); %lld camera "
        "shadow disagreements\n",
        stats.max_diff_mm, ll(stats.both_valid), ll(stats.hit_miss), stats.max_hit_miss_per_profile,
        ll(stats.shadow_disagreements));
  std::fflush(stdout);
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
                                "vgroove, plate, static-A .. static-F, the grooves (bevel, ugroove, ...). "
                                "Default: static-B")
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
  scan->add_flag("--camera-image", o.camera_image,
                 "Profiles from the camera's image instead of the error model: the stripe rendered "
                 "as the sensor's camera sees it (sheet thickness, reflectance, one bounce of "
                 "laser light, the stripe mirrored in the part's planes, speckle, noise, saturation) and its peaks detected per column "
                 "(docs/SENSOR_MODEL.md, \"The camera image\")");
  scan->add_option("--images", o.images,
                   "With --camera-image: also write each profile's image (PNG) and its labels "
                   "(CSV: true stripe row, bounce and mirror rows, which peak is true, which was chosen) into DIR")
      ->type_name("DIR");
  scan->add_option("--out", o.out,
                   "Output profile file (EXR, docs/EXR_FORMAT.md). Default: <cell name>.exr in "
                   "the current directory")
      ->type_name("FILE.exr");
  scan->add_option("--compression", o.compression,
                   "How the EXR is compressed, all lossless: zip (default; zlib over 16 rows, the "
                   "smallest files), zips (zlib row by row), piz (wavelet + Huffman), rle (run "
                   "lengths), none (stored: the fastest to write and read, about 3 times the size "
                   "of zip on profiles that hit)")
      ->type_name("zip|zips|piz|rle|none");
  scan->add_flag("--reference", o.reference,
                 "Also scan with the Embree ray-cast reference and store it in the ref.* channels");
  scan->add_option("--source", o.source,
                   "Which source fills the main channels: raster (OSMesa emulator, default) or "
                   "reference (Embree ray caster)")
      ->type_name("raster|reference");
  scan->add_option("--threads", o.threads, kThreadsHelp)->type_name("N");
  return scan;
}

// One line per mesh workpiece on stderr: what its file held (docs/SCENE_FORMAT.md).
static void report_mesh_workpieces(const Cell& cell) {
  for (std::size_t i = 0; i < cell.workpieces.size(); ++i) {
    const MeshLoadStats& s = cell.workpieces[i].mesh_stats;
    if (!cell.workpieces[i].is_mesh() || cell.workpieces[i].saddle) continue;  // a saddle is built, not read
    std::cerr << "vts scan: workpieces[" << i << "]: mesh " << s.file << ": " << s.triangles_kept
              << " triangles, " << s.skipped_degenerate << " degenerate skipped, " << s.open_edges
              << " open edges\n";
  }
}

int run_scan(const ScanOptions& opts) {
  const ScanPlan plan = plan_scan(opts);  // throws UsageError; nothing created yet
  report_mesh_workpieces(plan.spec.cell);
  // SIGINT and SIGTERM cancel the job between batches; the sink then removes
  // its temporary file, so nothing appears under the output name.
  const SignalCancel signals;
  ProgressLine progress("scan", plan.spec.cell.path.profiles);
  ScanCallbacks callbacks;
  callbacks.cancelled = &SignalCancel::cancelled;
  callbacks.progress = [&](std::int64_t done, std::int64_t, const ScanStats&) { progress.update(done); };
  try {
    ExrSink sink(plan.out, plan.compression);
    const ScanStats stats = run_scan_job(plan.spec, sink, callbacks);
    progress.done(plan.spec.cell.path.profiles);
    report(plan, stats);
    return kExitOk;
  } catch (const Cancelled&) {
    std::cerr << (isatty(STDERR_FILENO) == 1 ? "\n" : "") << "vts scan: interrupted by "
              << SignalCancel::signal_name() << "; nothing was written to " << plan.out.string() << "\n";
    // The shell's convention: 128 + the signal number (130 SIGINT, 143 SIGTERM).
    return 128 + SignalCancel::signal();
  }
}

}  // namespace vts::cli
