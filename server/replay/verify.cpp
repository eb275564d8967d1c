// throng-replay verify: re-simulate the log and compare every tick's state hash (and, in logs with
// world keyframes, every keyframe's checkpoint); --jobs splits it into keyframe-aligned segments.
#include <algorithm>
#include <cstdio>
#include <thread>

#include <fmt/format.h>

#include "commands.h"
#include "open_log.h"
#include "throng/matchlog/reader.h"
#include "throng/matchlog/replay.h"

namespace throng::replay {

int run_verify(const VerifyOptions& o) {
  const auto reader = open_log<matchlog::MatchLogReader>("verify", o.log);
  if (!reader) return kExitBadInput;
  const matchlog::LogHeader& h = reader->header();
  const matchlog::LogScan& s = reader->scan();
  const std::string here = matchlog::default_build_id();
  if (h.build_id != here)
    fmt::print(stderr, "note: the log was written by '{}', this is '{}': if the simulation changed in between, hashes may "
                       "legitimately differ\n", h.build_id, here);
  if (!s.scene_hash_matches)
    fmt::print(stderr, "note: this build re-serialises the log's scene differently (the scene format changed)\n");

  Progress progress("verify", !o.quiet);
  matchlog::VerifyResult v;
  try {
    matchlog::ResimOptions ro;
    ro.exact_interest = o.exact_config;
    const unsigned jobs = o.jobs > 0 ? o.jobs : std::max(1u, std::thread::hardware_concurrency());
    v = matchlog::verify_log(*reader, [&](std::uint64_t done, std::uint64_t total) { progress.update(done, total); }, 30, ro,
                             jobs);
  } catch (const std::exception& e) {
    progress.finish();
    fmt::print(stderr, "throng-replay verify: {}: {}\n", o.log, e.what());
    return kExitBadInput;
  }
  progress.finish();

  const auto speed = fmt::format("{:.1f} s, {:.0f} ticks/s, {:.1f}x real time at {} Hz; {} job{}, {} segment{}{}", v.seconds,
                                 v.ticks_per_second, v.realtime_factor, h.config.tick_hz, v.jobs, v.jobs == 1 ? "" : "s",
                                 v.segments, v.segments == 1 ? "" : "s",
                                 s.keyframes.empty() ? "" : fmt::format(", {} keyframes compared", v.keyframes_checked));
  auto print_objects = [&] {
    if (!v.differences.empty()) {
      fmt::print("Objects whose state differs at tick {} (the logged keyframe vs the re-simulation from the keyframe of tick {}){}:\n",
                 v.diff_tick, v.diff_from_tick, v.differences.size() >= 20 ? ", the 20 that differ most" : "");
      for (const auto& d : v.differences) fmt::print("  object {}: {}\n", d.object_id, d.what);
    }
    if (!v.diff_note.empty()) fmt::print("Objects: {}\n", v.diff_note);
  };
  if (v.mismatch) {
    fmt::print("MISMATCH at tick {}: the log has state hash {:016x}, the re-simulation gives {:016x}; ticks {}..{} matched ({})\n",
               v.mismatch_tick, v.expected_hash, v.actual_hash, v.start_tick + 1, v.start_tick + v.ticks_verified, speed);
    print_objects();
    return kExitMismatch;
  }
  if (v.keyframe_mismatch) {
    fmt::print("MISMATCH at the keyframe of tick {}: every state hash up to it matched, but the re-simulated world "
               "differs from the logged keyframe ({})\n", v.keyframe_mismatch_tick, speed);
    print_objects();
    return kExitMismatch;
  }
  if (v.stopped_at_gap) {
    fmt::print("verified ticks {}..{}: all hashes match ({}); STOPPED: tick {} onwards cannot be re-simulated, the writer "
               "dropped ticks {}.. (its backlog exceeded its cap)\n",
               v.start_tick + 1, v.start_tick + v.ticks_verified, speed, v.gap_first_tick, v.gap_first_tick);
    return kExitDamaged;
  }
  fmt::print("verified {} ticks ({}..{}{}): all state hashes{} match ({})\n", v.ticks_verified, v.start_tick + 1, s.last_tick,
             v.start_tick > 0 ? fmt::format(", from the keyframe of tick {} the log starts with", v.start_tick) : "",
             s.keyframes.empty() ? "" : " and keyframes", speed);
  if (v.ticks_verified > 0) {
    const double n = static_cast<double>(v.ticks_verified);
    fmt::print("per tick: world step {:.2f} ms, NPC AI {:.2f} ms, snapshots {:.2f} ms, inputs {:.3f} ms, other {:.3f} ms\n",
               v.step_ms / n, v.ai_ms / n, v.snapshots_ms / n, v.apply_ms / n,
               std::max(0.0, v.seconds * 1000.0 - v.step_ms - v.ai_ms - v.snapshots_ms - v.apply_ms) / n);
  }
  if (!v.keyframe_note.empty()) fmt::print("note: {}\n", v.keyframe_note);
  switch (s.end) {
    case matchlog::LogEnd::closed: break;
    case matchlog::LogEnd::unclosed: fmt::print("note: {}\n", s.problem); break;
    case matchlog::LogEnd::torn: fmt::print("note: {}\n", s.problem); break;
    case matchlog::LogEnd::corrupt:
      fmt::print("LOG DAMAGED: {}\n", s.problem);
      return kExitDamaged;
  }
  return kExitOk;
}

}  // namespace throng::replay
