// On plain pointers, with the ids held as values: the cache's counts are bytes, and a store
// through a byte pointer may alias anything, so in the lambda over the world's vectors this
// replaced every count update made the compiler reload each vector's data pointer; the events
// went through push_back. That saved little (docs/design/solver.md): the loop waits on memory (a
// write into each owner's 64-byte block of the cache), not on instructions. Walking the pairs in
// list (spatial) order instead of schedule order does not help either.
#include "world/warm_store.h"

#include "solver/contact_solver.h"

namespace throng::detail {

std::size_t store_fast_pushes(PairSchedule& s, const SolverBodies& bodies, const WarmStoreTarget& t, WorkerPool* pool) {
  const std::uint32_t* const order = t.order;
  WarmEntry* const warm = t.warm;
  std::uint8_t* const warm_count = t.warm_count;
  float* const list_lambda = t.list_lambda;
  const std::uint32_t* const list_entry = t.list_entry;
  const std::uint32_t* const id = bodies.id.data();
  const std::uint32_t* const pa = s.a.data();
  const std::uint32_t* const pb = s.b.data();
  const std::uint32_t* const src = s.src.data();
  const float* const lambda = s.lambda.data();
  const float* const share = s.share_exact.data();
  // A pair with a push writes an event; the count and the store below must agree on which.
  auto pushed = [](float push) { return !(push <= 0.0f); };
  const std::size_t blocks = s.block_count();
  // Each block's events start where the earlier blocks' end (block order, whatever thread stores
  // them): counted first.
  std::size_t total = 0;
  if (t.events != nullptr) {
    s.block_events.resize(blocks + 1);
    auto count = [&](std::uint32_t k) {
      std::uint32_t n = 0;
      for (std::uint32_t f = s.block_fast_begin(k), end = s.block_fast_end(k); f < end; ++f) n += pushed(lambda[f]) ? 1 : 0;
      s.block_events[k] = n;
    };
    run_tasks(pool, static_cast<std::uint32_t>(blocks), count);
    for (std::size_t k = 0; k < blocks; ++k) {
      const std::uint32_t n = s.block_events[k];
      s.block_events[k] = static_cast<std::uint32_t>(total);
      total += n;
    }
  }
  // The cache's slots fill in the forward sweep's order: a body's pairs in two blocks are stored
  // phase by phase, the same for any number of threads.
  for_each_block(s, pool, true, [&](std::uint32_t k) {
    PushEvent* const events = t.events != nullptr ? t.events + s.block_events[k] : nullptr;
    std::size_t written = 0;
    for (std::uint32_t f = s.block_fast_begin(k), end = s.block_fast_end(k); f < end; ++f) {
      const float push = lambda[f];
      if (!pushed(push)) {
        if (list_lambda != nullptr && src[f] != PairSchedule::kNoPair) list_lambda[list_entry[src[f]]] = 0.0f;
        continue;
      }
      const std::uint32_t a = pa[f], b = pb[f];
      const std::uint32_t id_a = id[a], id_b = id[b];
      const float kept = keep_warm_push(order, warm, warm_count, a, b, id_a, id_b, push);
      if (list_lambda != nullptr) list_lambda[list_entry[src[f]]] = kept;
      if (events != nullptr) {
        events[written++] = {ObjectId{id_a}, ObjectId{id_b}, static_cast<float>(fast_pair_start_depth(bodies, s, f)),
                             share[f], push};
      }
    }
  });
  return total;
}

}  // namespace throng::detail
