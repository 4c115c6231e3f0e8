#pragma once
// `vts scan`: runs a cell's scan path through a profile source and writes the
// profiles to an EXR file (docs/CLI.md).
#include <stdexcept>
#include <string>

#include <CLI/CLI.hpp>

namespace vts::cli {

// Exit codes: 0 success, 1 runtime failure (GL, EXR write), 2 bad input
// (option value, scene file). 128 + the signal when interrupted: 130 SIGINT,
// 143 SIGTERM.
inline constexpr int kExitOk = 0;
inline constexpr int kExitRuntime = 1;
inline constexpr int kExitUsage = 2;

// A bad option value or input file, found before any output is created.
struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

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
  bool reference = false;
  bool ideal = false;
};

// Adds the `scan` subcommand to app; the options are written into opts.
CLI::App* add_scan_command(CLI::App& app, ScanOptions& opts);

// Runs the scan; returns the exit code. Throws UsageError (before creating
// any file) for bad input; runtime failures throw other exceptions.
int run_scan(const ScanOptions& opts);

}  // namespace vts::cli
