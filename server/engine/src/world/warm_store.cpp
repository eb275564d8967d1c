// On plain pointers, with the ids held as values: the cache's counts are bytes, and a store
// through a byte pointer may alias anything, so in the lambda over the world's vectors this
// replaced every count update made the compiler reload each vector's data pointer; the events
// went through push_back. That saved little (docs/design/solver.md): the loop waits on memory (a
// write into each owner's 64-byte block of the cache), not on instructions. Walking the pairs in
// list (spatial) order instead of schedule order does not help either.
#include "world/warm_store.h"

#include "solver/contact_solver.h"

namespace throng::detail {

std::size_t store_fast_pushes(const PairSchedule& s, const SolverBodies& bodies, const WarmStoreTarget& t) {
  const std::uint32_t* const order = t.order;
  WarmEntry* const warm = t.warm;
  std::uint8_t* const warm_count = t.warm_count;
  float* const list_lambda = t.list_lambda;
  const std::uint32_t* const list_entry = t.list_entry;
  PushEvent* const events = t.events;
  const std::uint32_t* const id = bodies.id.data();
  const std::uint32_t* const pa = s.a.data();
  const std::uint32_t* const pb = s.b.data();
  const std::uint32_t* const src = s.src.data();
  const float* const lambda = s.lambda.data();
  const float* const share = s.share_exact.data();
  const std::size_t slots = s.fast_size();
  std::size_t written = 0;
  for (std::size_t f = 0; f < slots; ++f) {
    const float push = lambda[f];
    if (push <= 0.0f) {
      if (list_lambda != nullptr && src[f] != PairSchedule::kNoPair) list_lambda[list_entry[src[f]]] = 0.0f;
      continue;
    }
    const std::uint32_t a = pa[f], b = pb[f];
    const std::uint32_t id_a = id[a], id_b = id[b];
    const float kept = keep_warm_push(order, warm, warm_count, a, b, id_a, id_b, push);
    if (list_lambda != nullptr) list_lambda[list_entry[src[f]]] = kept;
    if (events != nullptr) {
      events[written++] = {ObjectId{id_a}, ObjectId{id_b},
                           static_cast<float>(fast_pair_start_depth(bodies, s, static_cast<std::uint32_t>(f))),
                           share[f], push};
    }
  }
  return written;
}

}  // namespace throng::detail
