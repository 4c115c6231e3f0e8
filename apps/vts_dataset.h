#pragma once
#include <CLI/CLI.hpp>

namespace vts::apps {

// `vts dataset --spec SPEC.yaml --out DIR`: labelled profiles for training
// and testing seam detectors (dataset/dataset.h, docs/DATASETS.md): the
// shards not yet complete in DIR, then DIR/manifest.json; `--shard K` makes
// one shard only. The callback stores its exit status in exit_code.
CLI::App* add_dataset_command(CLI::App& app, int& exit_code);

}  // namespace vts::apps
