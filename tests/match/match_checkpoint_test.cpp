// Match::save_checkpoint / restore_checkpoint: a match restored at tick K into a fresh Match of the
// same scene and config produces, fed the same inputs, the same state hash and the same outbox
// (join/param replies, client events, every snapshot's bytes, match-info republishes) every tick.
// Also: round trip, warm-buffer save, errors (truncation, magic, version, other scene / config)
// that leave the match unchanged, and diff_checkpoints.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <limits>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "match_test_util.h"
#include "matchlog/checkpoint_v1.h"
#include "throng/match/checkpoint_diff.h"
#include "throng/match/match.h"
#include "throng/params/object_params.h"
#include "throng/scene/builtin_scenes.h"
#include "throng/scene/scale.h"
#include "throng/world/world.h"

namespace throng::match {
namespace {

using Bytes = std::vector<std::uint8_t>;

scene::SceneDef small_battle() { return scene::scale_scene(scene::builtin_scene("battle"), 300); }

// Everything the network would be told, as text (so a failure shows what differs).
std::string outbox_text(const Outbox& out, const TickReport& r) {
  std::ostringstream s;
  s << "tick " << r.tick << " hash " << r.state_hash << " info " << out.match_info_changed << "\n";
  for (const auto& j : out.join_replies) {
    s << "join " << j.client_nonce << ' ' << static_cast<int>(j.result) << ' ' << j.reason << ' ' << j.client_id << ' '
      << j.entity << ' ' << j.snapshot_partition << ' ' << j.tick << ' ' << int{j.faction} << "\n";
  }
  for (const auto& p : out.param_replies) {
    s << "param " << p.request_id << ' ' << p.ok << ' ' << p.error << ' ' << p.param_version << ' ' << p.tick << "\n";
  }
  for (const auto& e : out.client_events) {
    s << "event " << static_cast<int>(e.kind) << ' ' << e.client_id << ' ' << e.entity << ' ' << e.partition << ' '
      << e.name << ' ' << e.commands_accepted << ' ' << e.commands_rejected << "\n";
  }
  for (std::size_t k = 0; k < out.snapshot_count; ++k) {
    const protocol::Snapshot& n = out.snapshots[k];
    s << "snap " << n.client_id << ' ' << n.tick << ' ' << n.last_applied_sequence << ' ' << n.last_applied_tick << ' '
      << n.entity << ' ' << n.entity_x << ' ' << n.entity_y << ' ' << n.entity_z << ' ' << n.entity_yaw << ' '
      << n.origin_x_mm << ' ' << n.origin_y_mm << ' ' << n.unit_mm << ' ' << n.objects_in_view << " |";
    for (auto v : n.id_codes) s << ' ' << v;
    s << " |";
    for (std::size_t i = 0; i < n.x.size(); ++i) s << ' ' << n.x[i] << ',' << n.y[i] << ',' << n.z[i] << ',' << int{n.yaw[i]};
    s << " |";
    for (auto v : n.removed) s << ' ' << v;
    s << "\n";
  }
  return s.str();
}

// The inputs of every tick: joins, commands (some rejected, some over the rate limit), operator
// parameter changes (weight, faction of a client's entity, a new policy), a leave and a client that
// goes silent (times out). Commands depend only on the tick and on what the driver has learnt from
// join replies, so a copy of the driver continues exactly like the original.
struct Driver {
  std::map<std::uint32_t, std::uint32_t> entity;  // client id -> entity
  std::map<std::uint32_t, std::uint32_t> seq;

  void push(Match& m, std::uint64_t t) {
    if (t >= 2 && t <= 7) m.inputs().push(test::join_request(1000 + t, "bot" + std::to_string(t)));
    if (t == 150) m.inputs().push(test::join_request(2000, "late"));  // after a leave: gets a fresh id
    if (t == 120) m.inputs().push(test::leave_request(1005, 4));
    std::mt19937_64 rng(t * 7919);
    std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
    for (const auto& [c, e] : entity) {
      if (c == 5 && t > 60) continue;  // goes silent: times out 150 ticks later
      if (rng() % 3 == 0) continue;
      const std::uint32_t count = 1 + static_cast<std::uint32_t>(rng() % 6);
      for (std::uint32_t k = 0; k < count; ++k) {
        protocol::Command cmd = test::command(c, e, ++seq[c], 0.7f * unit(rng), 0.7f * unit(rng));
        cmd.facing_rad = 3.0f * unit(rng);
        cmd.camera_x = 10.0f * unit(rng);
        cmd.camera_y = 10.0f * unit(rng);
        if (rng() % 7 == 0) cmd.actions = protocol::kActionSprint;
        if (rng() % 11 == 0) cmd.actions = protocol::kActionBrace;
        if (rng() % 13 == 0) cmd.move_x = 3.0f;          // rejected
        if (rng() % 17 == 0) cmd.sequence = seq[c] - 1;  // stale / duplicate
        m.inputs().push(std::move(cmd));
      }
    }
    protocol::ParamUpdate u;
    u.request_id = t;
    if (t == 30 && entity.count(1)) {
      u.entity = entity[1];
      u.param = "weight_kg";
      u.value = 300.0;
      m.inputs().push(std::move(u));
    } else if (t == 45 && entity.count(2)) {
      u.entity = entity[2];
      u.param = "faction";  // the AI regroups it
      u.value = 7.0;
      m.inputs().push(std::move(u));
    } else if (t == 70) {
      u.policy_json = R"({"mode": "ratio", "terms": [{"param": "weight", "scale": 50}, {"param": "camera_distance_m", "scale": 200}, {"param": "morale", "scale": 20}]})";
      m.inputs().push(std::move(u));
    } else if (t == 90) {
      u.entity = 999999;  // rejected
      u.param = "weight_kg";
      m.inputs().push(std::move(u));
    }
  }
  void learn(const Outbox& out) {
    for (const auto& j : out.join_replies) {
      if (j.result == protocol::JoinResult::accepted) entity[j.client_id] = j.entity;
    }
    for (const auto& e : out.client_events) {
      if (e.kind != ClientEvent::Kind::joined) entity.erase(e.client_id);
    }
  }
};

const TickReport& step(Match& m, Driver& d, Outbox& out) {
  d.push(m, m.tick_index() + 1);
  const TickReport& r = m.tick(out);
  d.learn(out);
  if (r.tick == 330) m.begin_shutdown();
  return r;
}

TEST(MatchCheckpoint, RestoredMatchContinuesBitIdentically) {
  const std::vector<std::uint64_t> ks = {0, 1, 15, 16, 17, 31, 32, 33, 61, 125, 200, 335};
  constexpr std::uint64_t kMore = 210;
  const MatchConfig config = test::small_config();
  // Reference run: its outbox every tick, and a checkpoint (with the driver) at every K.
  Match a(small_battle(), config, "a");
  Outbox out;
  Driver da;
  std::vector<std::string> expected;
  std::map<std::uint64_t, std::pair<Bytes, Driver>> saved;
  a.save_checkpoint(saved[0].first);  // before the first tick: scenery not built yet, no clients
  while (a.tick_index() < ks.back() + kMore) {
    const TickReport& r = step(a, da, out);
    expected.push_back(outbox_text(out, r));
    if (std::find(ks.begin(), ks.end(), r.tick) != ks.end()) {
      Bytes bytes;
      a.save_checkpoint(bytes);
      saved[r.tick] = {bytes, da};
    }
  }
  EXPECT_GE(a.client_count(), 3u);
  EXPECT_GT(a.commands_accepted_total(), 300u);

  for (std::uint64_t k : ks) {
    SCOPED_TRACE("checkpoint at tick " + std::to_string(k));
    Match b(small_battle(), config, "b");
    b.restore_checkpoint(saved[k].first);
    Bytes again;
    b.save_checkpoint(again);
    ASSERT_EQ(again, saved[k].first) << "round trip changed the bytes";
    ASSERT_EQ(b.tick_index(), k);
    Driver db = saved[k].second;
    Outbox ob;
    for (std::uint64_t t = k + 1; t <= k + kMore; ++t) {
      const TickReport& r = step(b, db, ob);
      ASSERT_EQ(outbox_text(ob, r), expected[t - 1]) << "tick " << t;
    }
  }
}

// A match that hosts joins and leaves for hours holds the clients it has, not every client it had:
// a departed client's record goes with it, and the checkpoint (version 5) carries the connected
// clients and the next client id, so ids are still never reused after a restore. Version 4, still
// written on request, lists every id ever given out and restores to the same match.
TEST(MatchCheckpoint, HoldsTheConnectedClientsAndTheNextIdOnly) {
  const MatchConfig config = test::small_config();
  Match a(small_battle(), config, "a");
  Outbox out;
  const protocol::JoinReply stays = test::join_one(a, out, 1, "stays");
  ASSERT_EQ(stays.result, protocol::JoinResult::accepted);
  Bytes early;
  a.save_checkpoint(early);
  constexpr std::uint32_t kSessions = 60;
  for (std::uint32_t k = 0; k < kSessions; ++k) {
    const protocol::JoinReply r = test::join_one(a, out, 100 + k, "passer-by");
    a.inputs().push(test::command(stays.client_id, stays.entity, k + 1, 0.0f, 0.0f));  // stays active: no timeout
    ASSERT_EQ(r.client_id, stays.client_id + 1 + k) << "ids are never reused";
    a.inputs().push(test::command(r.client_id, r.entity, 1, 0.5f, 0.0f));
    a.tick(out);
    a.inputs().push(test::leave_request(100 + k, r.client_id));
    a.tick(out);
    ASSERT_EQ(out.client_events.size(), 1u);
    EXPECT_EQ(out.client_events[0].kind, ClientEvent::Kind::left);
    EXPECT_EQ(out.client_events[0].commands_accepted, 1u) << "the departure carries the counts out";
  }
  ASSERT_EQ(a.client_count(), 1u);
  Bytes v5, v4;
  a.save_checkpoint(v5);
  a.save_checkpoint(v4, SaveOptions{.format_version = 4});
  EXPECT_EQ(checkpoint_sections(v5).version, 5u);
  EXPECT_EQ(checkpoint_sections(v4).version, 4u);
  // A client record with its owner is over 130 bytes: version 4 carries kSessions of them more.
  // Version 5's match section grew by the next id alone, give or take the AI's regrouped bodies.
  const auto match_bytes = [](const Bytes& b) { return checkpoint_sections(b).match_state.size(); };
  EXPECT_GT(match_bytes(v4), match_bytes(v5) + kSessions * 130);
  EXPECT_LT(match_bytes(v5), match_bytes(early) + 200) << "departed clients left something in the checkpoint";

  // Restored from either version, the match continues alike: the same next id, the same replies
  // to a command and a leave from a departed client, the same state.
  Match b(small_battle(), config, "b"), c(small_battle(), config, "c");
  b.restore_checkpoint(v5);
  c.restore_checkpoint(v4);
  Bytes b5, c5;
  b.save_checkpoint(b5);
  c.save_checkpoint(c5);
  EXPECT_EQ(b5, v5);
  EXPECT_EQ(c5, v5);
  const std::uint32_t departed = stays.client_id + 1;
  std::vector<std::string> texts;
  for (Match* m : {&a, &b, &c}) {
    Outbox o;
    m->inputs().push(test::command(departed, 0, 9, 0.5f, 0.0f));
    m->inputs().push(test::leave_request(100, departed));
    m->inputs().push(test::join_request(999, "newcomer"));
    const TickReport& r = m->tick(o);
    EXPECT_EQ(m->rejected_by_reason()[static_cast<std::size_t>(RejectReason::unknown_client)], 1u);
    ASSERT_EQ(o.join_replies.size(), 2u);
    EXPECT_EQ(o.join_replies[0].result, protocol::JoinResult::left);
    EXPECT_EQ(o.join_replies[1].client_id, stays.client_id + kSessions + 1);
    texts.push_back(outbox_text(o, r));
  }
  EXPECT_EQ(texts[1], texts[0]);
  EXPECT_EQ(texts[2], texts[0]);
}

// A version 5 checkpoint that lists a client not connected, out of order or at or above the next
// id is refused, and the match is unchanged.
TEST(MatchCheckpoint, RefusesClientListsThatVersionFiveCannotHold) {
  const MatchConfig config = test::small_config();
  Match a(small_battle(), config, "a");
  Outbox out;
  test::join_one(a, out, 1, "one");
  test::join_one(a, out, 2, "two");
  Bytes good;
  a.save_checkpoint(good);
  const auto sec = checkpoint_sections(good);
  // The next id sits right before the client count; find it from the known values (3, then 2).
  const std::size_t match_at = static_cast<std::size_t>(sec.match_state.data() - good.data());
  std::size_t at = 0;
  for (std::size_t i = match_at; i + 8 <= match_at + sec.match_state.size(); ++i) {
    std::uint32_t next = 0, count = 0;
    std::memcpy(&next, &good[i], 4);
    std::memcpy(&count, &good[i + 4], 4);
    std::uint32_t first_id = 0;
    if (i + 12 <= good.size()) std::memcpy(&first_id, &good[i + 8], 4);
    if (next == 3 && count == 2 && first_id == 1) {
      at = i;
      break;
    }
  }
  ASSERT_NE(at, 0u) << "the client list was not found";
  Match b(small_battle(), config, "b");
  Bytes before;
  b.save_checkpoint(before);
  for (std::uint32_t bad_next : {0u, 1u, 2u}) {
    Bytes bad = good;
    std::memcpy(&bad[at], &bad_next, 4);
    EXPECT_THROW(b.restore_checkpoint(bad), CheckpointError) << "next id " << bad_next;
  }
  Bytes swapped = good;  // the second client's id made equal to the first's
  const std::uint32_t one = 1;
  const std::size_t second_id_at = at + 8 + 132 + 3 + 2;  // a record: 132 bytes and its strings ("one", "c1")
  std::uint32_t was = 0;
  std::memcpy(&was, &swapped[second_id_at], 4);
  ASSERT_EQ(was, 2u) << "record layout";
  std::memcpy(&swapped[second_id_at], &one, 4);
  EXPECT_THROW(b.restore_checkpoint(swapped), CheckpointError);
  Bytes after;
  b.save_checkpoint(after);
  EXPECT_EQ(after, before);
  b.restore_checkpoint(good);
  EXPECT_EQ(b.client_count(), 2u);
}

// The replay settings of matchlog::ResimOptions (exact_interest = false).
MatchConfig fast_interest(MatchConfig c) {
  c.interest.radius_m = 0.01;
  c.interest.budget_bytes = 128;
  c.worker_threads = 1;
  return c;
}

std::string without_snapshots(const Outbox& out, const TickReport& r) {
  const std::string s = outbox_text(out, r);
  return s.substr(0, s.find("snap "));
}

bool same(std::span<const std::uint8_t> a, std::span<const std::uint8_t> b) { return std::equal(a.begin(), a.end(), b.begin(), b.end()); }

TEST(MatchCheckpoint, WithoutBaselinesRestoresIntoOtherInterestSettings) {
  // SnapshotBaselines::reset: a checkpoint restores into a match with other interest settings;
  // every later state hash, reply, client event and match-info republish is the saved match's, and
  // so is the whole checkpoint but its snapshot section. Each connected client still gets a
  // snapshot every tick, starting from an empty baseline.
  const std::vector<std::uint64_t> ks = {0, 16, 61, 125, 200, 335};
  constexpr std::uint64_t kMore = 150;
  const MatchConfig config = test::small_config();
  Match a(small_battle(), config, "a");
  Outbox out;
  Driver da;
  std::vector<std::string> expected;
  std::vector<std::vector<std::uint32_t>> snapshot_clients;
  std::map<std::uint64_t, std::pair<Bytes, Driver>> saved;
  a.save_checkpoint(saved[0].first);
  saved[0].second = da;
  while (a.tick_index() < ks.back() + kMore) {
    const TickReport& r = step(a, da, out);
    expected.push_back(without_snapshots(out, r));
    snapshot_clients.emplace_back();
    for (std::size_t k = 0; k < out.snapshot_count; ++k) snapshot_clients.back().push_back(out.snapshots[k].client_id);
    if (r.tick % 25 == 0 || std::find(ks.begin(), ks.end(), r.tick) != ks.end()) {
      Bytes bytes;
      a.save_checkpoint(bytes);
      saved[r.tick] = {bytes, da};
    }
  }
  for (const MatchConfig& cfg : {fast_interest(config), config}) {
    for (std::uint64_t k : ks) {
      SCOPED_TRACE("checkpoint at tick " + std::to_string(k) + ", interest radius " + std::to_string(cfg.interest.radius_m));
      Match b(small_battle(), cfg, "b");
      b.restore_checkpoint(saved[k].first, RestoreOptions{SnapshotBaselines::reset});
      ASSERT_EQ(b.tick_index(), k);
      Driver db = saved[k].second;
      Outbox ob;
      for (std::uint64_t t = k + 1; t <= k + kMore; ++t) {
        const TickReport& r = step(b, db, ob);
        ASSERT_EQ(without_snapshots(ob, r), expected[t - 1]) << "tick " << t;
        std::vector<std::uint32_t> ids;
        for (std::size_t i = 0; i < ob.snapshot_count; ++i) ids.push_back(ob.snapshots[i].client_id);
        ASSERT_EQ(ids, snapshot_clients[t - 1]) << "tick " << t;
        if (t == k + 1) {
          // A fresh baseline has nothing to take back, and everything in view is news.
          for (std::size_t i = 0; i < ob.snapshot_count; ++i) {
            EXPECT_TRUE(ob.snapshots[i].removed.empty());
            if (ob.snapshots[i].objects_in_view > 0) {
              EXPECT_FALSE(ob.snapshots[i].x.empty());
            }
          }
        }
        if (saved.count(t) != 0) {
          Bytes mine;
          b.save_checkpoint(mine);
          const CheckpointSections x = checkpoint_sections(mine), y = checkpoint_sections(saved[t].first);
          EXPECT_TRUE(same(x.world, y.world)) << "tick " << t;
          EXPECT_TRUE(same(x.match_state, y.match_state)) << "tick " << t;
        }
      }
    }
  }
}

TEST(MatchCheckpoint, SavedWithoutBaselinesRestoresAsResetInEitherMode) {
  // SaveOptions{.snapshot_baselines = false} (the match log's keyframes by default): the same
  // world and match sections, an empty snapshot section, and in either restore mode the match goes
  // on exactly as one restored from the full checkpoint with reset: snapshots included.
  const MatchConfig config = test::small_config();
  Match a(small_battle(), config, "a");
  Outbox out;
  Driver da;
  for (int t = 0; t < 140; ++t) step(a, da, out);
  ASSERT_GE(a.client_count(), 3u);
  Bytes full, lean;
  a.save_checkpoint(full);
  a.save_checkpoint(lean, SaveOptions{.snapshot_baselines = false});
  const CheckpointSections f = checkpoint_sections(full), l = checkpoint_sections(lean);
  EXPECT_TRUE(same(f.world, l.world));
  EXPECT_TRUE(same(f.match_state, l.match_state));
  EXPECT_FALSE(f.snapshot_baselines.empty());
  EXPECT_TRUE(l.snapshot_baselines.empty());
  EXPECT_LT(lean.size(), full.size());
  for (const MatchConfig& cfg : {config, fast_interest(config)}) {
    SCOPED_TRACE("interest radius " + std::to_string(cfg.interest.radius_m));
    Match reference(small_battle(), cfg, "ref"), by_restore(small_battle(), cfg, "r"), by_reset(small_battle(), cfg, "s");
    reference.restore_checkpoint(full, RestoreOptions{SnapshotBaselines::reset});
    by_restore.restore_checkpoint(lean);  // restore mode: nothing to restore, no interest check
    by_reset.restore_checkpoint(lean, RestoreOptions{SnapshotBaselines::reset});
    Driver d0 = da, d1 = da, d2 = da;
    Outbox o0, o1, o2;
    for (int t = 0; t < 60; ++t) {
      const std::string want = outbox_text(o0, step(reference, d0, o0));
      ASSERT_EQ(outbox_text(o1, step(by_restore, d1, o1)), want) << "tick " << reference.tick_index();
      ASSERT_EQ(outbox_text(o2, step(by_reset, d2, o2)), want) << "tick " << reference.tick_index();
    }
  }
  // A full checkpoint still refuses other interest settings in restore mode: its baselines would not fit.
  Match other(small_battle(), fast_interest(config), "o");
  EXPECT_THROW(other.restore_checkpoint(full), CheckpointError);
}

TEST(MatchCheckpoint, VersionOneStillRestoresIntoTheSameConfig) {
  // Logs of earlier builds hold version 1 keyframes.
  const MatchConfig config = test::small_config();
  Match a(small_battle(), config, "a");
  Outbox out;
  Driver d;
  for (int t = 0; t < 130; ++t) step(a, d, out);
  Bytes v2;
  a.save_checkpoint(v2, SaveOptions{.format_version = 3});
  EXPECT_EQ(checkpoint_sections(v2).version, 3u);
  const Bytes v1 = ::throng::test::as_version_1(v2, config);
  EXPECT_EQ(checkpoint_sections(v1).version, 1u);
  EXPECT_TRUE(same(checkpoint_sections(v1).world, checkpoint_sections(v2).world));
  EXPECT_TRUE(diff_checkpoints(v1, v2).empty());

  Match b(small_battle(), config, "b");
  b.restore_checkpoint(v1);
  Bytes again;
  b.save_checkpoint(again, SaveOptions{.format_version = 3});
  EXPECT_EQ(again, v2);  // everything came back, snapshot baselines included
  Driver db = d;
  Outbox ob;
  for (int t = 0; t < 40; ++t) {
    const TickReport& ra = step(a, d, out);
    const std::string want = outbox_text(out, ra);
    ASSERT_EQ(outbox_text(ob, step(b, db, ob)), want);
  }

  // Its config hash covers the interest settings: only the same ones, even without baselines.
  Match c(small_battle(), config, "c");
  EXPECT_NO_THROW(c.restore_checkpoint(v1, RestoreOptions{SnapshotBaselines::reset}));
  Match fast(small_battle(), fast_interest(config), "f");
  try {
    fast.restore_checkpoint(v1, RestoreOptions{SnapshotBaselines::reset});
    ADD_FAILURE() << "a version 1 checkpoint restored into other interest settings";
  } catch (const CheckpointError& e) {
    EXPECT_NE(std::string(e.what()).find("version 1 checkpoint includes the interest settings"), std::string::npos) << e.what();
  }
  EXPECT_EQ(fast.tick_index(), 0u);
}

TEST(MatchCheckpoint, SaveIsAllocationFreeOnAWarmBufferAndStable) {
  Match a(small_battle(), test::small_config(), "a");
  Outbox out;
  Driver d;
  for (int t = 0; t < 40; ++t) step(a, d, out);
  Bytes first, second;
  a.save_checkpoint(first);
  const std::uint8_t* data = first.data();
  a.save_checkpoint(first);
  EXPECT_EQ(first.data(), data);  // warm: the storage was reused
  a.save_checkpoint(second);
  EXPECT_EQ(first, second);       // saving changes nothing
}

class MatchCheckpointErrors : public ::testing::Test {
 protected:
  void SetUp() override {
    Driver d;
    Outbox out;
    for (int t = 0; t < 20; ++t) step(source, d, out);
    source.save_checkpoint(saved);
    for (int t = 0; t < 5; ++t) step(target, d2, out);
    target.save_checkpoint(before);
  }
  // Restoring `bytes` into target throws a CheckpointError mentioning `needle`; target unchanged.
  void expect_error(Match& m, const Bytes& bytes, const std::string& needle, RestoreOptions options = {}) {
    Bytes was;
    m.save_checkpoint(was);
    try {
      m.restore_checkpoint(bytes, options);
      ADD_FAILURE() << "no error, expected one about " << needle;
    } catch (const CheckpointError& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
    Bytes now;
    m.save_checkpoint(now);
    ASSERT_EQ(now, was) << "a failed restore changed the match";
  }
  Match source{small_battle(), test::small_config(), "s"};
  Match target{small_battle(), test::small_config(), "t"};
  Driver d2;
  Bytes saved, before;
};

TEST_F(MatchCheckpointErrors, TruncatedAtManyOffsets) {
  for (std::size_t cut = 0; cut < saved.size(); cut += cut < 300 ? 1 : 211) {
    expect_error(target, Bytes(saved.begin(), saved.begin() + static_cast<std::ptrdiff_t>(cut)), "checkpoint");
  }
  // Still usable afterwards: the real checkpoint restores.
  target.restore_checkpoint(saved);
  EXPECT_EQ(target.tick_index(), 20u);
}

TEST_F(MatchCheckpointErrors, WrongMagicVersionAndTrailingBytes) {
  Bytes bad = saved;
  bad[1] ^= 0x40;
  expect_error(target, bad, "magic");
  bad = saved;
  bad[4] = 6;
  expect_error(target, bad, "version 6, this build reads versions 1 to 5");
  bad = saved;
  bad[4] = 0;
  expect_error(target, bad, "version 0");
  bad = saved;
  bad.push_back(1);
  expect_error(target, bad, "bytes after");
  bad = saved;
  bad[48] ^= 0xFF;  // first byte of the world section's magic (after the 44-byte header and its length)
  expect_error(target, bad, "world state");
}

// Corrupted bytes anywhere (a count, an index, a flag): a CheckpointError or a successful
// restore, never another exception, a crash or a huge allocation (the ASan build runs this too).
TEST_F(MatchCheckpointErrors, CorruptedBytesFailCleanly) {
  std::mt19937_64 rng(42);
  Match m(small_battle(), test::small_config(), "fuzz");  // whatever a successful restore leaves is fine
  for (int i = 0; i < 400; ++i) {
    Bytes bad = saved;
    const std::size_t at = i < 200 ? rng() % std::min<std::size_t>(bad.size(), 4096) : rng() % bad.size();
    bad[at] = static_cast<std::uint8_t>(rng() % 2 ? bad[at] ^ (1u << (rng() % 8)) : 0xFF);
    try {
      m.restore_checkpoint(bad);
    } catch (const CheckpointError&) {
      // expected for most
    }
  }
  // Counts claiming far more entries than the bytes hold fail as truncation.
  Bytes bad = saved;
  for (std::size_t k = 0; k < 4; ++k) bad[32 + k] = 0xFF;  // body count
  expect_error(target, bad, "bodies");
}

// Version 4 writes the NPC AI compact (server/match/src/npc_ai.h): no ids, and a formation slot
// still at its spawn value as a flag. The entity that changed faction at tick 45 was regrouped and
// keeps a slot of its own. Version 3 of the same state holds the same match: restored, either saves
// the same version 4 bytes and ticks on with the same hashes.
TEST(MatchCheckpoint, CompactAiHoldsTheSameStateAsTheAiWithIds) {
  const MatchConfig config = test::small_config();
  Match a(small_battle(), config, "a");
  Outbox out;
  Driver d;
  for (int t = 0; t < 130; ++t) step(a, d, out);
  Bytes v4, v3;
  a.save_checkpoint(v4, SaveOptions{.format_version = 4});
  a.save_checkpoint(v3, SaveOptions{.format_version = 3});
  EXPECT_EQ(checkpoint_sections(v4).version, 4u);
  EXPECT_EQ(checkpoint_sections(v3).version, 3u);
  const std::size_t n = a.world().body_count();
  // v3 holds per body an id (4 bytes) and two slot doubles; v4 a flag byte per body, two counts
  // and the doubles of regrouped bodies only (at least one: the faction change at tick 45).
  const std::size_t saved_bytes = checkpoint_sections(v3).match_state.size() - checkpoint_sections(v4).match_state.size();
  EXPECT_GT(saved_bytes, (4 + 16 - 1) * n - 16 * 8);
  EXPECT_LT(saved_bytes, (4 + 16 - 1) * n);
  EXPECT_TRUE(same(checkpoint_sections(v4).world, checkpoint_sections(v3).world));
  EXPECT_THROW(a.save_checkpoint(v3, SaveOptions{.format_version = 2}), std::invalid_argument);
  a.save_checkpoint(v3, SaveOptions{.format_version = 3});

  Match b(small_battle(), config, "b"), c(small_battle(), config, "c");
  b.restore_checkpoint(v4);
  c.restore_checkpoint(v3);
  Bytes b4, c4;
  b.save_checkpoint(b4, SaveOptions{.format_version = 4});
  c.save_checkpoint(c4, SaveOptions{.format_version = 4});
  EXPECT_EQ(b4, v4);
  EXPECT_EQ(c4, v4);
  Driver db = d, dc = d;
  for (int t = 0; t < 60; ++t) {
    const std::uint64_t ha = step(a, d, out).state_hash;
    EXPECT_EQ(step(b, db, out).state_hash, ha) << t;
    EXPECT_EQ(step(c, dc, out).state_hash, ha) << t;
  }
}

// Where the compact AI's slot flags are in `bytes` (a version 4 checkpoint of a match whose n
// bodies all keep their spawn slots): the u32 n, n flags of 1, then two counts of 0.
std::size_t compact_flags_offset(const Bytes& bytes, std::size_t n) {
  std::vector<std::uint8_t> pattern(4 + n + 8, 0);
  const auto n32 = static_cast<std::uint32_t>(n);
  std::memcpy(pattern.data(), &n32, 4);
  std::fill(pattern.begin() + 4, pattern.begin() + 4 + static_cast<std::ptrdiff_t>(n), std::uint8_t{1});
  const CheckpointSections sec = checkpoint_sections(bytes);
  const auto at = std::search(sec.match_state.begin(), sec.match_state.end(), pattern.begin(), pattern.end());
  if (at == sec.match_state.end()) return 0;
  return static_cast<std::size_t>(&*at - bytes.data()) + 4;
}

TEST_F(MatchCheckpointErrors, CompactAiSlotFlagsAreChecked) {
  const std::size_t n = source.world().body_count();
  const std::size_t at = compact_flags_offset(saved, n);
  ASSERT_NE(at, 0u) << "the AI's slot flags were not found";
  Bytes bad = saved;
  bad[at + 3] = 2;
  expect_error(target, bad, "ai slot flag 2");
  bad = saved;
  bad[at + 3] = 0;  // a regrouped body, but no slot follows for it
  expect_error(target, bad, "ai slot x");
  target.restore_checkpoint(saved);
  Outbox out;
  target.tick(out);
}

// Found by fuzzing (tests/fuzz match_checkpoint): an NPC AI section naming a body the world
// section does not hold was accepted, and the next tick threw from World::set_desired_velocity.
TEST_F(MatchCheckpointErrors, AiDrivingAnotherBodyIsRefused) {
  // Version 3 (the AI with its ids): a u32 count then every body's id (here in the world's dense
  // order), in the match section (the world section holds the same list: search only there).
  source.save_checkpoint(saved, SaveOptions{.format_version = 3});
  const World& w = source.world();
  std::vector<std::uint8_t> pattern(4 + 4 * w.body_count());
  const auto n = static_cast<std::uint32_t>(w.body_count());
  std::memcpy(pattern.data(), &n, 4);
  for (std::size_t d = 0; d < w.body_count(); ++d) {
    const std::uint32_t v = w.id_at(d).value;
    std::memcpy(pattern.data() + 4 + 4 * d, &v, 4);
  }
  const CheckpointSections sec = checkpoint_sections(saved);
  const auto at = std::search(sec.match_state.begin(), sec.match_state.end(), pattern.begin(), pattern.end());
  ASSERT_NE(at, sec.match_state.end()) << "the AI's id list was not found";
  const std::size_t offset = static_cast<std::size_t>(&*at - saved.data()) + 4;  // the first id
  Bytes bad = saved;
  const std::uint32_t stranger = 0xFFFFFFF0u;
  std::memcpy(&bad[offset], &stranger, 4);
  expect_error(target, bad, "NPC AI drives other bodies than its world section holds");
  expect_error(target, bad, "NPC AI drives other bodies", RestoreOptions{SnapshotBaselines::reset});
  // Still usable afterwards, and the real checkpoint still restores and ticks.
  target.restore_checkpoint(saved);
  Outbox out;
  target.tick(out);
}

// Found by fuzzing (tests/fuzz match_checkpoint): client records that disagree with the rest of the
// checkpoint were accepted and the next tick crashed or threw. First: a kept NPC character type of
// 1.002 (the client's timeout then threw from World::set_param in release()).
TEST(MatchCheckpointClients, InconsistentClientRecordsAreRefused) {
  const scene::SceneDef def = test::two_armies(4);
  Match m(def, test::small_config(), "m");
  Outbox out;
  m.inputs().push(test::join_request(1));
  m.tick(out);
  ASSERT_EQ(out.join_replies.size(), 1u);
  const ObjectId entity{out.join_replies[0].entity};
  // The NPC's own values, which the client record keeps for release(): read from an untouched twin.
  Match twin(def, test::small_config(), "twin");
  const params::ObjectParams& p = twin.world().params(entity);
  const double kept[3] = {p.get(params::Param::character_type), p.importance, p.weight_kg};
  Bytes saved;
  m.save_checkpoint(saved);
  const CheckpointSections sec = checkpoint_sections(saved);
  const auto* k = reinterpret_cast<const std::uint8_t*>(kept);
  const auto at = std::search(sec.match_state.begin(), sec.match_state.end(), k, k + sizeof(kept));
  ASSERT_NE(at, sec.match_state.end()) << "the client's kept NPC values were not found";
  const std::size_t offset = static_cast<std::size_t>(&*at - saved.data());
  Match target(def, test::small_config(), "t");
  for (const auto& [field, value, needle] : {std::tuple{0, 1.001953125, "character_type"}, std::tuple{1, -1.0, "importance"},
                                             std::tuple{2, std::numeric_limits<double>::quiet_NaN(), "weight_kg"}}) {
    Bytes bad = saved;
    std::memcpy(&bad[offset + 8 * static_cast<std::size_t>(field)], &value, 8);
    try {
      target.restore_checkpoint(bad);
      ADD_FAILURE() << "accepted a kept " << needle << " of " << value;
    } catch (const CheckpointError& e) {
      EXPECT_NE(std::string(e.what()).find(std::string("client 1: ") + needle), std::string::npos) << e.what();
    }
    EXPECT_EQ(target.tick_index(), 0u);  // unchanged
  }
  // A camera no command could have set (found by fuzzing: at -1.5e266 m the next snapshot threw).
  // The record holds the camera's x, y, z just before the kept NPC values.
  for (const double far : {-1.5e266, 2.0e6}) {
    Bytes bad = saved;
    std::memcpy(&bad[offset - 24], &far, 8);
    try {
      target.restore_checkpoint(bad);
      ADD_FAILURE() << "accepted a camera at x = " << far;
    } catch (const CheckpointError& e) {
      EXPECT_NE(std::string(e.what()).find("client 1: camera is not a finite coordinate within 1e6 m"), std::string::npos)
          << e.what();
    }
    EXPECT_EQ(target.tick_index(), 0u);
  }
  // A connected client whose entity is another body than the one it controls (found by fuzzing:
  // with an entity the world does not hold, the next snapshot read outside the position arrays).
  // Its record: ... partition string, then the entity id.
  const std::string& partition = out.join_replies[0].snapshot_partition;
  std::vector<std::uint8_t> pattern(partition.begin(), partition.end());
  const std::uint32_t ev = entity.value;
  pattern.insert(pattern.end(), reinterpret_cast<const std::uint8_t*>(&ev), reinterpret_cast<const std::uint8_t*>(&ev) + 4);
  const auto rec = std::search(sec.match_state.begin(), sec.match_state.end(), pattern.begin(), pattern.end());
  ASSERT_NE(rec, sec.match_state.end()) << "the client's record was not found";
  for (const std::uint32_t other : {m.world().id_at(m.world().id_at(0) == entity ? 1 : 0).value, 0xFFFFFFF0u}) {
    Bytes bad = saved;
    std::memcpy(&bad[static_cast<std::size_t>(&*rec - saved.data()) + partition.size()], &other, 4);
    try {
      target.restore_checkpoint(bad);
      ADD_FAILURE() << "accepted client 1 with entity " << other;
    } catch (const CheckpointError& e) {
      EXPECT_NE(std::string(e.what()).find("controlled by client 1, which does not control it"), std::string::npos) << e.what();
    }
    EXPECT_EQ(target.tick_index(), 0u);
  }
  // The client marked not connected (its record: entity, faction, then the connected flag): its
  // snapshot baselines are then a stranger's, and without them the body it controls is (found by
  // fuzzing: the builder and the clients disagreed and the next tick threw).
  // Version 5 holds connected clients only: the record is refused as such. Versions 3 and 4 also
  // hold departed clients, so there the flag is checked against the baselines and the bodies.
  {
    Bytes bad = saved;
    bad[static_cast<std::size_t>(&*rec - saved.data()) + partition.size() + 5] = 0;
    try {
      target.restore_checkpoint(bad);
      ADD_FAILURE() << "accepted a departed client in version 5";
    } catch (const CheckpointError& e) {
      EXPECT_NE(std::string(e.what()).find("client 1 is not connected (version 5 holds connected clients only)"),
                std::string::npos)
          << e.what();
    }
  }
  Bytes v4;
  m.save_checkpoint(v4, SaveOptions{.format_version = 4});
  const CheckpointSections sec4 = checkpoint_sections(v4);
  const auto rec4 = std::search(sec4.match_state.begin(), sec4.match_state.end(), pattern.begin(), pattern.end());
  ASSERT_NE(rec4, sec4.match_state.end()) << "the client's record was not found in version 4";
  {
    Bytes bad = v4;
    bad[static_cast<std::size_t>(&*rec4 - v4.data()) + partition.size() + 5] = 0;
    try {
      target.restore_checkpoint(bad);
      ADD_FAILURE() << "accepted baselines of a client that is not connected";
    } catch (const CheckpointError& e) {
      EXPECT_NE(std::string(e.what()).find("snapshot baselines of clients that are not connected"), std::string::npos) << e.what();
    }
    try {
      target.restore_checkpoint(bad, RestoreOptions{SnapshotBaselines::reset});
      ADD_FAILURE() << "accepted a body controlled by a client that is not connected";
    } catch (const CheckpointError& e) {
      EXPECT_NE(std::string(e.what()).find("controlled by client 1, which does not control it"), std::string::npos) << e.what();
    }
    EXPECT_EQ(target.tick_index(), 0u);
  }
  target.restore_checkpoint(saved);
  EXPECT_EQ(target.state_hash(), m.state_hash());
  target.tick(out);
}

TEST_F(MatchCheckpointErrors, OtherSceneOrConfig) {
  Match fewer(scene::scale_scene(scene::builtin_scene("battle"), 200), test::small_config(), "f");
  expect_error(fewer, saved, "300 bodies, this match 200");
  Match other_scene(test::two_armies(150), test::small_config(), "o");  // also 300 bodies
  expect_error(other_scene, saved, "another scene: scene hash");
  MatchConfig cfg = test::small_config();
  cfg.interest.radius_m = 20.0;
  Match other_config(small_battle(), cfg, "c");
  expect_error(other_config, saved, "another config: interest settings hash");
  cfg = test::small_config();
  cfg.npc_speed_mps = 1.5;
  Match other_speed(small_battle(), cfg, "n");
  expect_error(other_speed, saved, "another config: config hash");
  // Without the snapshot baselines, other interest settings are fine; other results-changing
  // settings are not.
  cfg = test::small_config();
  cfg.interest.radius_m = 20.0;
  Match other_interest(small_battle(), cfg, "i");
  EXPECT_NO_THROW(other_interest.restore_checkpoint(saved, RestoreOptions{SnapshotBaselines::reset}));
  EXPECT_EQ(other_interest.state_hash(), source.state_hash());
  expect_error(other_speed, saved, "another config: config hash", RestoreOptions{SnapshotBaselines::reset});
  // A truncated snapshot section is an error even when it is not read (the sections are framed).
  expect_error(target, Bytes(saved.begin(), saved.end() - 1), "truncated", RestoreOptions{SnapshotBaselines::reset});
  // worker_threads and solver_threads do not change results: allowed.
  cfg = test::small_config();
  cfg.worker_threads = 1;
  Match one_thread(small_battle(), cfg, "w");
  EXPECT_NO_THROW(one_thread.restore_checkpoint(saved));
  cfg.solver_threads = 3;
  Match solver_threads(small_battle(), cfg, "t");
  EXPECT_NO_THROW(solver_threads.restore_checkpoint(saved));
  EXPECT_EQ(solver_threads.state_hash(), source.state_hash());
}

TEST(MatchCheckpointDiff, FindsExactlyThePerturbedObject) {
  // Armies far apart, bodies not touching: a weight change moves nobody in one tick.
  const scene::SceneDef s = test::two_armies(20, 60.0, 10.0);
  Match a(s, test::small_config(), "a");
  Match b(s, test::small_config(), "b");
  Outbox out;
  for (int t = 0; t < 3; ++t) {
    a.tick(out);
    b.tick(out);
  }
  Bytes sa, sb;
  a.save_checkpoint(sa);
  b.save_checkpoint(sb);
  EXPECT_TRUE(diff_checkpoints(sa, sb).empty());
  const std::uint32_t victim = a.world().id_at(11).value;
  protocol::ParamUpdate u;
  u.request_id = 1;
  u.entity = victim;
  u.param = "weight_kg";
  u.value = 160.0;
  b.inputs().push(std::move(u));
  a.tick(out);
  b.tick(out);
  a.save_checkpoint(sa);
  b.save_checkpoint(sb);
  const std::vector<BodyDifference> d = diff_checkpoints(sa, sb);
  ASSERT_EQ(d.size(), 1u);
  EXPECT_EQ(d[0].object_id, victim);
  EXPECT_NE(d[0].what.find("params.weight_kg 80 vs 160"), std::string::npos) << d[0].what;
  EXPECT_THROW(diff_checkpoints(sa, Bytes(sb.begin(), sb.begin() + 30)), CheckpointError);
}

}  // namespace
}  // namespace throng::match
