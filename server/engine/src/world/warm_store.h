#pragma once
// A scheduled solve's fast pushes, read from the schedule, into the warm-start cache, the kept
// pair list and the push events (warm_store.cpp).
#include <cstddef>
#include <cstdint>

#include "solver/pair_schedule.h"
#include "solver/solver_data.h"
#include "throng/world/push_event.h"
#include "world/body_store.h"

namespace throng::detail {

// Where the pushes go. The cache (warm, warm_count: dense order, counts zeroed before) keeps each
// push with the body of the smaller id, in schedule order, up to kWarmSlots per body.
struct WarmStoreTarget {
  const std::uint32_t* order;  // solver index -> dense index
  WarmEntry* warm;
  std::uint8_t* warm_count;
  // A kept list (or null): each pair's entry gets the push as kept, 0 where the cache could not
  // keep it or the pair did not push.
  float* list_lambda;
  const std::uint32_t* list_entry;  // the schedule's pair index -> list entry
  // Push events (or null): written from events[0]; room for every fast pair.
  PushEvent* events;
};

// Stores the fast pairs' pushes; returns the number of events written.
std::size_t store_fast_pushes(const PairSchedule& s, const SolverBodies& bodies, const WarmStoreTarget& t);

}  // namespace throng::detail
