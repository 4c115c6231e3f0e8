#include "apps/vts_score.h"

#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <string>

#include "apps/cli.h"
#include "tracker/score.h"
#include "trackio/result_json.h"
#include "trackio/truth_json.h"

namespace vts::apps {
namespace {

namespace tk = vts::tracker;

struct ScoreOptions {
  std::string track, truth;
  double right_ideal_mm = 0.1, right_noisy_mm = 0.3, false_mm = 1.0;
  bool failures = false;
};

struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Each line of a JSON Lines file, parsed, with its line number.
template <class F>
void read_lines(const std::string& file, F each) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(file + ": no such file or not readable");
  std::string line;
  for (int n = 1; std::getline(in, line); ++n) {
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    trackio::Json j;
    try {
      j = trackio::Json::parse(line);
    } catch (const std::exception& e) {
      throw InputError(file + ":" + std::to_string(n) + ": not JSON (" + e.what() + ")");
    }
    try {
      each(j);
    } catch (const trackio::JsonError& e) {
      throw InputError(file + ":" + std::to_string(n) + ": " + e.what());
    }
  }
}

int run_score(const ScoreOptions& o) {
  std::map<std::int64_t, tk::Truth> truth;
  read_lines(o.truth, [&](const trackio::Json& j) {
    std::int64_t k = 0;
    tk::Truth t = trackio::truth_from_json(j, &k);
    if (!truth.emplace(k, t).second) throw trackio::JsonError("profile " + std::to_string(k) + " given twice");
  });
  tk::ScoreParams params;
  params.right_ideal_mm = o.right_ideal_mm;
  params.right_noisy_mm = o.right_noisy_mm;
  params.false_mm = o.false_mm;
  tk::ScoreTable table;
  std::size_t scored = 0;
  read_lines(o.track, [&](const trackio::Json& j) {
    std::int64_t k = 0;
    const tk::TrackResult r = trackio::result_from_json(j, &k);
    const auto t = truth.find(k);
    if (t == truth.end()) throw trackio::JsonError("profile " + std::to_string(k) + " has no truth in " + o.truth);
    table.add(r, t->second, params);
    if (o.failures) {
      const tk::Scored s = tk::score(r, t->second, params);
      if (s.outcome == tk::Outcome::False || s.outcome == tk::Outcome::Imprecise)
        std::cout << "profile " << k << ": " << tk::to_string(s.outcome) << ", track point " << s.track_error_mm
                  << " mm off\n";
    }
    ++scored;
  });
  if (scored == 0) throw InputError(o.track + ": no results");
  std::cout << table.markdown();
  return cli::kExitOk;
}

}  // namespace

CLI::App* add_score_command(CLI::App& app, int& exit_code) {
  auto o = std::make_shared<ScoreOptions>();
  CLI::App* cmd = app.add_subcommand(
      "score", "Score vts track's results against ground truth per profile: right, imprecise, rejected and false "
               "reads per joint and noise level (docs/JOINTS.md)");
  cmd->add_option("track", o->track, "vts track's output (JSON Lines)")->required()->type_name("TRACK.jsonl");
  cmd->add_option("truth", o->truth, "Ground truth per profile (JSON Lines, as vts-corpus writes it)")
      ->required()
      ->type_name("TRUTH.jsonl");
  cmd->add_option("--right-ideal", o->right_ideal_mm, "A right track point on a noise-free profile, mm (default 0.1)")
      ->check(CLI::PositiveNumber)
      ->type_name("MM");
  cmd->add_option("--right-noisy", o->right_noisy_mm, "A right track point on a noisy profile, mm (default 0.3)")
      ->check(CLI::PositiveNumber)
      ->type_name("MM");
  cmd->add_option("--false", o->false_mm, "An ok reading farther off is a false read, mm (default 1)")
      ->check(CLI::PositiveNumber)
      ->type_name("MM");
  cmd->add_flag("--failures", o->failures, "List every false and imprecise reading first");
  cmd->callback([o, &exit_code] {
    try {
      exit_code = run_score(*o);
    } catch (const InputError& e) {
      std::cout.flush();
      std::cerr << "vts score: " << e.what() << "\n";
      exit_code = cli::kExitUsage;
    }
  });
  return cmd;
}

}  // namespace vts::apps
