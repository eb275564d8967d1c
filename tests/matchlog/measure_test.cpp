// Measurements for the log issue's report (disabled: run on a Release build with
//   throng_matchlog_tests --gtest_also_run_disabled_tests --gtest_filter='Measure*'
// and THRONG_MEASURE_BODIES / THRONG_MEASURE_TICKS to change the size (defaults 6000 / 900)).
// The battle scene with 50 clients joined at tick 1, each sending one command per tick with its
// camera over its entity, logged live by the default writer with a world keyframe every 60 ticks
// (as the server does): bytes per tick for several writer settings, append time per tick inside a
// real match, keyframe save/append cost and size, seek time, and verify speed with 1 and 2 jobs.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <ctime>

#include "matchlog_test_util.h"
#include "throng/matchlog/log_player.h"
#include "throng/matchlog/reader.h"
#include "throng/matchlog/replay.h"
#include "throng/world/world.h"

namespace throng::matchlog {
namespace {

// CPU seconds of the whole process (every thread): on this shared machine wall times are inflated
// by the other engineers' builds, CPU time is what a quiet machine would need.
double process_cpu_s() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

std::uint64_t env_or(const char* name, std::uint64_t fallback) {
  const char* v = std::getenv(name);
  return v != nullptr ? std::strtoull(v, nullptr, 10) : fallback;
}

TEST(Measure, DISABLED_BattleLogSizeAppendTimeAndVerifySpeed) {
  using Clock = std::chrono::steady_clock;
  const std::uint64_t bodies = env_or("THRONG_MEASURE_BODIES", 6000);
  const std::uint64_t ticks = env_or("THRONG_MEASURE_TICKS", 900);
  const auto dir = test::test_dir();
  const scene::SceneDef scene = test::small_battle(bodies);
  match::MatchConfig config;  // the server's defaults: 30 Hz, 256 clients
  match::Match m(scene, config, "measure");
  match::Outbox out;
  LogHeader h = test::match_header(scene, config);
  MatchLogWriter w((dir / "live.tlog").string());
  w.begin(h);

  std::vector<TickRecord> recorded;
  std::vector<double> append_us, tick_ms, save_ms, kf_append_us;
  std::vector<std::uint8_t> checkpoint;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> clients;  // id, entity
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> unit(-0.7f, 0.7f);
  for (std::uint64_t t = 1; t <= ticks; ++t) {
    if (t == 1) {
      for (std::uint64_t n = 1; n <= 50; ++n) {
        protocol::JoinRequest j;
        j.client_nonce = n;
        j.name = "bot" + std::to_string(n);
        m.inputs().push(std::move(j));
      }
    }
    for (auto [id, entity] : clients) {
      const Vec3 p = m.world().position(ObjectId{entity});
      protocol::Command c;
      c.client_id = id;
      c.entity = entity;
      c.sequence = static_cast<std::uint32_t>(t);
      c.last_seen_tick = t - 1;
      c.move_x = unit(rng);
      c.move_y = unit(rng);
      c.facing_rad = unit(rng);
      c.camera_x = static_cast<float>(p.x);
      c.camera_y = static_cast<float>(p.y - 8.0);
      c.camera_z = 12.0f;
      m.inputs().push(std::move(c));
    }
    const auto t0 = Clock::now();
    const match::TickReport& r = m.tick(out);
    const auto t1 = Clock::now();
    w.append_tick(r.tick, m.last_inputs(), r.state_hash, 0);
    const auto t2 = Clock::now();
    tick_ms.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
    append_us.push_back(std::chrono::duration<double, std::micro>(t2 - t1).count());
    if (r.tick % w.keyframe_interval_ticks() == 0) {  // what the server does after the tick
      const auto k0 = Clock::now();
      m.save_checkpoint(checkpoint, match::SaveOptions{.snapshot_baselines = w.options().keyframe_snapshot_baselines});
      const auto k1 = Clock::now();
      w.append_keyframe_swap(r.tick, checkpoint);  // as the server does
      const auto k2 = Clock::now();
      save_ms.push_back(std::chrono::duration<double, std::milli>(k1 - k0).count());
      kf_append_us.push_back(std::chrono::duration<double, std::micro>(k2 - k1).count());
    }
    for (const auto& reply : out.join_replies) clients.emplace_back(reply.client_id, reply.entity);
    recorded.push_back(TickRecord{r.tick, r.state_hash, 0, m.last_inputs()});
  }
  w.close();
  const WriterStats ws = w.stats();
  ASSERT_EQ(clients.size(), 50u);
  std::sort(append_us.begin(), append_us.end());
  std::sort(tick_ms.begin(), tick_ms.end());
  const auto q = [](const std::vector<double>& v, double f) { return v[static_cast<std::size_t>(f * static_cast<double>(v.size() - 1))]; };
  std::printf("\nbattle scaled to %llu bodies, 50 clients x 1 command/tick, %llu ticks at %u Hz\n",
              static_cast<unsigned long long>(bodies), static_cast<unsigned long long>(ticks), config.tick_hz);
  std::printf("live Match::tick: median %.2f ms, p99 %.2f ms\n", q(tick_ms, 0.5), q(tick_ms, 0.99));
  std::printf("append_tick inside the match: median %.2f us, p99 %.2f us, max %.1f us (writer stats: p99 %.1f us, max %.1f us, "
              "backlog high-water %llu ticks, fsyncs %llu, max fsync %.2f ms)\n",
              q(append_us, 0.5), q(append_us, 0.99), append_us.back(), ws.p99_append_us, ws.max_append_us,
              static_cast<unsigned long long>(ws.backlog_high_water), static_cast<unsigned long long>(ws.fsyncs), ws.max_fsync_ms);

  std::sort(save_ms.begin(), save_ms.end());
  std::sort(kf_append_us.begin(), kf_append_us.end());
  if (!save_ms.empty())
    std::printf("keyframes (every %u ticks, %zu of them, checkpoint %zu bytes, the caller's buffer after the swap): save_checkpoint median %.2f ms, max %.2f ms; "
                "append_keyframe median %.1f us, max %.1f us; written %llu, dropped %llu, %.0f bytes each in the file "
                "(%.0f raw), %.1f bytes/tick of keyframes\n",
                w.keyframe_interval_ticks(), save_ms.size(), checkpoint.size(), q(save_ms, 0.5), save_ms.back(),
                q(kf_append_us, 0.5), kf_append_us.back(), static_cast<unsigned long long>(ws.keyframes_written),
                static_cast<unsigned long long>(ws.keyframes_dropped),
                ws.keyframes_written ? static_cast<double>(ws.keyframe_bytes) / static_cast<double>(ws.keyframes_written) : 0.0,
                ws.keyframes_written ? static_cast<double>(ws.keyframe_raw_bytes) / static_cast<double>(ws.keyframes_written) : 0.0,
                static_cast<double>(ws.keyframe_bytes) / static_cast<double>(ticks));
  {
    // What a keyframe is made of (the server leaves the baselines out unless --log-baselines).
    std::vector<std::uint8_t> full;
    m.save_checkpoint(full);
    const match::CheckpointSections sec = match::checkpoint_sections(full);
    std::printf("checkpoint sections at the last tick: world %zu, match %zu, snapshot baselines %zu bytes "
                "(keyframes %s the baselines)\n",
                sec.world.size(), sec.match_state.size(), sec.snapshot_baselines.size(),
                w.options().keyframe_snapshot_baselines ? "keep" : "leave out");
  }
  std::printf("bytes per tick (tick-block records incl. framing; whole file / ticks in brackets):\n");
  std::printf("  block_ticks  zstd_level  bytes/tick\n");
  for (std::uint32_t block : {1u, 5u, 15u, 30u}) {
    for (int level : {0, 1, 3, 9}) {
      WriterOptions o;
      o.block_ticks = block;
      o.zstd_level = level;
      const auto path = dir / ("b" + std::to_string(block) + "z" + std::to_string(level) + ".tlog");
      test::write_played(path, recorded, h, o);
      MatchLogReader r(path.string());
      std::printf("  %11u  %10d  %10.1f  [%.1f]%s\n", block, level,
                  static_cast<double>(r.scan().tick_block_bytes) / static_cast<double>(ticks),
                  static_cast<double>(r.scan().file_bytes) / static_cast<double>(ticks),
                  block == 15 && level == 1 ? "   <- default" : "");
    }
  }
  MatchLogReader live((dir / "live.tlog").string());
  std::printf("  uncompressed tick entries: %.1f bytes/tick; header %llu bytes\n",
              static_cast<double>(live.scan().raw_tick_bytes) / static_cast<double>(ticks),
              static_cast<unsigned long long>(live.scan().header_bytes));

  std::printf("  live log with keyframes: %.1f bytes/tick whole file (%llu bytes, %zu keyframes = %llu bytes)\n",
              static_cast<double>(live.scan().file_bytes) / static_cast<double>(ticks),
              static_cast<unsigned long long>(live.scan().file_bytes), live.scan().keyframes.size(),
              static_cast<unsigned long long>(live.scan().keyframe_bytes));

  // Seeks: to random ticks (forward and backward), each through the nearest keyframe; then the
  // tick with the most ticks after a keyframe. World settings (throng-replay seek, throng-view --log:
  // keyframes restored without snapshot baselines, cheap interest settings) and play's exact ones.
  for (const bool exact : {false, true}) {
    PlayerOptions po;
    po.resim.exact_interest = exact;
    LogPlayer player((dir / "live.tlog").string(), po);
    std::vector<double> seek_ms, seek_cpu_ms;
    std::mt19937_64 pick(7);
    for (int i = 0; i <= 20; ++i) {
      // 20 random ticks, then the one with the most ticks after a keyframe.
      const std::uint64_t target = i < 20 ? 1 + pick() % ticks : ticks - (ticks % 60 == 0 ? 1 : 0);
      const double c0 = process_cpu_s();
      const SeekResult s = player.seek(target);
      seek_cpu_ms.push_back(1e3 * (process_cpu_s() - c0));
      ASSERT_EQ(s.tick, target);
      ASSERT_EQ(s.hash_mismatches, 0u);
      seek_ms.push_back(s.ms);
    }
    std::sort(seek_ms.begin(), seek_ms.end());
    std::sort(seek_cpu_ms.begin(), seek_cpu_ms.end());
    std::printf("seek (LogPlayer, %s, keyframe restore + up to %u ticks): median %.1f ms, max %.1f ms over %zu seeks "
                "(CPU: median %.1f ms, max %.1f ms)\n",
                exact ? "exact: play's settings, snapshot baselines restored and built on the way"
                      : "world: seek/throng-view's settings, keyframes restored without snapshot baselines",
                w.keyframe_interval_ticks() - 1, q(seek_ms, 0.5), seek_ms.back(), seek_ms.size(), q(seek_cpu_ms, 0.5),
                seek_cpu_ms.back());
  }

  for (unsigned jobs : {1u, 2u}) {
    const double c0 = process_cpu_s();
    const VerifyResult v = verify_log(live, {}, 30, {}, jobs);
    const double cpu_s = process_cpu_s() - c0;
    ASSERT_TRUE(v.all_match()) << "jobs " << jobs << ": mismatch " << v.mismatch << " at " << v.mismatch_tick
                               << ", keyframe mismatch " << v.keyframe_mismatch << " at " << v.keyframe_mismatch_tick
                               << ", verified " << v.ticks_verified << "/" << v.ticks_total << ", from keyframe "
                               << v.diff_from_tick << " objects " << v.differences.size() << " "
                               << (v.differences.empty() ? v.diff_note : v.differences.front().what);
    const double n = static_cast<double>(v.ticks_verified);
    if (!v.keyframe_note.empty()) std::printf("  note: %s\n", v.keyframe_note.c_str());
    std::printf("verify --jobs %u CPU: %.2f s for %llu ticks = %.2f ms a tick; with a free core per job %.1fx real time\n", jobs,
                cpu_s, static_cast<unsigned long long>(v.ticks_verified), 1e3 * cpu_s / n,
                n / (cpu_s / jobs) / static_cast<double>(config.tick_hz));
    std::printf("verify --jobs %u (%llu keyframes compared, %llu segments; segments after the first restore a keyframe "
                "without its snapshot baselines): %llu ticks in "
                "%.2f s = %.0f ticks/s = %.1fx real time at %u Hz; per tick: step %.2f ms, ai %.2f ms, snapshots %.2f ms, "
                "inputs %.3f ms\n",
                jobs, static_cast<unsigned long long>(v.keyframes_checked), static_cast<unsigned long long>(v.segments),
                static_cast<unsigned long long>(v.ticks_verified), v.seconds, v.ticks_per_second, v.realtime_factor,
                config.tick_hz, v.step_ms / n, v.ai_ms / n, v.snapshots_ms / n, v.apply_ms / n);
  }
  // The same ticks without keyframes (v1-style): the fast interest settings are allowed.
  {
    const auto nokf = dir / "nokf.tlog";
    test::write_played(nokf, recorded, h);
    MatchLogReader r(nokf.string());
    const VerifyResult v = verify_log(r, {}, 30, {}, 1);
    ASSERT_TRUE(v.all_match());
    std::printf("verify of the same ticks without keyframes (1 cm interest radius): %.2f s = %.1fx real time\n", v.seconds,
                v.realtime_factor);
  }
}

}  // namespace
}  // namespace throng::matchlog
