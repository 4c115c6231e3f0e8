#pragma once
#include <CLI/CLI.hpp>

namespace vts::apps {

// `vts score TRACK.jsonl TRUTH.jsonl`: the tracker's results (vts track's
// output) against ground truth per profile (trackio/truth_json.h): right,
// imprecise, rejected and false reads per joint and noise level, as a
// Markdown table (docs/JOINTS.md "Scores"). The callback stores its exit
// status in exit_code.
CLI::App* add_score_command(CLI::App& app, int& exit_code);

}  // namespace vts::apps
