#pragma once
// MatchFollower: a match kept tick for tick in step with a primary server, the core of a hot
// standby. It is fed the primary's tick entries (encode_tick's bytes: the inputs the primary's tick
// applied, in order, and its state hash, exactly what the match log records for the tick) and, to
// start and after anything that breaks the chain, a checkpoint the primary saved
// (Match::save_checkpoint). Each applied tick's recomputed state hash is compared with the
// primary's; the first tick that differs stops the following until a fresh checkpoint arrives.
// A new follower is the primary's match before its first tick (the same header builds the same
// match), so one started with the primary needs no checkpoint; one started later does.
//
// Why a stream of entries and checkpoints rather than a log file: a standby must keep up with a
// live match and resynchronise without stopping it. The transport is the caller's (a DDS topic in
// the server, plain calls in tests); this class decides nothing about time.
//
// Not thread-safe: one thread feeds it.
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "throng/match/checkpoint_diff.h"
#include "throng/match/match.h"
#include "throng/matchlog/log_header.h"
#include "throng/matchlog/replay.h"
#include "throng/matchlog/tick_record.h"

namespace throng::matchlog {

struct FollowerOptions {
  // exact_interest: the primary's interest settings and snapshot baselines, so that the follower's
  // snapshots are the primary's byte for byte from a checkpoint saved with baselines on (what a
  // standby that takes over must publish). No push events: nothing reads a follower's, and
  // recording them costs a square root and the start depths per pushing pair every tick.
  ResimOptions resim{.record_push_events = false, .exact_interest = true, .logged_push_events = false};
  // Entries held while they cannot be applied yet (no checkpoint covers them, or a tick before them
  // is missing): the newest are kept. 900 is 30 s at 30 Hz, time for a checkpoint to arrive.
  std::size_t max_held_ticks = 900;
  // Called after each applied tick whose hash matched the primary's, with the tick, its hash and
  // flags and the inputs it applied (Match::last_inputs(), as the primary logged them): a standby
  // records it in its own match log.
  std::function<void(std::uint64_t tick, std::uint64_t state_hash, std::uint8_t flags, const match::TickInputs& inputs)>
      on_applied;
};

enum class FollowState : std::uint8_t {
  following,         // every tick up to tick() applied with the primary's hash
  // The last applied tick diverged, or an entry arrived past a missing tick (a follower started
  // after the primary, or entries lost): ask the primary for a checkpoint. Entries are still held,
  // and a missing tick that does arrive is still applied.
  needs_checkpoint,
};

// What a divergence looked like: the objects whose state differed from the primary's at the tick of
// the checkpoint that ended it (the diverged match stepped on with the primary's entries to that
// tick), as `throng-replay verify` names them.
struct Divergence {
  std::uint64_t first_tick = 0;   // the first tick whose hash differed
  std::uint64_t compared_at = 0;  // the checkpoint's tick (0: could not be compared, see note)
  std::vector<match::BodyDifference> differences;  // at most 20, ascending object id
  std::string note;               // why nothing was compared, or that the worlds were equal
};

struct FollowerStats {
  std::uint64_t applied = 0;              // ticks applied whose hash matched the primary's
  std::uint64_t mismatches = 0;           // ticks whose recomputed hash differed
  std::uint64_t first_mismatch_tick = 0;  // the latest divergence's first tick (0: none yet)
  std::uint64_t checkpoints = 0;          // checkpoints restored
  std::uint64_t stale_checkpoints = 0;    // checkpoints older than a match that still followed (ignored)
  std::uint64_t stale_entries = 0;        // entries for ticks already applied or covered by a checkpoint
  std::uint64_t gaps = 0;                 // entries whose previous tick was neither applied nor held
  std::uint64_t held_dropped = 0;         // held entries dropped for room (the oldest)
};

class MatchFollower {
 public:
  // The match the primary runs: its log header's scene, config and match id.
  explicit MatchFollower(const LogHeader& header, FollowerOptions options = {});
  ~MatchFollower();
  MatchFollower(const MatchFollower&) = delete;
  MatchFollower& operator=(const MatchFollower&) = delete;

  // One tick entry as the primary encoded it. Applied at once when it is the next tick, then any
  // held entries that follow it; held when it cannot be applied yet; counted and dropped when its
  // tick is already behind. Throws LogError, with nothing changed, on bytes that are not exactly
  // one well-formed entry.
  void on_tick_entry(std::span<const std::uint8_t> entry);
  // A checkpoint the primary saved after its tick T. Replaces the follower's match, drops held
  // entries up to T and applies those after it; ignored (counted) when T is behind a match that
  // still follows. A diverged match is first stepped on with the held entries up to T and compared
  // with the checkpoint (last_divergence() names the objects that differ). Throws match::CheckpointError when the bytes do not restore (another scene,
  // config or build; damaged): a match that was following is unchanged and still follows (a
  // diverged one may have been stepped on to compare it).
  void on_checkpoint(std::span<const std::uint8_t> checkpoint);

  FollowState state() const;
  std::uint64_t tick() const;  // ticks applied: the follower's match is the primary's after this tick
  std::size_t held() const { return held_.size(); }
  // The flags (kTick*, format.h) of the last applied tick: kTickShutdownBegan says the primary
  // ended the match.
  std::uint8_t last_applied_flags() const { return last_flags_; }
  const FollowerStats& stats() const { return stats_; }
  // The last divergence that a checkpoint ended (first_tick 0: none yet).
  const Divergence& last_divergence() const { return divergence_; }
  const match::Match& match() const { return resim_.match(); }
  const match::Outbox& outbox() const { return resim_.outbox(); }  // of the last applied tick

 private:
  void apply_held();
  void hold(TickRecord&& t);
  void explain_divergence(std::span<const std::uint8_t> checkpoint);

  FollowerOptions options_;
  Resimulator resim_;
  std::map<std::uint64_t, TickRecord> held_;  // by tick
  bool diverged_ = false;  // the last applied tick's hash differed
  std::uint8_t last_flags_ = 0;
  Divergence divergence_;
  std::vector<std::uint8_t> mine_;  // the diverged match's checkpoint, compared with the primary's
  FollowerStats stats_;
};

}  // namespace throng::matchlog
