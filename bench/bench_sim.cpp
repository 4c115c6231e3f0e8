// BM_SimScenario/NAME: one built-in scenario of `vts sim` (issue 19 point 5),
// the closed loop and the same program open loop, outputs not written. The
// counter x_real_time is simulated seconds per wall second.
#include <benchmark/benchmark.h>

#include "pipeline/scenario.h"
#include "pipeline/sim_run.h"

namespace {

void BM_SimScenario(benchmark::State& state, const std::string& name) {
  const vts::Scenario sc = vts::builtin_scenario(name);
  double simulated = 0.0;
  for (auto _ : state) {
    const vts::SimRun run = vts::run_sim(sc.spec);
    simulated += run.sim_time_s();
    benchmark::DoNotOptimize(run.metrics.data());
  }
  state.counters["x_real_time"] = benchmark::Counter(simulated, benchmark::Counter::kIsRate);
}

const int registered = [] {
  for (const std::string& name : vts::scenario_names())
    benchmark::RegisterBenchmark(("BM_SimScenario/" + name).c_str(), BM_SimScenario, name)
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime();
  return 0;
}();

}  // namespace
