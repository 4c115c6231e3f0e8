#include "apps/vts_export.h"

#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <string>

#include "apps/cli.h"
#include "sensor/profile_exr.h"
#include "sensor/profile_export.h"

namespace vts::apps {
namespace {

namespace fs = std::filesystem;

struct ExportOptions {
  std::string input, out, format;
};

int run_export(const ExportOptions& o) {
  // Everything is checked before anything is written.
  std::optional<ExportFormat> format;
  if (!o.format.empty()) {
    format = export_format_named(o.format);
    if (!format) cli::bad("--format", o.format, "expected csv, ply or npz");
  } else {
    format = export_format_of(o.out);
    if (!format)
      cli::bad("--out", o.out,
               "unknown output type '" + fs::path(o.out).extension().string() +
                   "': expected .csv, .ply or .npz, or give --format csv|ply|npz");
  }
  cli::check_output_file("--out", o.out);
  ProfileRecording rec;
  try {
    rec = read_profile_exr(o.input);
  } catch (const ExrError& e) {
    throw cli::UsageError(e.what());
  }
  export_recording(rec, o.out, *format);  // ExportError: a runtime failure (exit 1)
  std::size_t points = 0;
  for (const Profile& p : rec.profiles) points += static_cast<std::size_t>(p.valid_count());
  std::printf("wrote %zu profiles (%zu valid points) of %s to %s (%s)\n", rec.profiles.size(), points,
              o.input.c_str(), o.out.c_str(), export_format_name(*format));
  return cli::kExitOk;
}

}  // namespace

CLI::App* add_export_command(CLI::App& app, int& exit_code) {
  auto o = std::make_shared<ExportOptions>();
  CLI::App* cmd = app.add_subcommand(
      "export",
      "Write a profile EXR as CSV (the columns vts track reads), a PLY point cloud (world frame, mm) or NumPy "
      ".npz arrays, by the extension of --out or by --format");
  cmd->option_defaults()->always_capture_default(false);
  cmd->add_option("file", o->input, "vts profile EXR (docs/EXR_FORMAT.md)")->required()->type_name("FILE.exr");
  cmd->add_option("--out", o->out,
                  "File to write: OUT.csv, OUT.ply or OUT.npz; written whole or not at all. The directory must exist")
      ->required()
      ->type_name("OUT");
  cmd->add_option("--format", o->format, "csv, ply or npz, whatever the extension of --out")->type_name("FORMAT");
  cmd->callback([o, &exit_code] {
    try {
      exit_code = run_export(*o);
    } catch (const cli::UsageError& e) {
      std::cerr << "vts export: " << e.what() << "\n";
      exit_code = cli::kExitUsage;
    } catch (const ExportError& e) {
      std::cerr << "vts export: " << e.what() << "\n";
      exit_code = cli::kExitRuntime;
    }
  });
  return cmd;
}

}  // namespace vts::apps
