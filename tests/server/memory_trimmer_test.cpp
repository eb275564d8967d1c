#include "throng/server/memory_trimmer.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <limits>
#include <stdexcept>
#include <thread>
#include <vector>

namespace throng::server {
namespace {

using namespace std::chrono_literals;

// Resident bytes of this process (/proc/self/statm's second field, in pages).
std::size_t resident_bytes() {
  std::ifstream statm("/proc/self/statm");
  std::size_t size_pages = 0, resident_pages = 0;
  statm >> size_pages >> resident_pages;
  return resident_pages * static_cast<std::size_t>(sysconf(_SC_PAGESIZE));
}

template <class Pred>
bool wait_until(Pred pred, std::chrono::milliseconds limit) {
  const auto end = std::chrono::steady_clock::now() + limit;
  while (!pred()) {
    if (std::chrono::steady_clock::now() > end) return false;
    std::this_thread::sleep_for(1ms);
  }
  return true;
}

TEST(MemoryTrimmer, TrimsEveryIntervalAndNotAfterItIsDestroyed) {
  std::atomic<int> calls{0};
  std::uint64_t counted = 0;
  {
    MemoryTrimmer trimmer(5ms, [&] { ++calls; });
    ASSERT_TRUE(wait_until([&] { return calls.load() >= 3; }, 10s));
    // stats() counts every finished trim (a trim may be running right now: at most one more).
    const auto s = trimmer.stats();
    EXPECT_GE(s.trims, 2u);
    EXPECT_LE(s.trims, static_cast<std::uint64_t>(calls.load()));
    EXPECT_GE(s.max_seconds, 0.0);
    EXPECT_GE(s.total_seconds, s.max_seconds);
    counted = s.trims;
  }
  const int at_destruction = calls.load();
  EXPECT_GE(static_cast<std::uint64_t>(at_destruction), counted);
  std::this_thread::sleep_for(30ms);
  EXPECT_EQ(calls.load(), at_destruction);
}

TEST(MemoryTrimmer, StopsWithoutWaitingOutItsInterval) {
  std::atomic<int> calls{0};
  const auto t0 = std::chrono::steady_clock::now();
  { MemoryTrimmer trimmer(std::chrono::hours(1), [&] { ++calls; }); }
  // Waiting out the interval would take an hour; a bound far above a thread's start and join.
  EXPECT_LT(std::chrono::steady_clock::now() - t0, 30s);
  EXPECT_EQ(calls.load(), 0);
}

TEST(MemoryTrimmer, RefusesANonPositiveIntervalAndAMissingFunction) {
  EXPECT_THROW(MemoryTrimmer(0ms, [] {}), std::invalid_argument);
  EXPECT_THROW(MemoryTrimmer(-5ms, [] {}), std::invalid_argument);
  EXPECT_THROW(MemoryTrimmer(5ms, std::function<void()>{}), std::invalid_argument);
}

TEST(MemoryTrimmer, TheServersTrimmerIsOffAtZeroAndRoundsToMilliseconds) {
  EXPECT_EQ(MemoryTrimmer::every_seconds(0.0), nullptr);
  EXPECT_EQ(MemoryTrimmer::every_seconds(0.2)->interval(), 200ms);
  EXPECT_EQ(MemoryTrimmer::every_seconds(10.0)->interval(), 10000ms);
  EXPECT_EQ(MemoryTrimmer::every_seconds(0.1234)->interval(), 123ms);
  // Refused rather than turned into something else: below the floor, beyond a day, not a number.
  for (const double bad : {-1.0, 0.05, 86401.0, std::nan(""), std::numeric_limits<double>::infinity()})
    EXPECT_THROW(MemoryTrimmer::every_seconds(bad), std::invalid_argument) << bad;
}

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
constexpr bool kMallocIsGlibc = false;  // the sanitizer's allocator replaces glibc's: malloc_trim has nothing to trim
#else
constexpr bool kMallocIsGlibc = true;
#endif

// The case the server's trimmer is for: heap blocks freed below blocks still live stay resident
// (glibc returns a heap's pages only from its top) until trim_malloc_heap hands them back.
TEST(TrimMallocHeap, ReturnsFreedBlocksThatLiveBlocksKeepInTheHeap) {
  if (!kMallocIsGlibc) GTEST_SKIP() << "glibc's malloc is replaced by the sanitizer's";
  constexpr std::size_t kBlock = 96 << 10;  // under glibc's mapping threshold: from the heap
  constexpr int kBlocks = 128;              // half freed: 6 MiB
  // Every other block stays live, so a freed one cannot merge with its neighbours into the heap's
  // top (which free() hands back by itself); the last one allocated, at the top, is kept.
  std::vector<void*> blocks;
  for (int i = 0; i < kBlocks; ++i) {
    void* p = std::malloc(kBlock);
    ASSERT_NE(p, nullptr);
    std::memset(p, 0x5a, kBlock);  // resident
    blocks.push_back(p);
  }
  for (int i = 0; i < kBlocks; i += 2) std::free(blocks[static_cast<std::size_t>(i)]);
  const std::size_t before = resident_bytes();
  trim_malloc_heap();
  const std::size_t after = resident_bytes();
  for (int i = 1; i < kBlocks; i += 2) std::free(blocks[static_cast<std::size_t>(i)]);
  // Each freed block keeps a page or two of bookkeeping; the rest (about 6 MiB) goes back.
  EXPECT_GE(before, after + (4u << 20)) << "resident before " << before << ", after " << after;
}

}  // namespace
}  // namespace throng::server
