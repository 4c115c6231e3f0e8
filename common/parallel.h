#pragma once
// The one way vts works in parallel (docs/ARCHITECTURE.md, "Threads"), after
// Embree's common/algorithms/parallel_for.h: every parallel loop of the
// library goes through parallel_for, which runs on oneTBB in one task arena
// of at most thread_limit() threads. The same limit goes to Embree's devices
// ("threads=N"), bounds the raster source's OpenGL contexts (one per arena
// slot) and sizes OpenEXR's compression, which runs on the arena too. oneTBB
// composes with a caller's own use of it: a Python thread pool or a Dask
// worker running jobs shares one pool of worker threads with them instead of
// multiplying threads.
//
// The limit: set_thread_limit(n) if it was called, else the environment's
// VTS_THREADS, else every hardware thread; never more than the hardware
// has. It is fixed by the first parallel loop.
#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <type_traits>

namespace vts {

// The most threads vts works with at once, >= 1. Throws
// std::invalid_argument when VTS_THREADS is set to anything but an integer
// >= 1.
int thread_limit();
// n >= 1. Throws std::invalid_argument for n < 1, std::logic_error once the
// first parallel loop has fixed another limit.
void set_thread_limit(int n);
// VTS_THREADS: the limit it asks for, or none when unset; throws
// std::invalid_argument "VTS_THREADS = 'x': expected an integer >= 1".
std::optional<int> thread_limit_from_environment();
// The Embree device configuration for the limit: "threads=N" when it is
// below the hardware's thread count, else "" (Embree's default: all).
std::string embree_device_config();

// Inside a parallel_for body: the calling thread's slot in the arena,
// 0 .. thread_limit() - 1, never shared by two bodies running at once; -1
// outside one. Per-thread scratch is indexed by thread_slot() + 1, index 0
// belonging to a caller outside any loop.
int thread_slot();

namespace detail {
void parallel_for(std::size_t n, void (*call)(void* body, std::size_t i), void* body);
void run_detached(std::function<void()> task);
}  // namespace detail

// Calls body(i) for every i in [0, n), each index its own task, on the
// arena's threads (the caller's among them), and returns when all are done.
// The first exception a body throws cancels the indices not yet started
// and is rethrown here. n == 1 runs on the calling thread without entering
// the arena. A thread waiting for the loop takes no other work, so bodies
// may hold per-slot scratch while they run.
template <class Body>
void parallel_for(std::size_t n, Body&& body) {
  detail::parallel_for(
      n, [](void* b, std::size_t i) { (*static_cast<std::remove_reference_t<Body>*>(b))(i); },
      static_cast<void*>(&body));
}

// Runs `task` on one of the arena's threads and returns at once; the caller
// waits for it by its own means. For thread pools vts does not own
// (OpenEXR's), which block their caller until their tasks are done. An
// exception from `task` ends the process: catch inside.
inline void run_detached(std::function<void()> task) { detail::run_detached(std::move(task)); }

}  // namespace vts
