// find_warm_push (world/body_store.h) reads a body's eight warm-start slots at once; only the first
// `count` are live, the rest are whatever earlier ticks left there.
#include <gtest/gtest.h>

#include <array>

#include "world/body_store.h"

namespace throng::detail {
namespace {

TEST(WarmLookup, FindsOnlyLiveSlots) {
  std::array<WarmEntry, kWarmSlots> slots{};
  for (std::uint32_t q = 0; q < kWarmSlots; ++q) slots[q] = {100 + q, 0.5f + static_cast<float>(q)};
  // Every live slot is found, wherever it is.
  for (std::uint32_t q = 0; q < kWarmSlots; ++q) EXPECT_EQ(find_warm_push(slots.data(), kWarmSlots, 100 + q), 0.5f + q);
  // A partner in a stale slot (at or past count) is not.
  EXPECT_EQ(find_warm_push(slots.data(), 3, 102), 2.5f);
  EXPECT_EQ(find_warm_push(slots.data(), 3, 103), 0.0f);
  EXPECT_EQ(find_warm_push(slots.data(), 3, 107), 0.0f);
  EXPECT_EQ(find_warm_push(slots.data(), 0, 100), 0.0f);
  // An unknown partner, and id 0 (the zeroed slots of a fresh body), are not.
  EXPECT_EQ(find_warm_push(slots.data(), kWarmSlots, 99), 0.0f);
  std::array<WarmEntry, kWarmSlots> fresh{};
  EXPECT_EQ(find_warm_push(fresh.data(), 0, 0), 0.0f);
}

}  // namespace
}  // namespace throng::detail
