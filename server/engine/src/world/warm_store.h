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
// push with the body of the smaller id, in the order store_fast_pushes takes the pairs, up to
// kWarmSlots per body.
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

// Keeps pair (a, b)'s push for next tick's warm start with the body of the smaller id (solver
// indices a, b with ids id_a, id_b), in its next free slot if it has one. Returns the push as
// kept, 0 if it was not. Only a push > 0 is stored: the lookup and the checkpoint loader rely on
// it (a push too small for float, below ~1e-45 m, is not kept). Plain pointers and the ids as
// values: see warm_store.cpp.
inline float keep_warm_push(const std::uint32_t* order, WarmEntry* warm, std::uint8_t* warm_count, std::uint32_t a,
                            std::uint32_t b, std::uint32_t id_a, std::uint32_t id_b, float push) {
  const bool a_owns = id_a < id_b;
  const std::uint32_t owner = order[a_owns ? a : b];
  const std::uint32_t count = warm_count[owner];
  if (count < kWarmSlots && push > 0.0f) {
    warm[owner * kWarmSlots + count] = {a_owns ? id_b : id_a, push};
    warm_count[owner] = static_cast<std::uint8_t>(count + 1);
    return push;
  }
  return 0.0f;
}

// Stores the fast pairs' pushes, block by block (for_each_block, forward: the blocks of a phase on
// the pool's threads); returns the number of events written, in block order.
std::size_t store_fast_pushes(PairSchedule& s, const SolverBodies& bodies, const WarmStoreTarget& t,
                              WorkerPool* pool = nullptr);

}  // namespace throng::detail
