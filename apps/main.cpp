// vts: command-line front end (docs/CLI.md).
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <iostream>
#include <string>

#include <CLI/CLI.hpp>

#include "apps/cli.h"
#include "apps/vts_export.h"
#include "apps/vts_dataset.h"
#include "apps/vts_scan.h"
#include "apps/vts_score.h"
#include "apps/vts_mesh.h"
#include "apps/vts_peaks.h"
#include "apps/vts_plot.h"
#include "apps/vts_sensors.h"
#include "apps/vts_serve.h"
#include "apps/vts_sim.h"
#include "apps/vts_static.h"
#include "apps/vts_track.h"
#include "common/version.h"
#include "sensor/cell.h"


namespace {

int list_cells() {
  std::size_t width = 0;
  for (const auto& name : vts::builtin_cell_names()) width = std::max(width, name.size());
  for (const auto& name : vts::builtin_cell_names()) {
    std::string padded = name;
    padded.resize(width, ' ');
    std::cout << padded << "  " << vts::builtin_cell_description(name)
              << (name == vts::kDefaultCell ? " (default)" : "") << "\n";
  }
  return vts::cli::kExitOk;
}

int run(int argc, char** argv) {
  CLI::App app{"vts: virtual laser-triangulation seam sensor emulator for robotic arc welding.\n"
               "Lengths are in mm, angles in degrees, rates in Hz.",
               "vts"};
  app.set_version_flag("--version", "vts " + std::string(vts::version()));
  app.require_subcommand(0, 1);

  vts::cli::ScanOptions scan_options;
  CLI::App* scan = vts::cli::add_scan_command(app, scan_options);
  CLI::App* cells = app.add_subcommand("cells", "List the built-in cells, one line each");
  int plot_exit = vts::cli::kExitOk;
  CLI::App* plot = vts::apps::add_plot_command(app, plot_exit);  // runs from its callback
  int sensors_exit = vts::cli::kExitOk;
  CLI::App* sensors = vts::apps::add_sensors_command(app, sensors_exit);
  int track_exit = vts::cli::kExitOk;
  CLI::App* track = vts::apps::add_track_command(app, track_exit);  // runs from its callback
  int score_exit = vts::cli::kExitOk;
  CLI::App* score = vts::apps::add_score_command(app, score_exit);  // runs from its callback
  int static_exit = vts::cli::kExitOk;
  CLI::App* static_cmd = vts::apps::add_static_command(app, static_exit);  // runs from its callback
  int sim_exit = vts::cli::kExitOk;
  CLI::App* sim = vts::apps::add_sim_command(app, sim_exit);  // runs from its callback
  int mesh_exit = vts::cli::kExitOk;
  CLI::App* mesh = vts::apps::add_mesh_command(app, mesh_exit);  // runs from its callback
  int export_exit = vts::cli::kExitOk;
  CLI::App* export_cmd = vts::apps::add_export_command(app, export_exit);  // runs from its callback
  int dataset_exit = vts::cli::kExitOk;
  CLI::App* dataset = vts::apps::add_dataset_command(app, dataset_exit);  // runs from its callback
  int serve_exit = vts::cli::kExitOk;
  CLI::App* serve = vts::apps::add_serve_command(app, serve_exit);  // runs from its callback
  int peaks_exit = vts::cli::kExitOk;
  CLI::App* peaks = vts::apps::add_peaks_command(app, peaks_exit);  // runs from its callback

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // Help and --version exit 0; every parse error is a usage error.
    const int code = app.exit(e);
    return code == 0 ? vts::cli::kExitOk : vts::cli::kExitUsage;
  }

  if (scan->parsed()) {
    try {
      return vts::cli::run_scan(scan_options);
    } catch (const vts::cli::UsageError& e) {
      std::cerr << "vts scan: " << e.what() << "\n";
      return vts::cli::kExitUsage;
    }
  }
  if (cells->parsed()) return list_cells();
  if (plot->parsed()) return plot_exit;
  if (track->parsed()) return track_exit;
  if (score->parsed()) return score_exit;
  if (static_cmd->parsed()) return static_exit;
  if (sensors->parsed()) return sensors_exit;
  if (sim->parsed()) return sim_exit;
  if (mesh->parsed()) return mesh_exit;
  if (export_cmd->parsed()) return export_exit;
  if (dataset->parsed()) return dataset_exit;
  if (serve->parsed()) return serve_exit;
  if (peaks->parsed()) return peaks_exit;
  std::cout << app.help();
  return vts::cli::kExitOk;
}

}  // namespace

int main(int argc, char** argv) {
  // llvmpipe's own rasterizer threads slow one-row targets down (stack.md);
  // a user's explicit setting wins.
  ::setenv("LP_NUM_THREADS", "0", 0);
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::fflush(stdout);
    std::cerr << "vts: error: " << e.what() << "\n";
    return vts::cli::kExitRuntime;
  } catch (...) {
    std::cerr << "vts: error: unknown exception\n";
    return vts::cli::kExitRuntime;
  }
}
