#pragma once
// Re-simulation from a log: a fresh Match built from the header's scene and config, fed each
// logged tick's inputs exactly as the server's tick drained them. verify_log compares every
// tick's state hash with the logged one.
//
// What a mismatch can say: the log holds inputs and a 64-bit hash per tick, not the world, so the
// first divergent tick and both hashes are all that can be known; which bodies differ needs world
// keyframes in the log (phase 2 of the log issue).
#include <cstdint>
#include <functional>
#include <memory>

#include "throng/match/match.h"
#include "throng/matchlog/log_header.h"
#include "throng/matchlog/reader.h"
#include "throng/matchlog/tick_record.h"

namespace throng::matchlog {

struct ResimOptions {
  // Force WorldSettings::record_push_events on (export). The state hash does not depend on it
  // (push events steer nothing), and every step's hash is checked anyway.
  bool record_push_events = false;
  // false (default): replay with a 1 cm interest radius and the smallest snapshot budget. The
  // interest settings only shape snapshot content, which is not part of the state hash
  // (server/match: match_snapshots.cpp is their only reader), and building 50 full snapshots is
  // ~45% of a re-simulated tick at 6,000 bodies. Should that ever stop being true, verify reports
  // a mismatch (it can never pass falsely: the hash covers the world). true: the logged settings.
  bool exact_interest = false;
};

class Resimulator {
 public:
  explicit Resimulator(const LogHeader& header, ResimOptions options = {});
  ~Resimulator();
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
  std::unique_ptr<match::Match> match_;
  match::Outbox out_;
  const match::TickReport* report_ = nullptr;
  bool shutdown_ = false;
};

struct VerifyResult {
  std::uint64_t ticks_total = 0;     // readable ticks in the log
  std::uint64_t ticks_verified = 0;  // ticks whose hash matched, from tick 1 on
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
  bool all_match() const { return !mismatch && !stopped_at_gap && ticks_verified == ticks_total; }
};

// progress(done, total) is called every progress_every ticks and once at the end.
using VerifyProgress = std::function<void(std::uint64_t done, std::uint64_t total)>;
VerifyResult verify_log(MatchLogReader& reader, const VerifyProgress& progress = {}, std::uint64_t progress_every = 30,
                        ResimOptions options = {});

}  // namespace throng::matchlog
