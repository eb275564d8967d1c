#pragma once
// Replaces the global operator new/delete with versions that count allocations while g_counting
// is set — how the "no allocation in the tick after warm-up" tests observe allocation. Include
// this in exactly ONE source file of a test binary (it defines the replaceable operators); counting
// is off except inside a test's measured block, so the binary's other suites are unaffected.
//
// Every form is replaced, aligned ones included, so whatever allocates is released through the
// same allocator pair (malloc/aligned_alloc with free) — the sanitizers check that pairing.
#include <algorithm>
#include <atomic>
#include <cstddef>
#include <cstdlib>
#include <new>

// The operators pair malloc with free by design; GCC cannot see that they are a matched set and
// warns at call sites under the sanitizer build.
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"

inline std::atomic<bool> g_counting{false};
inline std::atomic<std::size_t> g_allocations{0};

namespace throng::test::detail {
inline void count_allocation() noexcept {
  if (g_counting.load(std::memory_order_relaxed)) g_allocations.fetch_add(1, std::memory_order_relaxed);
}
inline void* counted_malloc(std::size_t size) noexcept {
  count_allocation();
  return std::malloc(size == 0 ? 1 : size);
}
inline void* counted_aligned(std::size_t size, std::align_val_t align) noexcept {
  count_allocation();
  const auto a = static_cast<std::size_t>(align);
  return std::aligned_alloc(a, (std::max<std::size_t>(size, 1) + a - 1) / a * a);
}
}  // namespace throng::test::detail

void* operator new(std::size_t size) {
  if (void* p = throng::test::detail::counted_malloc(size)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t size) {
  if (void* p = throng::test::detail::counted_malloc(size)) return p;
  throw std::bad_alloc();
}
void* operator new(std::size_t size, const std::nothrow_t&) noexcept { return throng::test::detail::counted_malloc(size); }
void* operator new[](std::size_t size, const std::nothrow_t&) noexcept { return throng::test::detail::counted_malloc(size); }
void* operator new(std::size_t size, std::align_val_t a) {
  if (void* p = throng::test::detail::counted_aligned(size, a)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t size, std::align_val_t a) {
  if (void* p = throng::test::detail::counted_aligned(size, a)) return p;
  throw std::bad_alloc();
}
void* operator new(std::size_t size, std::align_val_t a, const std::nothrow_t&) noexcept {
  return throng::test::detail::counted_aligned(size, a);
}
void* operator new[](std::size_t size, std::align_val_t a, const std::nothrow_t&) noexcept {
  return throng::test::detail::counted_aligned(size, a);
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t, const std::nothrow_t&) noexcept { std::free(p); }
