// The per-tick 64-bit state hash: XXH3 over every value that influences future ticks, in dense
// order. Two runs with the same inputs on the same binary must agree on it every tick; the match
// log stores it so a replay can prove it re-simulated the same match.
#include <cstddef>
#include <vector>

#include <xxhash.h>

#include "world/world_impl.h"

namespace throng {
namespace {

template <class T>
void feed(XXH3_state_t* st, const std::vector<T>& v) {
  if (!v.empty()) XXH3_64bits_update(st, v.data(), v.size() * sizeof(T));
}

}  // namespace

std::uint64_t World::state_hash() const {
  const Impl& w = *impl_;
  XXH3_state_t* st = XXH3_createState();
  XXH3_64bits_reset(st);
  XXH3_64bits_update(st, &w.tick, sizeof(w.tick));
  const detail::BodyStore& b = w.bodies;
  feed(st, b.id);
  feed(st, b.x); feed(st, b.y); feed(st, b.z);
  feed(st, b.vx); feed(st, b.vy); feed(st, b.vz);
  feed(st, b.ax); feed(st, b.ay); feed(st, b.az);
  feed(st, b.push_x); feed(st, b.push_y);
  feed(st, b.r); feed(st, b.hh); feed(st, b.grounded);
  feed(st, b.resistance); feed(st, b.morale_level);
  // Warm-start pushes steer the next tick, so they are state too: each body's live entries
  // (partner, then lambda: 8 bytes with no padding), packed into one buffer and fed at once.
  // XXH3's streaming hash is that of the concatenated bytes, so this gives the value that feeding
  // the fields one by one gave, which took two calls per entry and made the hash a noticeable part
  // of every tick (docs/design/solver.md). The buffer stays with the thread: a fresh one every call
  // was a fresh mmap, its pages faulted in and zeroed.
  static_assert(sizeof(detail::WarmEntry) == 8 && offsetof(detail::WarmEntry, lambda) == 4);
  thread_local std::vector<detail::WarmEntry> packed;
  packed.clear();
  for (std::size_t i = 0; i < b.size(); ++i) {
    const detail::WarmEntry* e = &b.warm[i * detail::kWarmSlots];
    packed.insert(packed.end(), e, e + b.warm_count[i]);
  }
  feed(st, packed);
  // The kept pair list steers which pairs the next ticks solve and in what order: whether one is
  // kept (or, in a world restored and not yet stepped, to be searched again), where it was searched
  // (dense order, as a checkpoint holds it) and the cooldown counters.
  const std::size_t n = b.size();
  const World::Impl::ListRecord record = w.list_record();
  const std::uint8_t list_flag = w.list_record_byte();
  XXH3_64bits_update(st, &list_flag, 1);
  XXH3_64bits_update(st, &w.list.kept_ticks, sizeof(w.list.kept_ticks));
  XXH3_64bits_update(st, &w.list.cooldown, sizeof(w.list.cooldown));
  XXH3_64bits_update(st, &w.list.backoff, sizeof(w.list.backoff));
  if (record == World::Impl::ListRecord::kPending) {
    feed(st, w.list.restored_x); feed(st, w.list.restored_y); feed(st, w.list.restored_z);
  } else if (record == World::Impl::ListRecord::kKept) {
    thread_local std::vector<double> dense;
    dense.resize(n);
    for (const std::vector<double>* col : {&w.list.x, &w.list.y, &w.list.z}) {
      for (std::size_t s = 0; s < n; ++s) dense[w.solver_order[s]] = (*col)[s];
      feed(st, dense);
    }
  }
  const std::uint64_t h = XXH3_64bits_digest(st);
  XXH3_freeState(st);
  return h;
}

}  // namespace throng
