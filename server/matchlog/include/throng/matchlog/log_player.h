#pragma once
// LogPlayer: a re-simulated match positioned at any tick of a log, for everything that watches a
// log rather than checks it: `throng-replay play` (re-publishes over DDS), `throng-replay seek`,
// and `throng-view --log` (the browser timeline). One Match, advanced tick by tick from the
// logged inputs; seek() jumps through the nearest world keyframe at or before the target (or
// re-simulates from the start when the log has none) and then steps forward.
//
// Not thread-safe: one thread drives it. The Match it exposes is only valid until the next
// seek() (a seek may rebuild it).
#include <cstdint>
#include <memory>
#include <string>

#include "throng/match/match.h"
#include "throng/matchlog/log_header.h"
#include "throng/matchlog/reader.h"
#include "throng/matchlog/replay.h"

namespace throng::matchlog {

struct PlayerOptions {
  // exact_interest = true (default): snapshots are what play publishes, so the logged interest
  // settings are used, keyframes are restored whole (snapshot baselines included) and every tick
  // on the way to a seek's target builds its snapshots: from any seek on, the outbox holds byte for
  // byte the snapshots the server built, when the keyframes hold the baselines (the server's
  // --log-baselines; header().writer.keyframe_snapshot_baselines); without them every client's
  // snapshots start from an empty baseline at the keyframe. A seek costs the keyframe restore plus
  // up to a keyframe interval of full ticks.
  // false: for everything that reads the world, the match state and the hashes, not the logged
  // snapshot stream (throng-view --log, throng-replay seek): cheap interest settings, keyframes
  // restored without their snapshot baselines (match::SnapshotBaselines::reset). World, match
  // state (clients, NPC AI, facing, match info) and state hashes at any tick are exactly those of
  // stepping from the start; the outbox's snapshots are this player's own (tiny, from empty
  // baselines after each keyframe restore). A log whose keyframes are checkpoint version 1 switches
  // to the logged settings at its first keyframe restore (they restore only into them).
  ResimOptions resim{.record_push_events = false, .exact_interest = true};
};

struct SeekResult {
  std::uint64_t tick = 0;           // where the player now is
  std::uint64_t keyframe_tick = 0;  // the keyframe it started from (0: from the match start or the current tick)
  std::uint64_t ticks_simulated = 0;
  double ms = 0.0;                  // wall time of the seek
  std::uint64_t hash_mismatches = 0;     // ticks simulated by this seek whose hash differed from the log
  std::uint64_t first_mismatch_tick = 0; // the first of them (0: none)
  std::uint64_t logged_hash = 0;         // the log's state hash of `tick` (0 at tick 0)
};

class LogPlayer {
 public:
  // Opens and scans the log (throws LogError with the reader's message on a bad file).
  explicit LogPlayer(const std::string& path, PlayerOptions options = {});
  ~LogPlayer();
  LogPlayer(const LogPlayer&) = delete;
  LogPlayer& operator=(const LogPlayer&) = delete;

  const LogHeader& header() const;
  const LogScan& scan() const;
  std::uint32_t tick_hz() const;
  std::uint64_t first_tick() const;  // 1 when the log has ticks (T + 1 for one that starts after tick T), else 0
  std::uint64_t last_tick() const;   // last tick that can be re-simulated (stops before a gap)
  std::uint64_t tick() const;        // ticks applied so far: 0 = the match before its first tick

  // Moves to `tick` (clamped to 0..last_tick()). Restores the nearest logged keyframe at or before
  // `tick` when that is ahead of the current position or the seek goes backwards, then steps; a
  // forward seek with no keyframe in between steps on from the current position; backwards without
  // a keyframe re-simulates from the match start.
  SeekResult seek(std::uint64_t tick);
  // Applies the next logged tick; false (and nothing changes) at last_tick().
  bool step();
  // The last step's recomputed hash equalled the logged one (true before any step).
  bool last_hash_matched() const;
  // "" unless a keyframe failed to restore (another build's checkpoint format, say): then seeks
  // re-simulate from tick 1 and this says why.
  const std::string& keyframe_problem() const;

  const match::Match& match() const;
  const match::Outbox& outbox() const;            // of the last step(): replies, events, snapshots
  const match::TickReport& last_report() const;   // of the last step()

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace throng::matchlog
