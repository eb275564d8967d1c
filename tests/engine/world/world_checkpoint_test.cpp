// World::save_state / restore_state: a restored world steps bit-identically to the original, on
// every built-in scene and across the 16-tick dense re-sort; bad bytes throw CheckpointError and
// leave the world unchanged; diff_world_states names exactly the perturbed bodies.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "throng/core/byte_io.h"
#include "throng/params/object_params.h"
#include "throng/params/push_policy.h"
#include "throng/scene/build_scene.h"
#include "throng/scene/builtin_scenes.h"
#include "throng/scene/scale.h"
#include "throng/world/world.h"
#include "throng/world/world_state_diff.h"

namespace throng {
namespace {
// World::Impl::config_hash() of pinned_settings() with no scenery (see ConfigHashOfFixedSettingsIsPinned).
// The settings are the defaults of the day the value was pinned: a later change of a default must
// not move the pin, as the pin is about how the hash is taken.
// Re-pinned when the extra_iterations row was added (a new row is a new hash for every config).
constexpr std::uint64_t kPinnedConfigHash = 0xc92067cd50382f14ull;
WorldSettings pinned_settings() {
  WorldSettings s;
  s.conflict_share_limit = 0.25;
  s.extra_iterations = 16;
  return s;
}

using Bytes = std::vector<std::uint8_t>;

scene::SceneDef small(const std::string& name) {
  scene::SceneDef s = scene::builtin_scene(name);
  return name == "one_cell" ? s : scene::scale_scene(s, 400);
}

void run(scene::BuiltScene& b, int ticks) {
  for (int t = 0; t < ticks; ++t) {
    b.driver.apply(b.world);
    b.world.step();
  }
}

// Steers every body towards the origin (for worlds whose bodies no longer match the driver's).
void steer_in(World& w) {
  for (std::size_t d = 0; d < w.body_count(); ++d) {
    w.set_desired_velocity(w.id_at(d), Vec3{-0.1 * w.pos_x()[d], -0.1 * w.pos_y()[d], 0.0});
  }
}

// Runs the original to `k`, restores its state into a freshly built copy, then steps both and
// compares every tick's hash and the final state bytes.
void expect_continuation(const scene::SceneDef& def, int k, int more) {
  scene::BuiltScene a = scene::build_scene(def);
  run(a, k);
  Bytes saved;
  a.world.save_state(saved);
  scene::BuiltScene b = scene::build_scene(def);
  b.world.restore_state(saved);
  Bytes again;
  b.world.save_state(again);
  ASSERT_EQ(saved, again) << "round trip changed the bytes";
  ASSERT_EQ(a.world.state_hash(), b.world.state_hash());
  for (int t = 0; t < more; ++t) {
    a.driver.apply(a.world);
    b.driver.apply(b.world);
    a.world.step();
    b.world.step();
    ASSERT_EQ(a.world.state_hash(), b.world.state_hash()) << def.name << ": k " << k << ", tick " << a.world.tick();
  }
  a.world.save_state(saved);
  b.world.save_state(again);
  EXPECT_EQ(saved, again);
}

TEST(WorldCheckpoint, BuiltinScenesContinueBitIdentically) {
  for (const std::string& name : scene::builtin_scene_names()) {
    SCOPED_TRACE(name);
    for (int k : {0, 1, 15, 16, 17, 40}) expect_continuation(small(name), k, 60);
  }
}

// Destroyed and re-created bodies (free-list reuse, generations), runtime parameters, policy and
// group morale changes, cameras and the iteration budget are all part of the state.
TEST(WorldCheckpoint, RuntimeChangesAreCarried) {
  const scene::SceneDef def = small("mixed");
  auto mutate = [](scene::BuiltScene& b) {
    World& w = b.world;
    w.destroy_body(b.body_ids[3]);
    w.destroy_body(b.body_ids[7]);
    BodyDef d;
    d.position = {0.5, 0.5, 0.9};
    d.radius_m = 0.45;
    w.create_body(d);  // reuses slot 7 (LIFO)
    w.set_param(b.body_ids[10], params::Param::weight_kg, 400.0);
    w.set_policy(params::PushPolicy(params::PushMode::ratio, {params::Term{params::TermInput::weight_kg, 1.0, 50.0, false},
                                                              params::Term{params::TermInput::camera_distance_m, 1.0, 100.0, false}},
                                    {}));
    const Vec3 cams[] = {{1.0, 2.0, 1.7}, {-5.0, 0.0, 1.7}};
    w.set_cameras(cams);
    w.set_iterations(12);
  };
  scene::BuiltScene a = scene::build_scene(def);
  run(a, 10);
  mutate(a);
  for (int t = 0; t < 7; ++t) {  // k = 17: just after a re-sort
    steer_in(a.world);
    a.world.step();
  }
  Bytes saved;
  a.world.save_state(saved);
  scene::BuiltScene b = scene::build_scene(def);
  b.world.restore_state(saved);
  EXPECT_EQ(b.world.body_count(), a.world.body_count());
  EXPECT_EQ(b.world.settings().iterations, 12u);
  EXPECT_EQ(b.world.params(a.body_ids[10]).weight_kg, 400.0);
  EXPECT_FALSE(b.world.is_body(a.body_ids[3]));
  for (int t = 0; t < 80; ++t) {
    steer_in(a.world);
    steer_in(b.world);
    a.world.step();
    b.world.step();
    ASSERT_EQ(a.world.state_hash(), b.world.state_hash()) << "tick " << a.world.tick();
  }
  // The next created body gets the same id in both (slot 3 next on the free list).
  BodyDef d;
  d.position = {3.0, 3.0, 0.9};
  EXPECT_EQ(a.world.create_body(d), b.world.create_body(d));
}

// Where a world state section's slot table and body columns are (world/CHECKPOINT.md): the header
// is 40 bytes, then the slots (generations, kinds, dense references), the free list, the fixed
// objects' parameters (120 bytes each), 17 bytes of reach, then the body columns.
struct WorldLayout {
  std::uint32_t n = 0, ns = 0, nf = 0;
  std::size_t slots = 40, kinds = 0, refs = 0, columns = 0;
};
WorldLayout world_layout(const Bytes& b) {
  WorldLayout l;
  std::memcpy(&l.n, b.data() + 28, 4);
  std::memcpy(&l.ns, b.data() + 32, 4);
  std::memcpy(&l.nf, b.data() + 36, 4);
  l.kinds = l.slots + 4 * std::size_t{l.ns};
  l.refs = l.kinds + l.ns;
  std::uint32_t free_count = 0;
  std::memcpy(&free_count, b.data() + l.refs + 4 * std::size_t{l.ns}, 4);
  l.columns = l.refs + 4 * std::size_t{l.ns} + 4 + 4 * std::size_t{free_count} + 120 * std::size_t{l.nf} + 17;
  return l;
}

// Version 2 (logs of earlier builds) held every body's id as a column after `grounded` and as the
// first field of its parameter record; version 3 names the bodies by the slot table only. A
// version 2 section of the same world restores to the same state, with destroyed and re-created
// bodies (generations) among them.
TEST(WorldCheckpoint, VersionTwoWithItsIdColumnStillRestores) {
  const scene::SceneDef def = small("mixed");
  scene::BuiltScene a = scene::build_scene(def);
  run(a, 10);
  a.world.destroy_body(a.body_ids[3]);
  a.world.destroy_body(a.body_ids[7]);
  BodyDef nd;
  nd.position = {0.5, 0.5, 0.9};
  a.world.create_body(nd);  // slot 7 again, next generation
  for (int t = 0; t < 7; ++t) {
    steer_in(a.world);
    a.world.step();
  }
  Bytes now;
  a.world.save_state(now);
  const WorldLayout l = world_layout(now);
  std::uint32_t version = 0;
  std::memcpy(&version, now.data() + 4, 4);
  ASSERT_EQ(version, 4u);  // this build's (4 differs from 3 only in the pair list's kept byte)
  // 13 f64 columns (x .. hh) and grounded, each with its u32 count; the ids follow grounded.
  // The body columns, each a u32 count then n values: 13 f64 (x .. hh), grounded (u8), [version 2:
  // the ids], resistance (f64), rule_lhs, rule_rhs, group, mask (u32), coeff_dirty, morale_level,
  // warm_count (u8). Versions 3 and 4 write f64 columns as eight byte planes, version 2 value by value.
  const std::size_t n = l.n;
  Bytes v2(now.begin(), now.begin() + static_cast<std::ptrdiff_t>(l.columns));
  v2[4] = 2;
  const auto put_u32 = [&v2](std::uint32_t v) {
    const auto* p = reinterpret_cast<const std::uint8_t*>(&v);
    v2.insert(v2.end(), p, p + 4);
  };
  std::size_t at = l.columns;
  const std::vector<std::size_t> sizes = {8, 8, 8, 8, 8, 8, 8, 8, 8, 8, 8, 8, 8, 1, 0, 8, 4, 4, 4, 4, 1, 1, 1};
  for (const std::size_t size : sizes) {
    if (size == 0) {  // the ids, after grounded
      put_u32(l.n);
      for (std::size_t d = 0; d < n; ++d) put_u32(a.world.id_at(d).value);
      continue;
    }
    v2.insert(v2.begin() + static_cast<std::ptrdiff_t>(v2.size()), now.begin() + static_cast<std::ptrdiff_t>(at),
              now.begin() + static_cast<std::ptrdiff_t>(at + 4));
    at += 4;
    for (std::size_t i = 0; i < n; ++i) {
      for (std::size_t k = 0; k < size; ++k) v2.push_back(size == 8 ? now[at + k * n + i] : now[at + i * size + k]);
    }
    at += n * size;
  }
  // Then the warm entries (a u32 total, 12 bytes each), the body parameter records (116 bytes in
  // versions 3 and 4, 120 with the object id in front in version 2) and the rest as it is.
  std::uint32_t warm_total = 0;
  std::memcpy(&warm_total, now.data() + at, 4);
  const std::size_t params_at = at + 4 + 12 * std::size_t{warm_total};
  v2.insert(v2.end(), now.begin() + static_cast<std::ptrdiff_t>(at), now.begin() + static_cast<std::ptrdiff_t>(params_at));
  for (std::size_t d = 0; d < n; ++d) {
    put_u32(a.world.id_at(d).value);
    const auto rec = now.begin() + static_cast<std::ptrdiff_t>(params_at + 116 * d);
    v2.insert(v2.end(), rec, rec + 116);
  }
  v2.insert(v2.end(), now.begin() + static_cast<std::ptrdiff_t>(params_at + 116 * n), now.end());
  ASSERT_EQ(v2.size(), now.size() + 4 + 8 * n);  // the id column (count and ids) and the records' ids

  scene::BuiltScene b = scene::build_scene(def);
  b.world.restore_state(v2);
  Bytes again;
  b.world.save_state(again);
  EXPECT_EQ(again, now);
  EXPECT_EQ(b.world.state_hash(), a.world.state_hash());
  for (std::size_t d = 0; d < l.n; ++d) {
    ASSERT_EQ(b.world.id_at(d), a.world.id_at(d)) << d;
    ASSERT_EQ(b.world.params(b.world.id_at(d)).object_id, b.world.id_at(d).value) << d;
  }
  EXPECT_FALSE(b.world.is_body(a.body_ids[7]));
  for (int t = 0; t < 20; ++t) {
    steer_in(a.world);
    steer_in(b.world);
    a.world.step();
    b.world.step();
    ASSERT_EQ(a.world.state_hash(), b.world.state_hash()) << "tick " << a.world.tick();
  }

  // Version 3's and 4's slots must name every body exactly once: two slots referring to one dense index
  // leave another unnamed.
  std::vector<std::uint32_t> body_slots;
  for (std::uint32_t sl = 0; sl < l.ns && body_slots.size() < 2; ++sl) {
    if (now[l.kinds + sl] == 1) body_slots.push_back(sl);
  }
  ASSERT_EQ(body_slots.size(), 2u);
  Bytes bad = now;
  std::memcpy(bad.data() + l.refs + 4 * body_slots[1], now.data() + l.refs + 4 * body_slots[0], 4);
  scene::BuiltScene c = scene::build_scene(def);
  try {
    c.world.restore_state(bad);
    ADD_FAILURE() << "two slots naming one body were accepted";
  } catch (const CheckpointError& e) {
    EXPECT_NE(std::string(e.what()).find("does not match its slot"), std::string::npos) << e.what();
  }
  // A free slot made a body slot: one body slot more than bodies.
  bad = now;
  std::uint32_t free_slot = l.ns;
  for (std::uint32_t sl = 0; sl < l.ns; ++sl) {
    if (now[l.kinds + sl] == 0) free_slot = sl;
  }
  ASSERT_LT(free_slot, l.ns);
  bad[l.kinds + free_slot] = 1;
  try {
    c.world.restore_state(bad);
    ADD_FAILURE() << "a body slot too many was accepted";
  } catch (const CheckpointError& e) {
    EXPECT_NE(std::string(e.what()).find("body slots for"), std::string::npos) << e.what();
  }
}

// Version 4 only added the pair list's kept byte 2 (the next list's search begun in three parts,
// world_pair_list.cpp): a version-3 checkpoint is a version-4 one that never says 2. This build
// restores one bit-identically, and refuses a 2 under version 3 and a 3 under any version.
TEST(WorldCheckpoint, VersionThreeStillRestoresAndCannotSayASearchWasBegun) {
  const scene::SceneDef def = scene::scale_scene(scene::builtin_scene("crush"), 3000);
  scene::BuiltScene a = scene::build_scene(def);
  // The kept byte sits before the list's three position arrays (u32 count, then n f64) at the end.
  const std::size_t n = a.world.body_count();
  const auto kept_at = [n](const Bytes& b) { return b.size() - 3 * (4 + 8 * n) - 1; };
  Bytes kept, begun;
  for (int t = 0; t < 200 && (kept.empty() || begun.empty()); ++t) {
    a.driver.apply(a.world);
    const StepStats st = a.world.step();
    Bytes saved;
    a.world.save_state(saved);
    if (st.pair_list_reused == 0 || saved.size() < 3 * (4 + 8 * n) + 1) continue;
    const std::uint8_t byte = saved[kept_at(saved)];
    if (byte == 1 && st.pair_list_searched_ahead == 0 && kept.empty()) kept = saved;
    if (byte == 2 && st.pair_list_searched_ahead != 0 && begun.empty()) begun = saved;
  }
  ASSERT_FALSE(kept.empty()) << "no kept list";
  ASSERT_FALSE(begun.empty()) << "no search begun in three parts";

  Bytes v3 = kept;
  v3[4] = 3;
  scene::BuiltScene b = scene::build_scene(def);
  scene::BuiltScene c = scene::build_scene(def);
  b.world.restore_state(v3);
  c.world.restore_state(kept);
  EXPECT_EQ(b.world.state_hash(), c.world.state_hash());
  for (int t = 0; t < 20; ++t) {
    steer_in(b.world);
    steer_in(c.world);
    b.world.step();
    c.world.step();
    ASSERT_EQ(b.world.state_hash(), c.world.state_hash()) << "tick " << b.world.tick();
  }

  const auto refused = [&](Bytes bad, const char* what) {
    scene::BuiltScene d = scene::build_scene(def);
    const std::uint64_t before = d.world.state_hash();
    try {
      d.world.restore_state(bad);
      ADD_FAILURE() << what << " was accepted";
    } catch (const CheckpointError& e) {
      EXPECT_NE(std::string(e.what()).find("pair list kept"), std::string::npos) << e.what();
    }
    EXPECT_EQ(d.world.state_hash(), before) << what << " changed the world";
  };
  // The same state without the search begun: the diff names only that, as the world's.
  Bytes not_begun = begun;
  not_begun[kept_at(not_begun)] = 1;
  const std::vector<BodyDifference> d = diff_world_states(begun, not_begun);
  ASSERT_EQ(d.size(), 1u);
  EXPECT_EQ(d[0].object_id, 0u);
  EXPECT_NE(d[0].what.find("pair_list.ahead_begun 1 vs 0"), std::string::npos) << d[0].what;

  Bytes bad = begun;
  bad[4] = 3;
  refused(bad, "a search begun under version 3");
  bad = begun;
  bad[kept_at(bad)] = 3;
  refused(bad, "kept byte 3");
}

// A checkpoint carries a hash of the world's settings (and scenery) and a restore refuses another
// one. The hash walks the settings table (settings_fields.h) row by row, so reordering the table,
// or hashing a field another way, would make every earlier checkpoint and match log unreadable:
// the value for one fixed set of settings (pinned_settings) is pinned here.
// The config hash a world with these settings writes into its checkpoint.
std::uint64_t config_hash_of(const WorldSettings& settings) {
  World w(settings, scene::load_param_table({}), scene::load_push_policy({}));
  std::vector<std::uint8_t> saved;
  w.save_state(saved);
  ByteReader in(saved);
  in.get<std::uint32_t>("magic");
  in.get<std::uint32_t>("version");
  return in.get<std::uint64_t>("config hash");
}

TEST(WorldCheckpoint, ConfigHashOfFixedSettingsIsPinned) {
  EXPECT_EQ(config_hash_of(pinned_settings()), kPinnedConfigHash);
  WorldSettings other = pinned_settings();
  other.blocked_motion_carry = 0.5;
  EXPECT_NE(config_hash_of(other), kPinnedConfigHash) << "a setting must change the hash";
  // The last row too: a log of a match without extra sweeps must not restore into one with them.
  WorldSettings no_extra = pinned_settings();
  no_extra.extra_iterations = 0;
  EXPECT_NE(config_hash_of(no_extra), kPinnedConfigHash) << "extra_iterations must change the hash";
}

TEST(WorldCheckpoint, SaveReusesAWarmBuffer) {
  scene::BuiltScene a = scene::build_scene(small("crush"));
  run(a, 20);
  Bytes out;
  a.world.save_state(out);
  const std::uint8_t* data = out.data();
  const std::size_t size = out.size();
  a.world.save_state(out);
  EXPECT_EQ(out.data(), data);  // same storage: no reallocation
  EXPECT_EQ(out.size(), size);
}

TEST(WorldCheckpoint, BadBytesThrowAndLeaveTheWorldUnchanged) {
  const scene::SceneDef def = small("obstacles");
  scene::BuiltScene a = scene::build_scene(def);
  run(a, 20);
  Bytes saved;
  a.world.save_state(saved);
  scene::BuiltScene b = scene::build_scene(def);
  run(b, 3);
  Bytes before;
  b.world.save_state(before);
  auto expect_error = [&](const Bytes& bytes, const std::string& needle) {
    try {
      b.world.restore_state(bytes);
      ADD_FAILURE() << "no error for " << needle;
    } catch (const CheckpointError& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
    Bytes after;
    b.world.save_state(after);
    ASSERT_EQ(after, before) << "a failed restore changed the world";
  };
  // Truncated at many offsets (every one in the header, then spread over the body).
  for (std::size_t cut = 0; cut < saved.size(); cut += cut < 256 ? 1 : 97) {
    expect_error(Bytes(saved.begin(), saved.begin() + static_cast<std::ptrdiff_t>(cut)), "checkpoint");
  }
  Bytes bad = saved;
  bad[0] ^= 0xFF;
  expect_error(bad, "magic");
  bad = saved;
  bad[4] = 9;
  expect_error(bad, "version");
  bad = saved;
  bad.push_back(0);
  expect_error(bad, "bytes after");
  // Another configuration (other settings) is refused with its reason.
  scene::SceneDef other = def;
  other.settings.contact_margin_m = 0.07;
  scene::BuiltScene c = scene::build_scene(other);
  try {
    c.world.restore_state(saved);
    ADD_FAILURE() << "restored into another configuration";
  } catch (const CheckpointError& e) {
    EXPECT_NE(std::string(e.what()).find("another configuration"), std::string::npos) << e.what();
  }
}

// Found by fuzzing (tests/fuzz world_checkpoint): a checkpoint whose body position is NaN was
// accepted, and the next step converted it to a grid cell coordinate (undefined behavior). Values
// no API call could have made are refused with the body named; the world stays unchanged.
TEST(WorldCheckpoint, NonFiniteBodyStateIsRefused) {
  const scene::SceneDef def = small("obstacles");
  scene::BuiltScene a = scene::build_scene(def);
  run(a, 5);
  Bytes saved;
  a.world.save_state(saved);
  // The x column (the first body column) holds body 0's x as its first entry, written as byte
  // planes: its byte k is at plane k, n bytes apart.
  const WorldLayout l = world_layout(saved);
  const auto at = saved.begin() + static_cast<std::ptrdiff_t>(l.columns + 4);
  const double x0 = a.world.pos_x()[0];
  for (std::size_t k = 0; k < 8; ++k) {
    std::uint64_t bits = 0;
    std::memcpy(&bits, &x0, 8);
    ASSERT_EQ(at[static_cast<std::ptrdiff_t>(k * l.n)], static_cast<std::uint8_t>(bits >> (8 * k))) << k;
  }
  for (const double bad : {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    Bytes damaged = saved;
    std::uint64_t bits = 0;
    std::memcpy(&bits, &bad, 8);
    for (std::size_t k = 0; k < 8; ++k) {
      damaged[l.columns + 4 + k * l.n] = static_cast<std::uint8_t>(bits >> (8 * k));
    }
    scene::BuiltScene b = scene::build_scene(def);
    Bytes before;
    b.world.save_state(before);
    try {
      b.world.restore_state(damaged);
      ADD_FAILURE() << "accepted a body at x = " << bad;
    } catch (const CheckpointError& e) {
      EXPECT_NE(std::string(e.what()).find("body 0 has a non-finite position"), std::string::npos) << e.what();
    }
    Bytes after;
    b.world.save_state(after);
    EXPECT_EQ(after, before);
    b.world.step();  // still steps
  }
  // A body reach beyond any body's (found by fuzzing: the next step built scenery cells without
  // end): the max body reach and the scenery reach are the two doubles before the x column's count.
  for (const std::size_t back : {std::size_t{20}, std::size_t{12}}) {
    Bytes far = saved;
    const double reach = 1e9;
    std::memcpy(&far[static_cast<std::size_t>(at - saved.begin()) - back], &reach, 8);
    scene::BuiltScene b = scene::build_scene(def);
    try {
      b.world.restore_state(far);
      ADD_FAILURE() << "accepted a reach of 1e9 m";
    } catch (const CheckpointError& e) {
      EXPECT_NE(std::string(e.what()).find("reach"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("out of range"), std::string::npos) << e.what();
    }
  }
  // Parameters out of their ranges (found by fuzzing: a NaN parameter was accepted and the next
  // step threw from the push policy): body 0's record holds importance, size and weight in a row.
  {
    const params::ObjectParams& p0 = a.world.params(a.world.id_at(0));
    const double three[3] = {p0.importance, p0.size_m, p0.weight_kg};
    const auto* t = reinterpret_cast<const std::uint8_t*>(three);
    const auto rec = std::search(saved.begin() + (at - saved.begin()), saved.end(), t, t + sizeof(three));
    ASSERT_NE(rec, saved.end());
    Bytes bad = saved;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    std::memcpy(&bad[static_cast<std::size_t>(rec - saved.begin())], &nan, 8);
    scene::BuiltScene b = scene::build_scene(def);
    try {
      b.world.restore_state(bad);
      ADD_FAILURE() << "accepted a NaN importance";
    } catch (const CheckpointError& e) {
      EXPECT_NE(std::string(e.what()).find("body params"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("importance"), std::string::npos) << e.what();
    }
  }
  // A desired velocity beyond set_desired_velocity's 1000 m/s: the vx column starts after the
  // rest of x and the whole y and z columns (each a u32 count, then n doubles).
  const std::size_t n = a.world.body_count();
  const std::size_t vx0 = static_cast<std::size_t>(at - saved.begin()) + 3 * n * 8 + 3 * 4;
  Bytes fast = saved;
  const double too_fast = 2000.0;
  std::uint64_t bits = 0;
  std::memcpy(&bits, &too_fast, 8);
  for (std::size_t k = 0; k < 8; ++k) fast[vx0 + k * n] = static_cast<std::uint8_t>(bits >> (8 * k));  // byte planes
  scene::BuiltScene c = scene::build_scene(def);
  try {
    c.world.restore_state(fast);
    ADD_FAILURE() << "accepted a desired speed of 2000 m/s";
  } catch (const CheckpointError& e) {
    EXPECT_NE(std::string(e.what()).find("body 0 has a desired speed above 1000 m/s"), std::string::npos) << e.what();
  }
}

TEST(WorldCheckpoint, DiffNamesExactlyThePerturbedBodies) {
  // Without a kept pair list: a parameter change or a teleport drops it, which every body's
  // record shows (pair_list_kept), and this test is about the bodies that changed.
  scene::SceneDef def = small("crush");
  def.settings.pair_list_skin_m = 0.0;
  scene::BuiltScene a = scene::build_scene(def);
  scene::BuiltScene b = scene::build_scene(def);
  run(a, 5);
  run(b, 5);
  Bytes sa, sb;
  a.world.save_state(sa);
  b.world.save_state(sb);
  EXPECT_TRUE(diff_world_states(sa, sb).empty());
  const ObjectId p = b.body_ids[17], q = b.body_ids[2];
  b.world.set_param(p, params::Param::weight_kg, 123.0);
  b.world.set_position(q, b.world.position(q) + Vec3{0.0, 0.25, 0.0});
  b.world.save_state(sb);
  const std::vector<BodyDifference> d = diff_world_states(sa, sb);
  ASSERT_EQ(d.size(), 2u);
  EXPECT_EQ(d[0].object_id, std::min(p.value, q.value));
  EXPECT_EQ(d[1].object_id, std::max(p.value, q.value));
  const BodyDifference& dp = d[0].object_id == p.value ? d[0] : d[1];
  const BodyDifference& dq = d[0].object_id == q.value ? d[0] : d[1];
  EXPECT_NE(dp.what.find("params.weight_kg"), std::string::npos) << dp.what;
  EXPECT_NE(dq.what.find("y "), std::string::npos) << dq.what;
  EXPECT_EQ(diff_world_states(sa, sb, 1).size(), 1u);
  EXPECT_THROW(diff_world_states(sa, Bytes(sb.begin(), sb.begin() + 40)), CheckpointError);
}

TEST(WorldCheckpoint, DiffKeepsTheBodiesThatWentFurthestApartWhenMoreDifferThanItReports) {
  // A divergence spreads by rounding-sized amounts to many bodies; the cap must not hide the one
  // that went wrong behind lower object ids.
  scene::SceneDef def = small("crush");
  def.settings.pair_list_skin_m = 0.0;
  scene::BuiltScene a = scene::build_scene(def);
  scene::BuiltScene b = scene::build_scene(def);
  run(a, 5);
  run(b, 5);
  ASSERT_GE(b.body_ids.size(), 30u);
  for (std::size_t i = 0; i < 20; ++i) b.world.set_position(b.body_ids[i], b.world.position(b.body_ids[i]) + Vec3{1e-9, 0.0, 0.0});
  const ObjectId far = b.body_ids[25], weight = b.body_ids[28];
  b.world.set_position(far, b.world.position(far) + Vec3{0.5, 0.0, 0.0});
  b.world.set_param(weight, params::Param::weight_kg, 321.0);
  Bytes sa, sb;
  a.world.save_state(sa);
  b.world.save_state(sb);
  EXPECT_EQ(diff_world_states(sa, sb, 100).size(), 22u);
  const std::vector<BodyDifference> d = diff_world_states(sa, sb, 3);
  ASSERT_EQ(d.size(), 3u);
  std::vector<std::uint32_t> ids;
  for (const BodyDifference& x : d) ids.push_back(x.object_id);
  EXPECT_TRUE(std::is_sorted(ids.begin(), ids.end()));
  EXPECT_NE(std::find(ids.begin(), ids.end(), far.value), ids.end());
  EXPECT_NE(std::find(ids.begin(), ids.end(), weight.value), ids.end());
}

}  // namespace
}  // namespace throng
