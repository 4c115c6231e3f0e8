#pragma once
// `vts scan`: parses the options into a scan job (pipeline/scan_job.h) that
// writes the profiles to an EXR file, and prints its report (docs/CLI.md).
#include <string>

#include <CLI/CLI.hpp>

#include "apps/cli.h"

namespace vts::cli {

// Raw option text; run_scan() parses and checks every value so that its
// messages name the option and the value. Empty means "not given".
struct ScanOptions {
  std::string cell;
  std::string scene;
  std::string start;
  std::string direction;
  std::string step;
  std::string speed;
  std::string rate;
  std::string profiles;
  std::string standoff;
  std::string points;
  std::string seed;
  std::string sensor;
  std::string material;
  std::string out;
  std::string source;
  std::string threads;
  std::string compression;
  bool reference = false;
  bool ideal = false;
  bool camera_image = false;
  std::string images;
};

// Adds the `scan` subcommand to app; the options are written into opts.
CLI::App* add_scan_command(CLI::App& app, ScanOptions& opts);

// Runs the scan; returns the exit code. Throws UsageError (before creating
// any file) for bad input; runtime failures throw other exceptions.
int run_scan(const ScanOptions& opts);

}  // namespace vts::cli
