#include "common/parallel.h"

#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>
#include <tbb/task_arena.h>
#include <tbb/task_group.h>

#include <charconv>
#include <cstdlib>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string_view>

namespace vts {
namespace {

// The limit, fixed at its first use; the arena, built at the first loop.
struct State {
  std::mutex mutex;
  int requested = 0;  // set_thread_limit's, 0: not called
  int fixed = 0;      // 0: not yet fixed
  std::unique_ptr<tbb::task_arena> arena;
};

State& state() {
  static State s;
  return s;
}

int hardware_threads() { return std::max(1, tbb::info::default_concurrency()); }

// The limit to use now, under s.mutex.
int fix_limit(State& s) {
  if (s.fixed == 0) {
    int n = s.requested;
    if (n == 0) n = thread_limit_from_environment().value_or(0);
    if (n == 0) n = hardware_threads();
    s.fixed = std::min(n, hardware_threads());
  }
  return s.fixed;
}

tbb::task_arena& arena() {
  State& s = state();
  std::lock_guard lock(s.mutex);
  if (!s.arena) s.arena = std::make_unique<tbb::task_arena>(fix_limit(s));
  return *s.arena;
}

thread_local int t_slot = -1;

struct SlotScope {
  int saved;
  explicit SlotScope(int slot) : saved(t_slot) { t_slot = slot; }
  ~SlotScope() { t_slot = saved; }
};

}  // namespace

int thread_limit() {
  State& s = state();
  std::lock_guard lock(s.mutex);
  return fix_limit(s);
}

void set_thread_limit(int n) {
  if (n < 1) throw std::invalid_argument("thread limit " + std::to_string(n) + ": expected an integer >= 1");
  State& s = state();
  std::lock_guard lock(s.mutex);
  if (s.fixed != 0 && s.fixed != std::min(n, hardware_threads()))
    throw std::logic_error("the thread limit is fixed at " + std::to_string(s.fixed) +
                           " by the work already done; set it before the first scan");
  s.requested = n;
}

std::optional<int> thread_limit_from_environment() {
  const char* env = std::getenv("VTS_THREADS");
  if (!env) return std::nullopt;
  const std::string_view text(env);
  int n = 0;
  const auto r = std::from_chars(text.data(), text.data() + text.size(), n);
  if (text.empty() || r.ec != std::errc() || r.ptr != text.data() + text.size() || n < 1)
    throw std::invalid_argument("VTS_THREADS = '" + std::string(text) + "': expected an integer >= 1");
  return n;
}

std::string embree_device_config() {
  const int n = thread_limit();
  return n < hardware_threads() ? "threads=" + std::to_string(n) : std::string();
}

int thread_slot() { return t_slot; }

namespace detail {

void parallel_for(std::size_t n, void (*call)(void*, std::size_t), void* body) {
  if (n == 0) return;
  if (n == 1) {
    call(body, 0);
    return;
  }
  arena().execute([&] {
    // Isolated: a thread waiting for this loop runs only its tasks, never
    // another loop's body on top of a body of this one.
    tbb::this_task_arena::isolate([&] {
      tbb::task_group_context context;
      tbb::parallel_for(
          tbb::blocked_range<std::size_t>(0, n, 1),
          [&](const tbb::blocked_range<std::size_t>& r) {
            const SlotScope slot(tbb::this_task_arena::current_thread_index());
            for (std::size_t i = r.begin(); i != r.end(); ++i) call(body, i);
          },
          tbb::simple_partitioner(), context);
      // Cancelled from outside (an enclosing loop's failure), not by a body.
      if (context.is_group_execution_cancelled()) throw std::runtime_error("vts: parallel loop cancelled");
    });
  });
}

void run_detached(std::function<void()> task) {
  // An arena of one thread has no worker slot; oneTBB would add one for an
  // enqueued task, a second thread the limit forbids. And where the process
  // allows oneTBB no worker at all (a global_control of 1), nothing would
  // ever run it.
  if (thread_limit() == 1 ||
      tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism) < 2) {
    task();
    return;
  }
  arena().enqueue(std::move(task));
}

}  // namespace detail
}  // namespace vts
