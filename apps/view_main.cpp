// vts-view: the interactive viewer (README "Viewer"; --help lists the
// options). The options are parsed and checked here; viewer/window.h runs
// the window.
#include <iostream>
#include <optional>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

#include <CLI/CLI.hpp>

#include "common/parallel.h"
#include "sensor/presets.h"
#include "viewer/window.h"

namespace {

using namespace vts::viewer;

constexpr int kExitOk = 0;
constexpr int kExitRuntime = 1;
constexpr int kExitUsage = 2;

struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

std::pair<int, int> parse_size(const std::string& text) {
  int w = 0, h = 0;
  char x = 0, extra = 0;
  if (std::sscanf(text.c_str(), "%d%c%d%c", &w, &x, &h, &extra) != 3 || (x != 'x' && x != 'X'))
    throw UsageError("--size = '" + text + "': expected WIDTHxHEIGHT in pixels, e.g. 1280x720");
  if (w < 320 || h < 240 || w > 8192 || h > 8192)
    throw UsageError("--size = '" + text + "': width must be 320..8192 and height 240..8192 pixels");
  return {w, h};
}

int run(int argc, char** argv) {
  WindowOptions o;
  std::string size = "1280x720", keys;
  CLI::App cli{
      "vts-view: the cell in 3D (workpiece, torch, sensor, laser fan, lit line, camera) with the "
      "current profile and the tracker's output after the paper's Figure 7. The keyboard drives the "
      "torch (H lists the keys); the sensor scans at its rate of simulated time.",
      "vts-view"};
  cli.option_defaults()->always_capture_default(false);
  auto* cell = cli.add_option("--cell", o.app.cell,
                              "Built-in cell (`vts cells`): fillet, corner, lap, butt, vgroove, plate, "
                              "static-A .. static-F, the grooves (bevel, ugroove, ...). Default: static-B")
                   ->type_name("NAME");
  auto* scene = cli.add_option("--scene", o.app.scene, "Scene file (YAML, docs/SCENE_FORMAT.md)")
                    ->type_name("FILE");
  cell->excludes(scene);
  scene->excludes(cell);
  auto* sim = cli.add_flag("--sim", o.sim,
                           "Show the run of `vts sim` (docs/SIM.md): the master welding the box cell's two "
                           "seams, with --seed (default 1 here), --sensor, --material and --ideal as there; the torch follows "
                           "the master's poses on the viewer's clock, the keys only move the camera");
  sim->excludes(cell);
  sim->excludes(scene);
  auto* scenario = cli.add_option("--scenario", o.scenario,
                                  "With --sim: show this scenario's run (`vts sim --scenarios`, or a scenario file), "
                                  "the robot arm drawn when it has one")
                       ->type_name("NAME|FILE.yaml");
  scenario->needs(sim);
  std::string source = "raster";
  cli.add_option("--source", source, "Profile source: raster (OSMesa emulator, default) or reference (Embree)")
      ->type_name("KIND");
  cli.add_option("--sensor", o.sensor,
                 "Sensor preset (sensor/presets.h): mspot, lps-2048-short, "
                 "lps-1280-mid. Default: the cell's scanner")
      ->type_name("NAME");
  cli.add_option("--material", o.material, "Surface material preset for the error model, e.g. shiny-steel")
      ->type_name("NAME");
  auto* ideal = cli.add_flag("--ideal", o.ideal, "Start with the error model off (ideal geometric profiles)");
  cli.add_flag("--camera-image", o.camera_image,
               "Start in the camera-image mode: profiles read from the rendered stripe image, the image shown under "
               "the 3D view with the true stripe and the detected peaks (key I toggles it)")
      ->excludes(ideal);
  cli.add_option("--seed", o.app.seed, "Seed of the error model's random draws (default 0)")->type_name("N");
  cli.add_option("--record", o.app.record,
                 "File for the first recording started with P (later ones get -2, -3, ...). "
                 "Default: vts-view-CELL-YYYYmmdd-HHMMSS.exr in the working directory")
      ->type_name("FILE");
  cli.add_option("--screenshot", o.screenshot,
                 "After the last frame, write the window to this PNG and exit (needs an X display: "
                 "xvfb-run -a -s '-screen 0 1280x1024x24' vts-view ...)")
      ->type_name("PNG");
  cli.add_option("--frames", o.frames,
                 "Run this many frames and exit (default with --screenshot or --keys: the key "
                 "script's length + 3). Each frame is 1/30 s of simulated time and waits for its scans "
                 "(reproducible pictures), except with --fps")
      ->type_name("N")
      ->check(CLI::Range(1, 10000000));
  cli.add_option("--keys", keys,
                 "Key script, one token per frame: key names (w s a d r f q e z c t g plus minus h "
                 "space p m v backspace home b escape), 'a+b' for two keys in one frame, '_' for no "
                 "key, 'TOKEN*N' to repeat; e.g. \"w*30 _ d*10\"")
      ->type_name("SEQUENCE");
  cli.add_option("--size", size, "Window size in pixels, default 1280x720")->type_name("WxH");
  cli.add_flag("--fps", o.fps,
               "Print the frame rate at exit (frames after the first 10); the simulation then runs on "
               "real time with scans in the background, as interactively");
  std::optional<int> threads;
  cli.add_option("--threads", threads,
                 "Most threads the scans work with (default: $VTS_THREADS, else every hardware thread; never "
                 "more than the hardware has); the window's thread comes on top")
      ->type_name("N")
      ->check(CLI::Range(1, 1024));

  try {
    cli.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = cli.exit(e);
    return code == 0 ? kExitOk : kExitUsage;
  }

  // vts sim's default seed, so that `vts-view --sim` shows `vts sim`'s run.
  if (o.sim && cli.count("--seed") == 0) o.app.seed = 1;
  std::vector<KeyFrame> script;
  int width = 0, height = 0;
  try {
    script = parse_key_script(keys);
    std::tie(width, height) = parse_size(size);
    if (source != "raster" && source != "reference")
      throw UsageError("--source = '" + source + "': expected 'raster' or 'reference'");
    o.source = source == "raster" ? vts::SourceKind::Raster : vts::SourceKind::Reference;
    if (!o.sensor.empty() && !vts::sensor_preset(o.sensor))
      throw UsageError("--sensor = '" + o.sensor + "': unknown preset; valid names: " +
                       vts::join_names(vts::sensor_preset_names()));
    if (!o.material.empty()) {
      vts::ScannerDesc probe;
      if (!vts::apply_material(probe, o.material))
        throw UsageError("--material = '" + o.material + "': unknown material; valid names: " +
                         vts::join_names(vts::material_names()));
    }
    if (threads)
      vts::set_thread_limit(*threads);
    else
      vts::thread_limit_from_environment();  // throws std::invalid_argument for a bad value
    if (o.frames && *o.frames < static_cast<int>(script.size()))
      throw UsageError("--frames = " + std::to_string(*o.frames) + ": the --keys script needs " +
                       std::to_string(script.size()) + " frames");
  } catch (const std::invalid_argument& e) {
    std::cerr << "vts-view: " << e.what() << "\n";
    return kExitUsage;
  } catch (const UsageError& e) {
    std::cerr << "vts-view: " << e.what() << "\n";
    return kExitUsage;
  }
  o.script = std::move(script);
  o.width = width;
  o.height = height;
  return run_window(std::move(o));
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::fflush(stdout);
    std::cerr << "vts-view: error: " << e.what() << "\n";
    return kExitRuntime;
  }
}
