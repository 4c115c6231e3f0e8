// The one parallelism mechanism (common/parallel.h): every index once,
// slots within the limit, errors back as exceptions, the limit's rules.
#include <catch2/catch.hpp>

#include <atomic>
#include <cstdlib>
#include <mutex>
#include <set>
#include <stdexcept>
#include <thread>
#include <vector>

#include "common/parallel.h"

TEST_CASE("parallel_for: every index once, in slots within the thread limit", "[parallel]") {
  const int limit = vts::thread_limit();
  REQUIRE(limit >= 1);
  std::vector<std::atomic<int>> seen(1000);
  std::mutex mutex;
  std::set<int> slots;
  vts::parallel_for(seen.size(), [&](std::size_t i) {
    ++seen[i];
    const std::lock_guard lock(mutex);
    slots.insert(vts::thread_slot());
  });
  for (const auto& s : seen) CHECK(s == 1);
  CHECK(*slots.begin() >= 0);
  CHECK(*slots.rbegin() < limit);
  CHECK(slots.size() <= static_cast<std::size_t>(limit));
  CHECK(vts::thread_slot() == -1);  // outside a loop
}

TEST_CASE("parallel_for: one index runs on the caller, none runs nothing", "[parallel]") {
  const std::thread::id caller = std::this_thread::get_id();
  int calls = 0;
  vts::parallel_for(1, [&](std::size_t i) {
    CHECK(i == 0);
    CHECK(std::this_thread::get_id() == caller);
    ++calls;
  });
  vts::parallel_for(0, [&](std::size_t) { ++calls; });
  CHECK(calls == 1);
}

TEST_CASE("parallel_for: a body's exception comes back to the caller", "[parallel]") {
  std::atomic<int> ran{0};
  CHECK_THROWS_WITH(vts::parallel_for(64,
                                      [&](std::size_t i) {
                                        ++ran;
                                        if (i == 5) throw std::runtime_error("part 5 failed");
                                      }),
                    "part 5 failed");
  CHECK(ran >= 1);
  // The arena is usable afterwards.
  std::atomic<int> after{0};
  vts::parallel_for(8, [&](std::size_t) { ++after; });
  CHECK(after == 8);
}

TEST_CASE("parallel_for: loops nest", "[parallel]") {
  std::atomic<int> total{0};
  vts::parallel_for(4, [&](std::size_t) {
    const int outer = vts::thread_slot();
    vts::parallel_for(4, [&](std::size_t) { ++total; });
    CHECK(vts::thread_slot() == outer);  // restored after the inner loop
  });
  CHECK(total == 16);
}

TEST_CASE("thread limit: fixed by its first use - VTS_THREADS checked", "[parallel]") {
  const int limit = vts::thread_limit();
  CHECK_NOTHROW(vts::set_thread_limit(limit));
  CHECK_THROWS_AS(vts::set_thread_limit(0), std::invalid_argument);
  if (limit < static_cast<int>(std::thread::hardware_concurrency()))
    CHECK_THROWS_AS(vts::set_thread_limit(limit + 1), std::logic_error);
  if (limit > 1) CHECK_THROWS_AS(vts::set_thread_limit(1), std::logic_error);

  const char* saved = std::getenv("VTS_THREADS");
  const std::string restore = saved ? saved : "";
  ::setenv("VTS_THREADS", "3", 1);
  CHECK(vts::thread_limit_from_environment() == 3);
  for (const char* bad : {"0", "-2", "two", "", "2 "}) {
    ::setenv("VTS_THREADS", bad, 1);
    CHECK_THROWS_WITH(vts::thread_limit_from_environment(),
                      "VTS_THREADS = '" + std::string(bad) + "': expected an integer >= 1");
  }
  ::unsetenv("VTS_THREADS");
  CHECK_FALSE(vts::thread_limit_from_environment());
  if (saved) ::setenv("VTS_THREADS", restore.c_str(), 1);
}
