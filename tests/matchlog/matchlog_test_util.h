#pragma once
// Shared by the match-log tests: temporary files, random tick inputs, and a small recorded match
// (the battle scene scaled to ~300 bodies, six clients with valid and invalid commands, operator
// changes, a leave and a shutdown).
#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "throng/match/match.h"
#include "throng/matchlog/tick_record.h"
#include "throng/matchlog/writer.h"
#include "throng/scene/builtin_scenes.h"
#include "throng/scene/scale.h"

namespace throng::matchlog::test {

inline std::filesystem::path test_root() {
  return std::filesystem::temp_directory_path() / ("throng_matchlog_" + std::to_string(::getpid()));
}

// Removes test_root() after the run (THRONG_KEEP_TEST_FILES=1 keeps it for a post-mortem).
class CleanupEnvironment : public ::testing::Environment {
 public:
  void TearDown() override {
    if (std::getenv("THRONG_KEEP_TEST_FILES") == nullptr) {
      std::error_code ec;
      std::filesystem::remove_all(test_root(), ec);
    }
  }
};

// A fresh folder per test: <tmp>/throng_matchlog_<pid>/<suite>.<test>/
inline std::filesystem::path test_dir() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::filesystem::path d = test_root() / (std::string(info->test_suite_name()) + "." + info->name());
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d);
  return d;
}

inline std::vector<std::uint8_t> read_bytes(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

inline void write_bytes(const std::filesystem::path& p, const std::vector<std::uint8_t>& b, std::size_t n) {
  std::ofstream out(p, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(b.data()), static_cast<std::streamsize>(n));
}

inline scene::SceneDef small_battle(std::uint64_t bodies = 300) {
  return scene::scale_scene(scene::builtin_scene("battle"), bodies);
}

inline match::MatchConfig small_config() {
  match::MatchConfig c;
  c.tick_hz = 30;
  c.max_clients = 8;
  c.max_commands_per_tick = 4;
  return c;
}

// Random but valid-to-encode inputs: strings of any bytes, floats of any bit pattern (NaN
// payloads included), so the round trip is checked bit for bit.
inline match::TickInputs random_inputs(std::mt19937_64& rng) {
  auto any_float = [&] { return std::bit_cast<float>(static_cast<std::uint32_t>(rng())); };
  auto any_string = [&](std::size_t max) {
    std::string s(rng() % (max + 1), '\0');
    for (char& c : s) c = static_cast<char>(rng());
    return s;
  };
  match::TickInputs in;
  for (std::uint64_t n = rng() % 3; n > 0; --n) {
    protocol::JoinRequest j;
    j.client_nonce = rng();
    j.protocol_version = static_cast<std::uint32_t>(rng());
    j.name = any_string(70);
    j.leave = rng() % 2 == 0;
    j.client_id = static_cast<std::uint32_t>(rng());
    for (auto& b : j.sender.bytes) b = static_cast<std::uint8_t>(rng());
    j.identity = any_string(40);
    in.joins.push_back(j);
  }
  for (std::uint64_t n = rng() % 60; n > 0; --n) {
    protocol::Command c;
    c.client_id = static_cast<std::uint32_t>(rng());
    c.entity = static_cast<std::uint32_t>(rng());
    c.sequence = static_cast<std::uint32_t>(rng());
    c.last_seen_tick = rng();
    c.move_x = any_float();
    c.move_y = any_float();
    c.facing_rad = any_float();
    c.actions = static_cast<std::uint32_t>(rng());
    c.camera_x = any_float();
    c.camera_y = any_float();
    c.camera_z = any_float();
    for (auto& b : c.sender.bytes) b = static_cast<std::uint8_t>(rng());
    in.commands.push_back(c);
  }
  for (std::uint64_t n = rng() % 2; n > 0; --n) {
    protocol::ParamUpdate u;
    u.request_id = rng();
    u.entity = static_cast<std::uint32_t>(rng());
    u.param = any_string(20);
    u.value = std::bit_cast<double>(rng());
    u.policy_json = any_string(300);
    in.params.push_back(u);
  }
  return in;
}

inline void expect_same_inputs(const match::TickInputs& a, const match::TickInputs& b, std::uint64_t tick) {
  auto bits = [](float f) { return std::bit_cast<std::uint32_t>(f); };
  ASSERT_EQ(a.joins.size(), b.joins.size()) << "tick " << tick;
  ASSERT_EQ(a.commands.size(), b.commands.size()) << "tick " << tick;
  ASSERT_EQ(a.params.size(), b.params.size()) << "tick " << tick;
  for (std::size_t i = 0; i < a.joins.size(); ++i) {
    const auto &x = a.joins[i], &y = b.joins[i];
    ASSERT_EQ(x.client_nonce, y.client_nonce);
    ASSERT_EQ(x.protocol_version, y.protocol_version);
    ASSERT_EQ(x.name, y.name);
    ASSERT_EQ(x.leave, y.leave);
    ASSERT_EQ(x.client_id, y.client_id);
    ASSERT_EQ(x.sender, y.sender);
    ASSERT_EQ(x.identity, y.identity);
  }
  for (std::size_t i = 0; i < a.commands.size(); ++i) {
    const auto &x = a.commands[i], &y = b.commands[i];
    ASSERT_EQ(x.client_id, y.client_id);
    ASSERT_EQ(x.entity, y.entity);
    ASSERT_EQ(x.sequence, y.sequence);
    ASSERT_EQ(x.last_seen_tick, y.last_seen_tick);
    ASSERT_EQ(bits(x.move_x), bits(y.move_x));
    ASSERT_EQ(bits(x.move_y), bits(y.move_y));
    ASSERT_EQ(bits(x.facing_rad), bits(y.facing_rad));
    ASSERT_EQ(x.actions, y.actions);
    ASSERT_EQ(bits(x.camera_x), bits(y.camera_x));
    ASSERT_EQ(bits(x.camera_y), bits(y.camera_y));
    ASSERT_EQ(bits(x.camera_z), bits(y.camera_z));
    ASSERT_EQ(x.sender, y.sender);
  }
  for (std::size_t i = 0; i < a.params.size(); ++i) {
    const auto &x = a.params[i], &y = b.params[i];
    ASSERT_EQ(x.request_id, y.request_id);
    ASSERT_EQ(x.entity, y.entity);
    ASSERT_EQ(x.param, y.param);
    ASSERT_EQ(std::bit_cast<std::uint64_t>(x.value), std::bit_cast<std::uint64_t>(y.value));
    ASSERT_EQ(x.policy_json, y.policy_json);
  }
}

// Writes `ticks` ticks of random inputs (seeded) with hash = tick * constant; returns the inputs.
// params_only: the ticks keep only their parameter changes (a layout every format version shares).
inline std::vector<TickRecord> write_random_log(const std::filesystem::path& path, std::uint64_t ticks,
                                                WriterOptions options = {}, std::uint64_t seed = 1,
                                                bool params_only = false) {
  std::mt19937_64 rng(seed);
  std::vector<TickRecord> all;
  MatchLogWriter w(path.string(), options);
  LogHeader h;
  h.build_id = "test-build";
  h.match_id = "random";
  h.scene = small_battle(50);
  h.config = small_config();
  w.begin(h);
  for (std::uint64_t t = 1; t <= ticks; ++t) {
    TickRecord r;
    r.tick = t;
    r.inputs = random_inputs(rng);
    if (params_only) {
      r.inputs.joins.clear();
      r.inputs.commands.clear();
    }
    r.state_hash = t * 0x9E3779B97F4A7C15ull;
    r.flags = t == ticks ? kTickShutdownBegan : 0;
    w.append_tick(r.tick, r.inputs, r.state_hash, r.flags);
    all.push_back(std::move(r));
  }
  w.close();
  return all;
}

// Plays a small match and returns what the server would log: each tick's last_inputs(), state
// hash and flags. Clients: six join at ticks 2..7; commands from tick 8 with out-of-range moves,
// stale sequences, rate-limit floods, wrong entities, unknown clients and unknown action bits
// mixed in; an operator weight change (and a rejected one) at 40 and a policy change at 90;
// client 5 leaves at 120; begin_shutdown() before the last tick, plus a join it refuses.
struct PlayedMatch {
  std::vector<TickRecord> ticks;
  // Match::save_checkpoint() after every 15th tick (what the server hands to append_keyframe);
  // keyframes[k] is the checkpoint after tick 15 * (k + 1).
  std::vector<std::vector<std::uint8_t>> keyframes;
  // The same checkpoints without their snapshot baselines (the server's keyframes by default).
  std::vector<std::vector<std::uint8_t>> lean_keyframes;
  std::uint64_t commands_accepted = 0, commands_rejected = 0, joins_accepted = 0;
};

inline PlayedMatch play_match(std::uint64_t ticks = 200, const scene::SceneDef& scene = small_battle(),
                              const match::MatchConfig& config = small_config()) {
  PlayedMatch played;
  match::Match m(scene, config, "recorded");
  match::Outbox out;
  std::mt19937_64 rng(4242);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  std::vector<std::uint32_t> entity(7, 0), seq(7, 0);
  for (std::uint64_t t = 1; t <= ticks; ++t) {
    if (t >= 2 && t <= 7) {
      protocol::JoinRequest j;
      j.client_nonce = 1000 + t;
      j.name = "bot" + std::to_string(t);
      m.inputs().push(std::move(j));
    }
    if (t >= 8) {
      for (std::uint32_t c = 1; c <= 6; ++c) {
        if (c == 5 && t >= 120) continue;
        const std::uint32_t n = rng() % 9 == 0 ? 6 : 1;  // sometimes over the rate limit
        for (std::uint32_t k = 0; k < n; ++k) {
          protocol::Command cmd;
          cmd.client_id = c;
          cmd.entity = entity[c];
          cmd.sequence = ++seq[c];
          cmd.last_seen_tick = t - 1;
          cmd.move_x = 0.7f * unit(rng);
          cmd.move_y = 0.7f * unit(rng);
          cmd.facing_rad = 3.0f * unit(rng);
          cmd.camera_x = 20.0f * unit(rng);
          cmd.camera_y = 20.0f * unit(rng);
          cmd.camera_z = 10.0f;
          if (rng() % 5 == 0) cmd.actions = protocol::kActionSprint;
          if (rng() % 13 == 0) cmd.move_x = 3.0f;          // out of range
          if (rng() % 17 == 0) cmd.sequence = seq[c] - 2;  // stale
          if (rng() % 19 == 0) cmd.entity += 1;            // not your entity
          if (rng() % 23 == 0) cmd.client_id = 77;         // unknown client
          if (rng() % 29 == 0) cmd.actions = 0x80;         // unknown action bits
          m.inputs().push(std::move(cmd));
        }
      }
    }
    if (t == 40) {
      protocol::ParamUpdate u;
      u.request_id = 1;
      u.entity = entity[1];
      u.param = "weight_kg";
      u.value = 250.0;
      m.inputs().push(std::move(u));
      protocol::ParamUpdate bad;
      bad.request_id = 2;
      bad.entity = entity[2];
      bad.param = "no_such_param";
      bad.value = 1.0;
      m.inputs().push(std::move(bad));
    }
    if (t == 90) {
      protocol::ParamUpdate p;
      p.request_id = 3;
      p.policy_json = R"({"mode": "ratio", "terms": [{"param": "weight", "scale": 50}]})";
      m.inputs().push(std::move(p));
    }
    if (t == 120) {
      protocol::JoinRequest leave;
      leave.client_nonce = 1005;
      leave.leave = true;
      leave.client_id = 5;
      m.inputs().push(std::move(leave));
    }
    std::uint8_t flags = 0;
    if (t == ticks) {
      m.begin_shutdown();
      flags = kTickShutdownBegan;
      protocol::JoinRequest late;  // refused: shutting down
      late.client_nonce = 5555;
      late.name = "late";
      m.inputs().push(std::move(late));
    }
    const match::TickReport& r = m.tick(out);
    for (const auto& reply : out.join_replies) {
      if (reply.result == protocol::JoinResult::accepted && reply.client_id < entity.size()) entity[reply.client_id] = reply.entity;
    }
    played.commands_accepted += r.commands_accepted;
    played.commands_rejected += r.commands_rejected;
    played.joins_accepted += r.joins_accepted;
    played.ticks.push_back(TickRecord{r.tick, r.state_hash, flags, m.last_inputs()});
    if (t % 15 == 0) {
      played.keyframes.emplace_back();
      m.save_checkpoint(played.keyframes.back());
      played.lean_keyframes.emplace_back();
      m.save_checkpoint(played.lean_keyframes.back(), match::SaveOptions{.snapshot_baselines = false});
    }
  }
  return played;
}

inline LogHeader match_header(const scene::SceneDef& scene = small_battle(), const match::MatchConfig& config = small_config()) {
  LogHeader h;
  h.build_id = "test-build";
  h.match_id = "recorded";
  h.scene = scene;
  h.config = config;
  return h;
}

// Writes played ticks through a writer. tamper_tick > 0: that tick's hash is written wrong (a log
// whose hashes were tampered with). keyframes (PlayedMatch::keyframes): appended as the server does,
// after every tick that is a multiple of the writer's keyframe interval.
inline void write_played(const std::filesystem::path& path, const std::vector<TickRecord>& ticks, const LogHeader& header,
                         WriterOptions options = {}, std::uint64_t tamper_tick = 0,
                         const std::vector<std::vector<std::uint8_t>>* keyframes = nullptr) {
  // A test appends a whole match within a millisecond, the server one keyframe per ~2 s: room for
  // all of them (Keyframes.WriterBehindDropsKeyframesLoudlyNotTicks tests the full case itself).
  if (keyframes != nullptr) options.keyframe_slots = std::max<std::uint32_t>(options.keyframe_slots, 64);
  // The header says what the keyframes hold, as the server's does.
  if (keyframes != nullptr && !keyframes->empty())
    options.keyframe_snapshot_baselines = !match::checkpoint_sections(keyframes->front()).snapshot_baselines.empty();
  MatchLogWriter w(path.string(), options);
  w.begin(header);
  const std::uint64_t every = w.keyframe_interval_ticks();
  for (const TickRecord& t : ticks) {
    w.append_tick(t.tick, t.inputs, t.tick == tamper_tick ? t.state_hash ^ 1ull : t.state_hash, t.flags);
    if (keyframes != nullptr && every > 0 && t.tick % every == 0 && every % 15 == 0 && t.tick / 15 <= keyframes->size())
      w.append_keyframe(t.tick, (*keyframes)[t.tick / 15 - 1]);
  }
  w.close();
}

// Everything a snapshot carries, to compare two players' outboxes.
inline void expect_same_snapshots(const match::Outbox& a, const match::Outbox& b) {
  ASSERT_EQ(a.snapshot_count, b.snapshot_count);
  for (std::size_t i = 0; i < a.snapshot_count; ++i) {
    const auto &x = a.snapshots[i], &y = b.snapshots[i];
    EXPECT_EQ(x.client_id, y.client_id);
    EXPECT_EQ(x.tick, y.tick);
    EXPECT_EQ(x.entity, y.entity);
    EXPECT_EQ(x.id_codes, y.id_codes);
    EXPECT_EQ(x.x, y.x);
    EXPECT_EQ(x.y, y.y);
    EXPECT_EQ(x.z, y.z);
    EXPECT_EQ(x.yaw, y.yaw);
    EXPECT_EQ(x.removed, y.removed);
  }
}

}  // namespace throng::matchlog::test
