#pragma once
// Replaces the global operator new and delete of the test binary that
// includes this header (include it in exactly one source file per binary) so
// that tests can count heap allocations: g_allocations counts every operator
// new, on any thread. Every replaceable form that pairs with the deletes
// below goes through malloc, so no allocation from the runtime's own operator
// new (or ASan's) is handed to free (ASan: alloc-dealloc-mismatch).
#include <atomic>
#include <cstdlib>
#include <new>

namespace vts::test {
inline std::atomic<long> g_allocations{0};
}  // namespace vts::test

#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
void* operator new(std::size_t n) {
  vts::test::g_allocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void* operator new(std::size_t n, const std::nothrow_t&) noexcept {
  vts::test::g_allocations.fetch_add(1, std::memory_order_relaxed);
  return std::malloc(n ? n : 1);
}
void* operator new[](std::size_t n) { return operator new(n); }
void* operator new[](std::size_t n, const std::nothrow_t& t) noexcept { return operator new(n, t); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { std::free(p); }
