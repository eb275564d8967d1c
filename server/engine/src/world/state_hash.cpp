// The per-tick 64-bit state hash: XXH3 over every value that influences future ticks, in dense
// order. Two runs with the same inputs on the same binary must agree on it every tick; the match
// log stores it so a replay can prove it re-simulated the same match.
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
  feed(st, b.px); feed(st, b.py);
  feed(st, b.r); feed(st, b.hh); feed(st, b.grounded);
  feed(st, b.resistance); feed(st, b.morale_level);
  // Warm-start pushes steer the next tick, so they are state too (hashed field by field: the
  // struct has padding whose bytes are unspecified).
  for (std::size_t i = 0; i < b.size(); ++i) {
    for (std::uint32_t k = 0; k < b.warm_count[i]; ++k) {
      const detail::WarmEntry& e = b.warm[i * detail::kWarmSlots + k];
      XXH3_64bits_update(st, &e.partner, sizeof(e.partner));
      XXH3_64bits_update(st, &e.lambda, sizeof(e.lambda));
    }
  }
  const std::uint64_t h = XXH3_64bits_digest(st);
  XXH3_freeState(st);
  return h;
}

}  // namespace throng
