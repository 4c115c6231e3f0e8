#include "apps/vts_dataset.h"

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <iostream>
#include <limits>
#include <memory>
#include <string>

#include "apps/cli.h"
#include "dataset/dataset.h"
#include "pipeline/scan_job.h"

namespace vts::apps {
namespace {

namespace fs = std::filesystem;

struct DatasetOptions {
  std::string spec, out, shard, threads;
};

// Everything checked before anything is written.
struct DatasetPlan {
  DatasetSpec spec;
  fs::path out;
  int shard = -1;  // -1: every shard and the manifest
};

DatasetPlan plan_dataset(const DatasetOptions& o) {
  DatasetPlan plan;
  try {
    plan.spec = load_dataset_spec(o.spec);
  } catch (const DatasetSpecError& e) {
    throw cli::UsageError(e.what());
  }
  plan.out = o.out;
  std::error_code ec;
  if (fs::exists(plan.out, ec) && !fs::is_directory(plan.out, ec))
    cli::bad("--out", o.out, "exists and is not a directory");
  if (!o.shard.empty()) {
    plan.shard = static_cast<int>(cli::parse_integer("--shard", o.shard, 0, std::numeric_limits<int>::max()));
    if (plan.shard >= shard_count(plan.spec))
      cli::bad("--shard", o.shard,
               "the spec has shards 0 .. " + std::to_string(shard_count(plan.spec) - 1) + " (" + o.spec + ")");
  }
  cli::apply_thread_limit(o.threads);
  return plan;
}

int run_dataset_command(const DatasetOptions& o) {
  const DatasetPlan plan = plan_dataset(o);  // throws UsageError; nothing created yet
  const DatasetSpec& spec = plan.spec;
  const cli::SignalCancel signals;
  const std::int64_t total = plan.shard < 0 ? shard_count(spec) * profiles_per_shard(spec) : profiles_per_shard(spec);
  cli::ProgressLine progress("dataset", total);
  DatasetCallbacks callbacks;
  callbacks.cancelled = &cli::SignalCancel::cancelled;
  callbacks.progress = [&](const DatasetProgress& p) { progress.update(p.profiles_done); };
  try {
    if (plan.shard >= 0) {
      const ShardInfo info = write_shard(spec, plan.shard, plan.out, callbacks);
      progress.done(total);
      std::printf("wrote %s: %d scenes, %lld profiles, %zu files in %s\n", shard_record_name(plan.shard).c_str(),
                  info.scenes, static_cast<long long>(info.profiles), info.files.size(), plan.out.c_str());
      return cli::kExitOk;
    }
    const DatasetResult r = run_dataset(spec, plan.out, callbacks);
    progress.done(total);
    const double rate = r.elapsed_s > 0 ? static_cast<double>(r.profiles_written) / r.elapsed_s : 0.0;
    std::printf("%d shards in %s: %zu written, %zu already complete; %lld profiles written in %.2f s (%.0f profiles/s)\n",
                shard_count(spec), plan.out.c_str(), r.written.size(), r.skipped.size(),
                static_cast<long long>(r.profiles_written), r.elapsed_s, rate);
    std::printf("manifest: %s\n", r.manifest.c_str());
    return cli::kExitOk;
  } catch (const Cancelled&) {
    std::cerr << (isatty(STDERR_FILENO) == 1 ? "\n" : "") << "vts dataset: interrupted by "
              << cli::SignalCancel::signal_name()
              << "; the complete shards are kept, the same command resumes from them\n";
    return 128 + cli::SignalCancel::signal();
  } catch (const DatasetDrawError& e) {
    std::cerr << "vts dataset: " << o.spec << ": " << e.what() << "\n";
    return cli::kExitUsage;
  }
}

}  // namespace

CLI::App* add_dataset_command(CLI::App& app, int& exit_code) {
  auto o = std::make_shared<DatasetOptions>();
  CLI::App* cmd = app.add_subcommand(
      "dataset",
      "Generate labelled profiles for training and testing seam detectors (docs/DATASETS.md): random joints, "
      "dimensions, sensors, materials and views from a spec, written as shards (one EXR per scene and one JSON "
      "line per profile with its truth) and a manifest. Shards already complete are kept: running again resumes");
  cmd->option_defaults()->always_capture_default(false);
  cmd->add_option("--spec", o->spec, "Dataset spec (YAML, docs/DATASETS.md; example: examples/dataset.yaml)")
      ->type_name("SPEC.yaml")
      ->required();
  cmd->add_option("--out", o->out, "Output directory (created if missing)")->type_name("DIR")->required();
  cmd->add_option("--shard", o->shard,
                  "Make only shard K (0-based), whether or not it is complete, and no manifest: for running shards "
                  "on several machines; a later run without --shard keeps them and writes the manifest")
      ->type_name("K");
  cmd->add_option("--threads", o->threads, cli::kThreadsHelp)->type_name("N");
  cmd->callback([o, &exit_code] {
    try {
      exit_code = run_dataset_command(*o);
    } catch (const cli::UsageError& e) {
      std::cerr << "vts dataset: " << e.what() << "\n";
      exit_code = cli::kExitUsage;
    }
  });
  return cmd;
}

}  // namespace vts::apps
