// World checkpoints: everything that influences future ticks, written field by field (layout in
// world/CHECKPOINT.md), and restored so that step() continues bit-identically.
//
// Saved: tick, solver iteration budget (runtime-settable), the slot table (generations, kinds,
// dense references) and the LIFO free list, fixed objects' parameters, the scenery-cell reach,
// every BodyStore column in the current dense order (the 16-tick spatial re-sort changes
// iteration order and therefore floating-point results) including the warm-start cache and the
// coefficient cache with its dirty flags, per-body parameters, cameras, groups (morale level is
// the hysteresis state), the morale counts of the running refresh period, the policy and its
// version.
// Not saved, because step() rebuilds them from the above before reading them (scratch): the
// broadphase grid and its order, solver arrays, pair/plane/contact lists, start/moved positions,
// pile-relief list, morale point index, camera_xyz, the reorder scratch stores, the median
// scratch, `dyn` (recomputed from the policy: restore forces it), the scenery cells (rebuilt from
// the saved reach) and StepStats/push_events (describe the last step only; empty after restore).
// The kept pair list is saved as where it was searched (world_pair_list.cpp says why that is
// enough), and whether the next list's search was begun in three parts (its positions follow from
// the saved bodies; its grid, next_grid, is scratch the restored world builds when it finishes).
// Not saved because it is configuration, checked by the config hash instead: WorldSettings other
// than iterations, the scenery shapes, the parameter table.
#include <cmath>
#include <cstring>
#include <exception>
#include <limits>
#include <string>
#include <type_traits>

#include "throng/world/world.h"
#include "world/param_codec.h"
#include "world/settings_fields.h"
#include "world/body_limits.h"
#include "world/world_impl.h"
#include "world/world_state.h"

namespace throng {
namespace {

constexpr std::size_t kMaxSlots = std::size_t{ObjectId::kMaxIndex} + 1;
constexpr std::size_t kMaxCameras = 1u << 20;

// FNV-1a over the bytes of each value: a dozen lines, no allocation (XXH3's streaming state
// allocates, and save_state must not).
struct Fnv {
  std::uint64_t h = 14695981039346656037ull;
  template <class T>
  void add(const T& v) {
    unsigned char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    for (unsigned char c : b) h = (h ^ c) * 1099511628211ull;
  }
};

// f64 columns as eight byte planes (byte 0 of every value, then byte 1, ...; bytes little-endian).
// Why: the sign, exponent and leading mantissa bytes of neighbouring positions and velocities
// repeat, and zstd finds them once they are adjacent: about 6% of a battle keyframe.
void put_planes(ByteWriter& w, const std::vector<double>& col) {
  const std::size_t n = col.size();
  w.put(static_cast<std::uint32_t>(n));
  std::uint8_t* p = w.grow(n * 8);
  for (std::size_t i = 0; i < n; ++i) {
    std::uint64_t b = 0;
    std::memcpy(&b, &col[i], 8);
    for (std::size_t k = 0; k < 8; ++k) p[k * n + i] = static_cast<std::uint8_t>(b >> (8 * k));
  }
}

void get_planes(ByteReader& r, std::vector<double>& col, std::size_t n) {
  const std::uint32_t count = r.get_count("body column", n);
  if (count != n) r.fail("body column: " + std::to_string(count) + " entries, expected " + std::to_string(n));
  const std::uint8_t* p = r.take(n * 8, "body column");
  col.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    std::uint64_t b = 0;
    for (std::size_t k = 0; k < 8; ++k) b |= std::uint64_t{p[k * n + i]} << (8 * k);
    std::memcpy(&col[i], &b, 8);
  }
}

std::string hex(std::uint64_t v) {
  static const char* digits = "0123456789abcdef";
  std::string s(16, '0');
  for (int i = 15; i >= 0; --i, v >>= 4) s[static_cast<std::size_t>(i)] = digits[v & 15];
  return s;
}

}  // namespace

std::uint64_t World::Impl::config_hash() const {
  Fnv f;
  // Every field of the settings table but iterations (set_iterations is state, saved as such), in
  // the table's order; a flag as one byte. Not threads: the thread count never changes a result.
  for (const detail::SettingField& field : detail::kSettingFields) {
    if (field.u32 == &WorldSettings::iterations) continue;
    switch (field.type) {
      case detail::SettingField::Type::f64: f.add(settings.*field.f64); break;
      case detail::SettingField::Type::u32: f.add(settings.*field.u32); break;
      case detail::SettingField::Type::boolean: f.add(static_cast<std::uint8_t>(settings.*field.boolean)); break;
    }
  }
  f.add(static_cast<std::uint64_t>(scenery.size()));
  for (ObjectId id : fixed_ids) f.add(id.value);
  return f.h;
}

void World::Impl::save_state(ByteWriter& w) const {
  const std::size_t n = bodies.size();
  w.put(detail::kWorldStateMagic);
  w.put(detail::kWorldStateVersion);
  w.put(config_hash());
  w.put(tick);
  w.put(settings.iterations);
  w.put(static_cast<std::uint32_t>(n));
  w.put(static_cast<std::uint32_t>(slots.size()));
  w.put(static_cast<std::uint32_t>(fixed_params.size()));
  // Slots as three columns (Slot has padding).
  std::uint8_t* p = w.grow(slots.size() * 9);
  for (const Slot& s : slots) { std::memcpy(p, &s.generation, 4); p += 4; }
  for (const Slot& s : slots) *p++ = static_cast<std::uint8_t>(s.kind);
  for (const Slot& s : slots) { std::memcpy(p, &s.ref, 4); p += 4; }
  w.put_array(free_slots);
  detail::put_params(w, fixed_params);
  w.put(static_cast<std::uint8_t>(scenery_dirty ? 1 : 0));
  w.put(max_body_reach_m);
  w.put(scenery_reach_m);
  // Every column but the ids: the slots above say which slot refers to which dense index.
  bodies.for_each_column([&](const auto& col) {
    using Col = std::decay_t<decltype(col)>;
    if constexpr (std::is_same_v<Col, std::vector<double>>) {
      put_planes(w, col);
    } else if constexpr (!std::is_same_v<Col, std::vector<ObjectId>>) {
      w.put_array(col);
    }
  });
  // Warm-start entries: only the first warm_count of each body's kWarmSlots are ever read.
  std::uint32_t warm_total = 0;
  for (std::size_t i = 0; i < n; ++i) warm_total += bodies.warm_count[i];
  w.put(warm_total);
  p = w.grow(std::size_t{warm_total} * 12);
  for (std::size_t i = 0; i < n; ++i) {
    for (std::uint32_t k = 0; k < bodies.warm_count[i]; ++k) {
      const detail::WarmEntry& e = bodies.warm[i * detail::kWarmSlots + k];
      // Written as f64 (the format predates float pushes; the widening is exact).
      const double lambda = e.lambda;
      std::memcpy(p, &e.partner, 4);
      std::memcpy(p + 4, &lambda, 8);
      p += 12;
    }
  }
  // A body's object id is its id; the records in dense order, whether settled or not.
  detail::put_params(w, body_params, detail::ObjectIdField::left_out, params_order);
  w.put(static_cast<std::uint32_t>(cameras.size()));
  for (const Vec3& c : cameras) { w.put(c.x); w.put(c.y); w.put(c.z); }
  w.put(static_cast<std::uint8_t>(all_coefficients_dirty ? 1 : 0));
  detail::put_groups(w, groups);
  // Morale counts of the running period, sparse (the tables have 65,536 entries, few non-zero).
  const bool present = !morale_allies.empty();
  w.put(static_cast<std::uint8_t>(present ? 1 : 0));
  std::uint32_t nonzero = 0;
  if (present) {
    for (std::size_t g = 0; g < morale_allies.size(); ++g) nonzero += (morale_allies[g] | morale_enemies[g]) != 0 ? 1u : 0u;
  }
  w.put(nonzero);
  if (present) {
    for (std::uint32_t g = 0; g < morale_allies.size(); ++g) {
      if ((morale_allies[g] | morale_enemies[g]) == 0) continue;
      w.put(g);
      w.put(morale_allies[g]);
      w.put(morale_enemies[g]);
    }
  }
  w.put(policy_version);
  detail::put_policy(w, policy);
  // The kept pair list: only where it was searched (the restored world searches there again and
  // takes the pushes from the warm-start cache above), in the dense order.
  // A world restored from such a checkpoint and not stepped since still holds them as restored.
  w.put(list.kept_ticks);
  w.put(list.cooldown);
  w.put(list.backoff);
  const ListRecord record = list_record();
  w.put(list_record_byte());
  if (record == ListRecord::kKept) {
    for (const std::vector<double>* col : {&list.x, &list.y, &list.z}) {
      w.put(static_cast<std::uint32_t>(n));
      p = w.grow(n * 8);
      for (std::size_t s = 0; s < n; ++s) std::memcpy(p + std::size_t{solver_order[s]} * 8, &(*col)[s], 8);
    }
  } else if (record == ListRecord::kPending) {
    w.put_array(list.restored_x);
    w.put_array(list.restored_y);
    w.put_array(list.restored_z);
  }
}

namespace detail {

WorldState decode_world_state(ByteReader& r) {
  WorldState st;
  const auto magic = r.get<std::uint32_t>("world magic");
  if (magic != kWorldStateMagic) r.fail("not a world state section (magic " + hex(magic) + ")");
  const auto version = r.get<std::uint32_t>("world version");
  if (version < kOldestWorldStateVersion || version > kWorldStateVersion) {
    r.fail("world state version " + std::to_string(version) + " (this build reads " + std::to_string(kOldestWorldStateVersion) +
           " to " + std::to_string(kWorldStateVersion) + ")");
  }
  st.config_hash = r.get<std::uint64_t>("world config hash");
  st.tick = r.get<std::uint64_t>("world tick");
  st.iterations = r.get<std::uint32_t>("iterations");
  const std::uint32_t n = r.get_count("body count", kMaxSlots);
  const std::uint32_t ns = r.get_count("slot count", kMaxSlots);
  const std::uint32_t nf = r.get_count("fixed count", kMaxSlots);
  const std::uint8_t* p = r.take(std::size_t{ns} * 9, "slots");  // before sizing anything by ns
  st.slot_generation.resize(ns);
  st.slot_kind.resize(ns);
  st.slot_ref.resize(ns);
  if (ns != 0) {
    std::memcpy(st.slot_generation.data(), p, std::size_t{ns} * 4);
    std::memcpy(st.slot_kind.data(), p + std::size_t{ns} * 4, ns);
    std::memcpy(st.slot_ref.data(), p + std::size_t{ns} * 5, std::size_t{ns} * 4);
  }
  r.get_array(st.free_slots, "free slots", ns);
  get_params(r, nf, st.fixed_params, "fixed params");
  st.scenery_dirty = r.get_bool("scenery dirty");
  st.max_body_reach_m = r.get<double>("max body reach");
  st.scenery_reach_m = r.get<double>("scenery reach");
  // The scenery cells are built for the largest reach plus 1 m. Found by fuzzing: a restored reach
  // of 1e9 m made the next step allocate scenery cells without end.
  if (!(st.max_body_reach_m >= 0.0 && st.max_body_reach_m <= kMaxBodyReachM) ||
      !(st.scenery_reach_m >= 0.0 && st.scenery_reach_m <= kMaxBodyReachM + 1.0)) {
    r.fail("body reach " + std::to_string(st.max_body_reach_m) + " / scenery reach " + std::to_string(st.scenery_reach_m) +
           " out of range");
  }
  st.bodies.for_each_column([&](auto& col) {
    using Col = std::decay_t<decltype(col)>;
    if constexpr (std::is_same_v<Col, std::vector<ObjectId>>) {
      if (version >= 3) return;  // named by the slots, below
    }
    if constexpr (std::is_same_v<Col, std::vector<double>>) {
      if (version >= 3) return get_planes(r, col, n);
    }
    r.get_array_exact(col, "body column", n);
  });
  if (version >= 3) {
    // Each body slot names its dense index; every index must be named exactly once (checked with the
    // slots below: an index no slot names keeps the invalid id 0).
    st.bodies.id.assign(n, ObjectId{});
    std::uint32_t body_slots = 0;
    for (std::uint32_t s = 0; s < ns; ++s) {
      if (st.slot_kind[s] != 1) continue;
      ++body_slots;
      if (st.slot_ref[s] < n) st.bodies.id[st.slot_ref[s]] = ObjectId::make(s, st.slot_generation[s]);
    }
    if (body_slots != n) r.fail(std::to_string(body_slots) + " body slots for " + std::to_string(n) + " bodies");
  }
  st.bodies.warm.assign(std::size_t{n} * kWarmSlots, WarmEntry{0, 0.0f});
  std::uint32_t warm_total = 0;
  for (std::uint32_t i = 0; i < n; ++i) {
    if (st.bodies.warm_count[i] > kWarmSlots) r.fail("warm count " + std::to_string(st.bodies.warm_count[i]) + " > 8");
    warm_total += st.bodies.warm_count[i];
  }
  if (r.get<std::uint32_t>("warm total") != warm_total) r.fail("warm entry total disagrees with the warm counts");
  p = r.take(std::size_t{warm_total} * 12, "warm entries");
  for (std::uint32_t i = 0; i < n; ++i) {
    for (std::uint32_t k = 0; k < st.bodies.warm_count[i]; ++k) {
      WarmEntry& e = st.bodies.warm[std::size_t{i} * kWarmSlots + k];
      double lambda;
      std::memcpy(&e.partner, p, 4);
      std::memcpy(&lambda, p + 4, 8);
      // Only pushes > 0 are stored; anything else would put NaN or a pull into the next solve.
      if (!(lambda > 0.0 && lambda <= std::numeric_limits<float>::max())) {
        r.fail("warm-start push " + std::to_string(lambda) + " of body " + std::to_string(i) + " is not in (0, FLT_MAX]");
      }
      e.lambda = static_cast<float>(lambda);
      p += 12;
    }
  }
  // What the public API guarantees of every body (create_body, set_position, set_desired_velocity
  // and the step keep positions, velocities and pushes finite, radius and half height in range):
  // a checkpoint may not bring in what no call could have made. Found by fuzzing: a NaN position
  // was accepted and reached the grids' cell keys (a float-to-integer conversion) in the next step.
  {
    const BodyStore& b = st.bodies;
    for (std::uint32_t i = 0; i < n; ++i) {
      for (const double v : {b.x[i], b.y[i], b.z[i], b.vx[i], b.vy[i], b.vz[i], b.ax[i], b.ay[i], b.az[i], b.push_x[i],
                             b.push_y[i], b.resistance[i]}) {
        if (!std::isfinite(v)) r.fail("body " + std::to_string(i) + " has a non-finite position, velocity, push or resistance");
      }
      // set_desired_velocity's limit (found by fuzzing: a 1e33 m/s desire reached the scenery sweep).
      if (b.vx[i] * b.vx[i] + b.vy[i] * b.vy[i] + b.vz[i] * b.vz[i] > kMaxDesiredSpeedMps * kMaxDesiredSpeedMps) {
        r.fail("body " + std::to_string(i) + " has a desired speed above 1000 m/s");
      }
      if (!(b.r[i] >= kMinBodyRadiusM && b.r[i] <= kMaxBodyRadiusM) ||
          !(b.hh[i] >= 0.0 && b.hh[i] <= kMaxBodyHalfHeightM)) {
        r.fail("body " + std::to_string(i) + " radius " + std::to_string(b.r[i]) + " / half height " +
               std::to_string(b.hh[i]) + " out of range");
      }
      if (b.morale_level[i] < -1 || b.morale_level[i] > 1) {
        r.fail("body " + std::to_string(i) + " morale level " + std::to_string(b.morale_level[i]));
      }
    }
  }
  if (version >= 3) {
    get_params(r, n, st.body_params, "body params", ObjectIdField::left_out);
    for (std::uint32_t d = 0; d < n; ++d) st.body_params[d].object_id = st.bodies.id[d].value;
  } else {
    get_params(r, n, st.body_params, "body params");
  }
  st.cameras.resize(r.get_count("cameras", kMaxCameras, 24));
  for (Vec3& c : st.cameras) {
    c.x = r.get<double>("camera");
    c.y = r.get<double>("camera");
    c.z = r.get<double>("camera");
  }
  st.all_coefficients_dirty = r.get_bool("coefficients dirty");
  st.groups = get_groups(r);
  st.morale_counts_present = r.get_bool("morale counts present");
  const std::uint32_t nonzero = r.get_count("morale counts", params::kMaxGroupId + 1, 12);
  if (st.morale_counts_present) {
    st.morale_allies.assign(params::kMaxGroupId + 1, 0);
    st.morale_enemies.assign(params::kMaxGroupId + 1, 0);
  } else if (nonzero != 0) {
    r.fail("morale counts listed but marked absent");
  }
  for (std::uint32_t k = 0; k < nonzero; ++k) {
    const auto g = r.get<std::uint32_t>("morale group");
    if (g > params::kMaxGroupId) r.fail("morale group " + std::to_string(g));
    st.morale_allies[g] = r.get<std::uint32_t>("morale allies");
    st.morale_enemies[g] = r.get<std::uint32_t>("morale enemies");
  }
  st.policy_version = r.get<std::uint64_t>("policy version");
  st.policy = get_policy(r);
  st.pair_list_kept_ticks = r.get<std::uint32_t>("pair list kept ticks");
  st.pair_list_cooldown = r.get<std::uint32_t>("pair list cooldown");
  st.pair_list_backoff = r.get<std::uint32_t>("pair list backoff");
  if (st.pair_list_cooldown > kPairListMaxCooldownTicks ||
      st.pair_list_backoff < kPairListCooldownTicks ||
      st.pair_list_backoff > kPairListMaxCooldownTicks) {
    r.fail("pair list cooldown " + std::to_string(st.pair_list_cooldown) + " / backoff " +
           std::to_string(st.pair_list_backoff) + " out of range");
  }
  const auto kept = r.get<std::uint8_t>("pair list kept");
  if (kept > (version >= 4 ? 2 : 1)) r.fail("pair list kept " + std::to_string(kept) + " is not a known value");
  st.pair_list_kept = kept != 0;
  st.pair_list_ahead_begun = kept == 2;
  if (st.pair_list_kept) {
    for (std::vector<double>* col : {&st.pair_list_x, &st.pair_list_y, &st.pair_list_z}) {
      r.get_array_exact(*col, "pair list positions", n);
      for (const double v : *col) {
        if (!std::isfinite(v)) r.fail("pair list position is not finite");
      }
    }
  }

  // Consistency: every body's id names a body slot that points back at it; slots point inside
  // their arrays; the free list holds distinct free slots. What step() indexes with is checked here.
  for (std::uint32_t s = 0; s < ns; ++s) {
    const std::uint8_t kind = st.slot_kind[s];
    if (kind > 2) r.fail("slot " + std::to_string(s) + " has kind " + std::to_string(kind));
    if (kind == 1 && st.slot_ref[s] >= n) r.fail("slot " + std::to_string(s) + " refers to body " + std::to_string(st.slot_ref[s]) + " of " + std::to_string(n));
    if (kind == 2 && st.slot_ref[s] >= nf) r.fail("slot " + std::to_string(s) + " refers to fixed shape " + std::to_string(st.slot_ref[s]));
  }
  for (std::uint32_t d = 0; d < n; ++d) {
    const ObjectId id = st.bodies.id[d];
    const std::uint32_t s = id.index();
    if (!id.valid() || s >= ns || st.slot_kind[s] != 1 || st.slot_ref[s] != d ||
        (st.slot_generation[s] & ObjectId::kGenerationMask) != id.generation()) {
      r.fail("body " + std::to_string(d) + " (id " + std::to_string(id.value) + ") does not match its slot");
    }
  }
  std::vector<std::uint8_t> listed(ns, 0);
  for (std::uint32_t s : st.free_slots) {
    if (s >= ns || st.slot_kind[s] != 0 || listed[s] != 0) r.fail("free list entry " + std::to_string(s) + " is not a distinct free slot");
    listed[s] = 1;
  }
  return st;
}

}  // namespace detail

void World::Impl::apply_state(detail::WorldState&& st) {
  // Checks against this world first: nothing below the commit line may throw.
  const std::uint64_t mine = config_hash();
  if (st.config_hash != mine) {
    throw CheckpointError("world checkpoint is from another configuration (world settings or scenery differ): hash " +
                          hex(st.config_hash) + ", this world " + hex(mine));
  }
  if (st.fixed_params.size() != fixed_ids.size()) {
    throw CheckpointError("world checkpoint has " + std::to_string(st.fixed_params.size()) + " fixed objects, this world " +
                          std::to_string(fixed_ids.size()));
  }
  for (std::size_t k = 0; k < fixed_ids.size(); ++k) {
    const std::uint32_t s = fixed_ids[k].index();
    if (s >= st.slot_kind.size() || st.slot_kind[s] != 2 || st.slot_ref[s] != k ||
        (st.slot_generation[s] & ObjectId::kGenerationMask) != fixed_ids[k].generation()) {
      throw CheckpointError("world checkpoint: fixed object " + std::to_string(fixed_ids[k].value) + " is not in its slot");
    }
  }
  WorldSettings s = settings;
  s.iterations = st.iterations;
  params::GroupTable g(groups.morale_config());
  try {
    s.validate();
    for (const auto& [id, group] : st.groups) g.set(id, group);
  } catch (const std::exception& e) {
    throw CheckpointError(std::string("world checkpoint does not validate: ") + e.what());
  }

  // Commit.
  settings = s;
  tick = st.tick;
  last_reorder.clear();  // a restore sets the saved order; callers realign with id_at
  slots.resize(st.slot_kind.size());
  for (std::size_t i = 0; i < slots.size(); ++i) {
    slots[i] = Slot{st.slot_generation[i], static_cast<SlotKind>(st.slot_kind[i]), st.slot_ref[i]};
  }
  free_slots = std::move(st.free_slots);
  fixed_params = std::move(st.fixed_params);
  bodies = std::move(st.bodies);
  cell0_dirty = true;
  // The next step searches a kept list again where the saved world searched it (world_pair_list.cpp).
  list.valid = false;
  list.searched_ahead = false;
  list.restore_pending = st.pair_list_kept;
  list.kept_ticks = st.pair_list_kept_ticks;
  list.cooldown = st.pair_list_cooldown;
  list.backoff = st.pair_list_backoff;
  list.restored_x = std::move(st.pair_list_x);
  list.restored_y = std::move(st.pair_list_y);
  list.restored_z = std::move(st.pair_list_z);
  list.scan_complete = false;
  list.ahead_built = false;
  list.ahead_begun = st.pair_list_ahead_begun;
  if (list.ahead_begun) predict_begun_ahead();  // where the saved world began it, from the same state
  body_params = std::move(st.body_params);
  params_order.clear();
  cameras = std::move(st.cameras);
  all_coefficients_dirty = st.all_coefficients_dirty;
  groups = std::move(g);
  morale_allies = std::move(st.morale_allies);
  morale_enemies = std::move(st.morale_enemies);
  policy = std::move(st.policy);
  policy_version = st.policy_version;
  dyn.policy_version = ~policy_version;  // derived from the policy: recomputed at the next step
  max_body_reach_m = st.max_body_reach_m;
  if (st.scenery_dirty) {
    scenery_dirty = true;  // the next step builds the scenery and its cells, as the saved world would have
    scenery_reach_m = st.scenery_reach_m;
    scenery_cells.clear();
  } else {
    rebuild_scenery_cells(st.scenery_reach_m);
  }
  event_count = 0;
  stats = StepStats{};
}

void World::save_state(ByteWriter& out) const { impl_->save_state(out); }

void World::save_state(std::vector<std::uint8_t>& out) const {
  ByteWriter w(out, ByteWriter::kOverwrite);
  impl_->save_state(w);
  w.finish();
}

void World::restore_state(ByteReader& in) { impl_->apply_state(detail::decode_world_state(in)); }

void World::restore_state(std::span<const std::uint8_t> bytes) { restore_state(bytes, {}); }

void World::restore_state(std::span<const std::uint8_t> bytes,
                          const std::function<void(std::span<const ObjectId> body_ids)>& check_bodies) {
  ByteReader r(bytes);
  detail::WorldState st = detail::decode_world_state(r);
  if (r.remaining() != 0) r.fail(std::to_string(r.remaining()) + " bytes after the world state");
  if (check_bodies) check_bodies(st.bodies.id);
  impl_->apply_state(std::move(st));
}

}  // namespace throng
