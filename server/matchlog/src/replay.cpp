// Re-simulation and hash verification.
#include "throng/matchlog/replay.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <thread>

#include <fmt/format.h>

namespace throng::matchlog {
namespace {

scene::SceneDef replay_scene(const LogHeader& h, const ResimOptions& o) {
  scene::SceneDef s = h.scene;
  if (o.record_push_events) s.settings.record_push_events = true;
  return s;
}

match::MatchConfig replay_config(const LogHeader& h, const ResimOptions& o) {
  match::MatchConfig c = h.config;
  if (!o.exact_interest) {
    c.interest.radius_m = 0.01;
    c.interest.budget_bytes = 128;
    c.worker_threads = 1;  // not part of any result (match_config.h)
    c.push_events = o.record_push_events;  // nor this
  } else if (o.record_push_events || !o.logged_push_events) {
    c.push_events = o.record_push_events;  // forced on, or off for a follower
  }
  return c;
}

// Options for a re-simulation that starts from `checkpoint`: a version 1 checkpoint restores only
// into the logged interest settings.
ResimOptions options_for(ResimOptions o, std::span<const std::uint8_t> checkpoint) {
  if (!o.exact_interest && !Resimulator::restores_with_fast_interest(checkpoint)) o.exact_interest = true;
  return o;
}

bool same_bytes(std::span<const std::uint8_t> a, std::span<const std::uint8_t> b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin());
}

}  // namespace

Resimulator::Resimulator(const LogHeader& header, ResimOptions options)
    : options_(options),
      match_(std::make_unique<match::Match>(replay_scene(header, options), replay_config(header, options), header.match_id)) {}

bool Resimulator::restores_with_fast_interest(std::span<const std::uint8_t> checkpoint) {
  return match::checkpoint_sections(checkpoint).version >= 2;
}

Resimulator::~Resimulator() = default;

std::uint64_t Resimulator::tick() const { return match_->tick_index(); }

std::uint64_t Resimulator::step(TickRecord& t) {
  if (t.tick != match_->tick_index() + 1)
    throw LogError(fmt::format("cannot re-simulate tick {} after tick {}: ticks {}..{} are not in the log", t.tick,
                               match_->tick_index(), match_->tick_index() + 1, t.tick - 1));
  if ((t.flags & kTickShutdownBegan) != 0 && !shutdown_) {
    match_->begin_shutdown();
    shutdown_ = true;
  }
  match::InputQueue& q = match_->inputs();
  for (auto& j : t.inputs.joins) q.push(std::move(j));
  for (auto& c : t.inputs.commands) q.push(std::move(c));
  for (auto& p : t.inputs.params) q.push(std::move(p));
  report_ = &match_->tick(out_);
  return report_->state_hash;
}

namespace {

// One keyframe-aligned piece of a verification: ticks start+1 .. end, from the logged keyframe
// at `start` (0: the match start).
struct Range {
  std::uint64_t start = 0, end = 0;
};

struct RangeOutcome {
  std::uint64_t verified_through = 0;  // every tick start+1..this matched
  bool mismatch = false;
  std::uint64_t tick = 0, expected = 0, actual = 0;
  bool keyframe_mismatch = false;
  std::uint64_t keyframe_tick = 0;
  std::vector<match::BodyDifference> differences;  // keyframe mismatch: log vs re-simulation
  std::string where;  // keyframe mismatch: why the checkpoints could not be compared
  std::string outside_world_note;
  std::uint64_t keyframes_checked = 0;
  double apply_ms = 0, ai_ms = 0, step_ms = 0, snapshots_ms = 0;
  std::string error;
};

void lower_to(std::atomic<std::uint64_t>& a, std::uint64_t v) {
  std::uint64_t cur = a.load(std::memory_order_relaxed);
  while (v < cur && !a.compare_exchange_weak(cur, v, std::memory_order_relaxed)) {
  }
}

std::size_t first_keyframe_after(const std::vector<KeyframeInfo>& k, std::uint64_t tick) {
  return static_cast<std::size_t>(
      std::upper_bound(k.begin(), k.end(), tick, [](std::uint64_t t, const KeyframeInfo& x) { return t < x.tick; }) - k.begin());
}

RangeOutcome verify_range(const MatchLogReader& reader, ResimOptions options, Range range, bool check_keyframes,
                          std::atomic<std::uint64_t>& earliest_failure, std::atomic<std::uint64_t>& done,
                          const std::function<void()>& tick_done) {
  RangeOutcome o;
  o.verified_through = range.start;
  try {
    const auto& kfs = reader.scan().keyframes;
    std::vector<std::uint8_t> logged, mine;
    if (range.start > 0) {
      const KeyframeInfo* k = reader.find_keyframe(range.start);
      if (k == nullptr || k->tick != range.start) throw LogError(fmt::format("no keyframe at tick {}", range.start));
      reader.read_keyframe(*k, logged);
      options = options_for(options, logged);
    }
    const bool exact = options.exact_interest;
    const bool keyframe_baselines = reader.header().writer.keyframe_snapshot_baselines;
    Resimulator sim(reader.header(), options);
    if (range.start > 0) sim.restore(logged);
    TickCursor cursor(reader);
    cursor.seek(range.start + 1);
    std::size_t next_kf = first_keyframe_after(kfs, range.start);
    TickRecord t;
    while (sim.tick() < range.end) {
      if (earliest_failure.load(std::memory_order_relaxed) <= sim.tick()) break;  // an earlier tick already failed
      if (!cursor.next(t) || t.tick != sim.tick() + 1)
        throw LogError(fmt::format("tick {} is not readable although the scan listed it", sim.tick() + 1));
      const std::uint64_t expected = t.state_hash, tick = t.tick;
      const std::uint64_t actual = sim.step(t);
      done.fetch_add(1, std::memory_order_relaxed);
      const match::TickReport& rep = sim.last_report();
      o.apply_ms += (rep.drain_us + rep.apply_us) / 1000.0;
      o.ai_ms += rep.ai_us / 1000.0;
      o.step_ms += rep.step_us / 1000.0;
      o.snapshots_ms += rep.snapshots_us / 1000.0;
      if (actual != expected) {
        o.mismatch = true;
        o.tick = tick;
        o.expected = expected;
        o.actual = actual;
        lower_to(earliest_failure, tick);
        break;
      }
      o.verified_through = tick;
      if (check_keyframes && next_kf < kfs.size() && kfs[next_kf].tick == tick) {
        reader.read_keyframe(kfs[next_kf], logged);
        // Baselines only where they are compared: with the logged interest settings, when the log's
        // keyframes hold them.
        sim.match().save_checkpoint(mine, match::SaveOptions{.snapshot_baselines = exact && keyframe_baselines});
        ++o.keyframes_checked;
        ++next_kf;
        // The world must be equal (bodies: pose, velocities, parameters, ...): a difference is a
        // divergence even when the hash missed it. Outside the world (clients, NPC AI, counters;
        // snapshot baselines with the logged interest settings) a difference is reported, not
        // failed: the world and every hash still match.
        bool world_differs = false;
        try {
          const match::CheckpointSections a = match::checkpoint_sections(logged), b = match::checkpoint_sections(mine);
          if (!same_bytes(a.world, b.world)) {
            o.differences = match::diff_checkpoints(logged, mine, 20);
            world_differs = !o.differences.empty();
          }
          std::string section;
          std::span<const std::uint8_t> sa, sb;
          if (world_differs || a.version != b.version || !o.outside_world_note.empty()) {
            // nothing more to compare (a keyframe of another checkpoint version has other sections)
          } else if (!same_bytes(a.match_state, b.match_state)) {
            section = "match section (clients, NPC AI, counters)";
            sa = a.match_state, sb = b.match_state;
          } else if (exact && !same_bytes(a.snapshot_baselines, b.snapshot_baselines)) {
            section = "snapshot baselines";
            sa = a.snapshot_baselines, sb = b.snapshot_baselines;
          }
          if (!section.empty()) {
            const auto at = std::mismatch(sa.begin(), sa.end(), sb.begin(), sb.end());
            o.outside_world_note = fmt::format(
                "at the keyframe of tick {} (re-simulated from {}) the world and the state hashes match but the {} "
                "differs ({} bytes logged, {} re-simulated, first difference at byte {} of the section): match state "
                "outside the world did not survive the keyframe restore or re-simulation exactly",
                tick, range.start == 0 ? std::string("the match start") : fmt::format("the keyframe of tick {}", range.start),
                section, sa.size(), sb.size(), at.first - sa.begin());
          }
        } catch (const std::exception& e) {
          world_differs = true;
          o.where = e.what();
        }
        if (world_differs) {
          o.keyframe_mismatch = true;
          o.keyframe_tick = tick;
          lower_to(earliest_failure, tick);
          break;
        }
      }
      if (tick_done) tick_done();
    }
  } catch (const std::exception& e) {
    o.error = fmt::format("segment from tick {}: {}", range.start, e.what());
    lower_to(earliest_failure, range.start + 1);
  }
  return o;
}

}  // namespace

void Resimulator::restore(std::span<const std::uint8_t> checkpoint) {
  match_->restore_checkpoint(checkpoint, match::RestoreOptions{options_.exact_interest ? match::SnapshotBaselines::restore
                                                                                       : match::SnapshotBaselines::reset});
  report_ = nullptr;
  shutdown_ = false;  // a flagged tick after the keyframe calls begin_shutdown() again (idempotent)
}

VerifyResult verify_log(MatchLogReader& reader, const VerifyProgress& progress, std::uint64_t progress_every,
                        ResimOptions options, unsigned jobs) {
  using Clock = std::chrono::steady_clock;
  VerifyResult v;
  const LogScan& s = reader.scan();
  v.ticks_total = s.ticks;
  const auto t0 = Clock::now();
  // A log that starts from a checkpoint is verified from it; its opening gap is no hole.
  const std::uint64_t base = start_keyframe_tick(s);
  const std::span<const GapInfo> gaps = holes(s);
  v.start_tick = base;
  const std::uint64_t contiguous_last = s.ticks == 0 ? base : (gaps.empty() ? s.last_tick : gaps.front().first_tick - 1);
  const bool keyframes = !s.keyframes.empty();
  jobs = std::max(1u, jobs);

  // Keyframe-aligned ranges: more than jobs, so a slow stretch of the match does not leave
  // threads idle at the end.
  std::vector<Range> ranges;
  {
    std::vector<std::uint64_t> starts{base};
    if (keyframes && jobs > 1) {
      std::vector<std::uint64_t> usable;
      for (const KeyframeInfo& k : s.keyframes)
        if (k.tick > base && k.tick < contiguous_last) usable.push_back(k.tick);
      const std::size_t r = std::min<std::size_t>(usable.size() + 1, 4 * static_cast<std::size_t>(jobs));
      for (std::size_t i = 1; i < r; ++i) starts.push_back(usable[i * (usable.size() + 1) / r - 1]);
    }
    for (std::size_t i = 0; i < starts.size(); ++i)
      ranges.push_back({starts[i], i + 1 < starts.size() ? starts[i + 1] : contiguous_last});
  }
  v.segments = ranges.size();
  v.jobs = static_cast<unsigned>(std::min<std::size_t>(jobs, ranges.size()));

  std::atomic<std::uint64_t> earliest_failure{~0ull}, done{0};
  std::vector<RangeOutcome> outcomes(ranges.size());
  if (v.jobs == 1) {
    std::uint64_t n = 0;
    const std::function<void()> tick_done = [&] {
      if (progress && progress_every > 0 && ++n % progress_every == 0) progress(n, v.ticks_total);
    };
    for (std::size_t i = 0; i < ranges.size(); ++i)
      outcomes[i] = verify_range(reader, options, ranges[i], keyframes, earliest_failure, done, tick_done);
  } else {
    std::atomic<std::size_t> next{0};
    std::atomic<unsigned> running{v.jobs};
    std::vector<std::thread> threads;
    for (unsigned j = 0; j < v.jobs; ++j) {
      threads.emplace_back([&] {
        for (std::size_t i = next.fetch_add(1); i < ranges.size(); i = next.fetch_add(1))
          outcomes[i] = verify_range(reader, options, ranges[i], keyframes, earliest_failure, done, {});
        running.fetch_sub(1);
      });
    }
    while (running.load() > 0) {
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
      if (progress) progress(done.load(std::memory_order_relaxed), v.ticks_total);
    }
    for (std::thread& t : threads) t.join();
  }

  // In tick order: everything up to the first failure counts.
  for (std::size_t i = 0; i < ranges.size(); ++i) {
    const RangeOutcome& o = outcomes[i];
    v.apply_ms += o.apply_ms;
    v.ai_ms += o.ai_ms;
    v.step_ms += o.step_ms;
    v.snapshots_ms += o.snapshots_ms;
    v.keyframes_checked += o.keyframes_checked;
    if (v.keyframe_note.empty()) v.keyframe_note = o.outside_world_note;
    if (!o.error.empty()) throw LogError(o.error);
    if (o.mismatch) {
      v.mismatch = true;
      v.mismatch_tick = o.tick;
      v.expected_hash = o.expected;
      v.actual_hash = o.actual;
      v.ticks_verified = o.tick - 1 - base;
      break;
    }
    v.ticks_verified = o.verified_through - base;
    if (o.keyframe_mismatch) {
      v.keyframe_mismatch = true;
      v.keyframe_mismatch_tick = o.keyframe_tick;
      v.differences = o.differences;
      v.diff_from_tick = ranges[i].start;
      v.diff_tick = o.keyframe_tick;
      if (v.differences.empty()) v.diff_note = "the keyframes could not be compared: " + o.where;
      break;
    }
    if (o.verified_through != ranges[i].end) break;  // cannot happen without a failure above
  }
  if (!v.mismatch && !v.keyframe_mismatch && !gaps.empty()) {
    v.stopped_at_gap = true;
    v.gap_first_tick = gaps.front().first_tick;
  }
  const std::uint64_t simulated = done.load();
  v.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  if (progress) progress(v.ticks_verified, v.ticks_total);  // counts, from the log's first tick
  if (v.mismatch) explain_divergence(reader, v.mismatch_tick, options, v);
  if (v.seconds > 0) {
    v.ticks_per_second = static_cast<double>(simulated) / v.seconds;
    v.realtime_factor = v.ticks_per_second / static_cast<double>(reader.header().config.tick_hz);
  }
  return v;
}

void explain_divergence(const MatchLogReader& reader, std::uint64_t divergent_tick, ResimOptions options, VerifyResult& v,
                        std::size_t max_objects) {
  const auto& kfs = reader.scan().keyframes;
  if (kfs.empty()) {
    v.diff_note = "the log has no world keyframes (format version 1, or keyframes were off), so which objects differ "
                  "cannot be told from it";
    return;
  }
  const std::size_t after = first_keyframe_after(kfs, divergent_tick - 1);  // first keyframe >= divergent_tick
  if (after == kfs.size()) {
    v.diff_note = fmt::format("no logged keyframe at or after tick {} to compare the world with", divergent_tick);
    return;
  }
  const KeyframeInfo* before = reader.find_keyframe(divergent_tick - 1);
  try {
    std::vector<std::uint8_t> logged, mine;
    if (before != nullptr) {
      reader.read_keyframe(*before, logged);
      options = options_for(options, logged);
    }
    Resimulator sim(reader.header(), options);
    if (before != nullptr) sim.restore(logged);
    TickCursor cursor(reader);
    cursor.seek(sim.tick() + 1);
    TickRecord t;
    while (sim.tick() < kfs[after].tick) {
      if (!cursor.next(t) || t.tick != sim.tick() + 1) {
        v.diff_note = fmt::format("tick {} is missing from the log", sim.tick() + 1);
        return;
      }
      sim.step(t);
    }
    reader.read_keyframe(kfs[after], logged);
    sim.match().save_checkpoint(mine);
    v.diff_from_tick = before != nullptr ? before->tick : 0;
    v.diff_tick = kfs[after].tick;
    v.differences = match::diff_checkpoints(logged, mine, max_objects);
    if (v.differences.empty())
      v.diff_note = fmt::format(
          "the re-simulated world at the keyframe of tick {} equals the logged one{}: the logged state hash itself "
          "looks wrong, or the difference vanished by then",
          v.diff_tick, logged == mine ? " byte for byte" : "");
  } catch (const std::exception& e) {
    v.diff_note = fmt::format("comparing with the keyframe failed: {}", e.what());
  }
}

}  // namespace throng::matchlog
