#pragma once
// Re-simulation from a log: a fresh Match built from the header's scene and config, fed each
// logged tick's inputs exactly as the server's tick drained them. verify_log compares every
// tick's state hash with the logged one.
//
// What a mismatch can say: the first divergent tick and both hashes; with world keyframes in the
// log (format version 2) also the objects whose state differs, found by re-simulating from the
// keyframe before the divergent tick to the keyframe after it and diffing the two checkpoints.
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "throng/match/checkpoint_diff.h"
#include "throng/match/match.h"
#include "throng/matchlog/log_header.h"
#include "throng/matchlog/reader.h"
#include "throng/matchlog/tick_record.h"

namespace throng::matchlog {

struct ResimOptions {
  // Force WorldSettings::record_push_events on (export, the viewer's contacts overlay). The state
  // hash does not depend on it (push events steer nothing), and every step's hash is checked
  // anyway. Left false, the events are recorded as the log's settings say with exact_interest
  // (unless logged_push_events is false), and not at all without it: nothing of such a replay
  // reads them (MatchConfig::push_events).
  bool record_push_events = false;
  // false (default): replay with a 1 cm interest radius, the smallest snapshot budget and one
  // snapshot thread. The interest settings only shape snapshot content, which is not part of the
  // state hash (server/match: match_snapshots.cpp is their only reader), and building every
  // client's full snapshots is a large part of a re-simulated tick (docs/design/match-log.md; the
  // worker pool's hand-offs cost more than the 1 cm builds they would share). Keyframes are
  // restored without their snapshot
  // baselines (match::SnapshotBaselines::reset: every state hash continues exactly; the snapshots
  // in the outbox are this replay's own, not the server's). Should the snapshots ever feed back
  // into the simulation, verify reports a mismatch (it can never pass falsely: the hash covers the
  // world). Keyframes of checkpoint version 1 (logs of earlier builds) restore only into the logged
  // interest settings: callers check restores_with_fast_interest() and turn exact_interest on.
  // true: the logged settings and worker threads; keyframes restored whole, so the outbox holds
  // byte for byte the snapshots the server built (throng-replay play).
  bool exact_interest = false;
  // With exact_interest: true (default), push events as the logged config says; false, none unless
  // record_push_events (a standby's follower, which reads none: a standby that takes over builds
  // a new Match from a checkpoint, and push events are no part of one). Without exact_interest
  // there are none unless record_push_events anyway.
  bool logged_push_events = true;
};

class Resimulator {
 public:
  explicit Resimulator(const LogHeader& header, ResimOptions options = {});
  ~Resimulator();
  // Replaces the match's state with a logged keyframe's checkpoint (Match::restore_checkpoint, with
  // SnapshotBaselines::reset unless exact_interest; throws match::CheckpointError, e.g. for a
  // version 1 checkpoint without exact_interest). The next step() must then be the keyframe's tick + 1.
  void restore(std::span<const std::uint8_t> checkpoint);
  // Whether a checkpoint can be restored without exact_interest (checkpoint version 2 or later).
  // Throws match::CheckpointError on bytes that are not a checkpoint.
  static bool restores_with_fast_interest(std::span<const std::uint8_t> checkpoint);
  const ResimOptions& options() const { return options_; }
  // Applies one logged tick (its inputs are moved out): begin_shutdown() if the tick is flagged,
  // push the inputs, tick(). Returns the recomputed state hash. Throws LogError if t.tick is not
  // the next tick (a gap in the log cannot be re-simulated across).
  std::uint64_t step(TickRecord& t);
  const match::Match& match() const { return *match_; }
  const match::TickReport& last_report() const { return *report_; }  // of the last step(); step() first
  bool stepped() const { return report_ != nullptr; }
  const match::Outbox& outbox() const { return out_; }  // of the last step(): replies, events, snapshots
  std::uint64_t tick() const;

 private:
  ResimOptions options_;
  std::unique_ptr<match::Match> match_;
  match::Outbox out_;
  const match::TickReport* report_ = nullptr;
  bool shutdown_ = false;
};

struct VerifyResult {
  unsigned jobs = 1;                 // threads used
  std::uint64_t segments = 1;        // keyframe-aligned pieces verified independently (each but the first from its keyframe)
  std::uint64_t keyframes_checked = 0;  // logged keyframes the re-simulated checkpoint was compared with
  // The state hashes matched up to a keyframe tick but the re-simulated world differs from the
  // logged keyframe's world there (differences names the objects).
  bool keyframe_mismatch = false;
  std::uint64_t keyframe_mismatch_tick = 0;
  // On a mismatch in a log with keyframes: the objects whose state differs at diff_tick (the first
  // logged keyframe at or after the divergent tick), re-simulated from the keyframe at diff_from_tick.
  std::vector<match::BodyDifference> differences;
  std::uint64_t diff_from_tick = 0, diff_tick = 0;
  std::string diff_note;             // why no objects could be named ("" when differences says it)
  // Not a failure: the rest of the checkpoint is compared too (the match section: clients, NPC AI,
  // counters; with exact_interest also the snapshot baselines); the first keyframe whose world
  // matched but whose other match state did not is described here.
  std::string keyframe_note;
  std::uint64_t ticks_total = 0;     // readable ticks in the log
  std::uint64_t ticks_verified = 0;  // ticks whose hash matched, from the log's first tick on
  // The log starts after this tick, from its keyframe (a hot standby's log); 0: from tick 1.
  std::uint64_t start_tick = 0;
  bool mismatch = false;
  std::uint64_t mismatch_tick = 0, expected_hash = 0, actual_hash = 0;
  bool stopped_at_gap = false;       // the writer dropped ticks: nothing after can be re-simulated
  std::uint64_t gap_first_tick = 0;
  double seconds = 0.0;              // re-simulation wall time (log decoding included)
  double ticks_per_second = 0.0;
  double realtime_factor = 0.0;      // ticks_per_second / tick_hz
  // Where the re-simulation time went, summed over the verified ticks (Match::tick phases; the
  // rest is log decoding and pushing inputs).
  double apply_ms = 0.0, ai_ms = 0.0, step_ms = 0.0, snapshots_ms = 0.0;
  bool all_match() const { return !mismatch && !keyframe_mismatch && !stopped_at_gap && ticks_verified == ticks_total; }
};

// progress(done, total) is called every progress_every ticks (jobs > 1: about every 0.2 s) and
// once at the end, always from the calling thread.
//
// A log with keyframes (format version 2): at every logged keyframe the re-simulated world must
// equal the keyframe's world (byte for byte, else diff_checkpoints: a difference is
// keyframe_mismatch with the objects named); the rest of the checkpoint is compared as well (see
// keyframe_note). jobs > 1 splits the log into keyframe-aligned segments verified in parallel, each
// but the first starting from its logged keyframe, restored as ResimOptions says (without its
// snapshot baselines unless exact_interest; version 1 keyframes with the logged interest settings);
// the restore is proven by the segment's every hash check and its next keyframe comparison; the
// result is the same as with jobs = 1. Without keyframes jobs is ignored (one segment).
using VerifyProgress = std::function<void(std::uint64_t done, std::uint64_t total)>;
VerifyResult verify_log(MatchLogReader& reader, const VerifyProgress& progress = {}, std::uint64_t progress_every = 30,
                        ResimOptions options = {}, unsigned jobs = 1);

// Re-simulates from the logged keyframe at or before `divergent_tick - 1` (or tick 0) to the first
// logged keyframe at or after divergent_tick and diffs the two checkpoints; fills the diff_* fields
// and differences of v. At most max_objects objects.
void explain_divergence(const MatchLogReader& reader, std::uint64_t divergent_tick, ResimOptions options, VerifyResult& v,
                        std::size_t max_objects = 20);

}  // namespace throng::matchlog
