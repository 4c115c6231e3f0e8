#include "apps/vts_static.h"

#include <charconv>
#include <filesystem>
#include <iostream>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "apps/cli.h"
#include "pipeline/groove_passes.h"
#include "pipeline/static_experiment.h"

namespace vts::apps {
namespace {

namespace fs = std::filesystem;

struct StaticOptions {
  std::string out_dir = "static";
  std::string profiles = "10";
  std::string seed;
  std::string source = "raster";
  std::string threads;
  bool ideal = false;
};

int run_static(const StaticOptions& o) {
  StaticSpec spec;
  {
    const auto r = std::from_chars(o.profiles.data(), o.profiles.data() + o.profiles.size(), spec.profiles);
    if (r.ec != std::errc() || r.ptr != o.profiles.data() + o.profiles.size() || spec.profiles < 1 ||
        spec.profiles > 100000)
      cli::bad("--profiles", o.profiles, "expected an integer from 1 to 100000");
  }
  if (!o.seed.empty()) spec.seed = cli::parse_seed("--seed", o.seed);
  spec.source = cli::parse_source("--source", o.source);
  spec.ideal = o.ideal;
  const fs::path dir = fs::absolute(o.out_dir).lexically_normal();
  {
    std::error_code ec;
    if (fs::exists(dir, ec) && !fs::is_directory(dir, ec)) cli::bad("--out-dir", o.out_dir, "exists and is not a directory");
  }
  cli::apply_thread_limit(o.threads);

  // Scan and track everything first: a failure leaves no files behind.
  const StaticResult result = run_static_experiment(spec);
  const std::string md = static_table_markdown(result);
  std::vector<plot::Canvas> pictures;
  for (const StaticRow& r : result.rows) pictures.push_back(static_figure(r, result.conditions));
  // The built-in groove cells (issue 18), each with its own beads, read by
  // the groove model at its own preset and standoff.
  std::vector<GroovePassRun> grooves;
  for (const std::string& name : builtin_cell_names(CellSet::Small)) {
    auto cell = builtin_cell(name);
    if (!cell || cell->workpieces.size() != 1 || !is_groove(cell->workpieces.front().type)) continue;
    GroovePassSpec g;
    g.cell = *cell;
    g.cell.scanner.ideal = spec.ideal;
    g.first_pass = g.cell.workpieces.front().params.passes;
    g.profiles = spec.profiles;
    g.source = spec.source;
    g.seed = spec.seed;
    g.fill = FillMode::Model;  // one scan of the cell as built: no bead laid after it
    grooves.push_back(run_groove_passes(g));
  }
  const std::string grooves_md = groove_cells_markdown(grooves);

  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw std::runtime_error("cannot create directory " + dir.string() + ": " + ec.message());
  cli::write_text_file(dir / "table3.csv", static_table_csv(result));
  cli::write_text_file(dir / "table3.md", "# The paper's static experiment (Table 3)\n\n" + md);
  for (std::size_t i = 0; i < result.rows.size(); ++i) {
    const fs::path png = dir / (std::string("static-") + result.rows[i].label + ".png");
    if (const std::string err = pictures[i].save_png(png); !err.empty()) throw std::runtime_error(err);
  }
  cli::write_text_file(dir / "grooves.md", "# The groove cells (docs/JOINTS.md, \"Grooves and fill\")\n\n" +
                                               result.conditions + "\n\n" + grooves_md);
  std::cout << md;
  for (const StaticRow& r : result.rows)
    if (r.ok < r.profiles) std::cout << "static-" << r.label << ": " << r.first_reason << "\n";
  std::cout << "\nThe groove cells, each with its own beads:\n\n" << grooves_md;
  std::cout << "\nwrote table3.csv, table3.md, grooves.md and static-A.png .. static-F.png to " << dir.string()
            << "\n";
  return cli::kExitOk;
}

}  // namespace

CLI::App* add_static_command(CLI::App& app, int& exit_code) {
  auto o = std::make_shared<StaticOptions>();
  CLI::App* cmd = app.add_subcommand(
      "static",
      "The paper's static experiment: scan setups static-A .. static-F, track them with the fillet template "
      "and write Table 3 (CSV, Markdown) and one PNG per setup (Figure 7) to --out-dir");
  cmd->option_defaults()->always_capture_default(false);
  cmd->add_option("--out-dir", o->out_dir, "Output directory, created if missing (default: static)")
      ->type_name("DIR");
  cmd->add_option("--profiles", o->profiles,
                  "Profiles scanned per setup, 0.5 mm apart along the seam (default 10); the table reports "
                  "medians over the accepted ones")
      ->type_name("N");
  cmd->add_option("--seed", o->seed, "Seed of the sensor error model (default 1)")->type_name("S");
  cmd->add_flag("--ideal", o->ideal, "Error model off: track the ideal geometric profiles");
  cmd->add_option("--source", o->source,
                  "Profile source: raster (OSMesa emulator, default) or reference (Embree ray caster)")
      ->type_name("raster|reference");
  cmd->add_option("--threads", o->threads, cli::kThreadsHelp)->type_name("N");
  cmd->callback([o, &exit_code] {
    try {
      exit_code = run_static(*o);
    } catch (const cli::UsageError& e) {
      std::cerr << "vts static: " << e.what() << "\n";
      exit_code = cli::kExitUsage;
    }
  });
  return cmd;
}

}  // namespace vts::apps
