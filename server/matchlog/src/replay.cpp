// Re-simulation and hash verification.
#include "throng/matchlog/replay.h"

#include <chrono>

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
  }
  return c;
}

}  // namespace

Resimulator::Resimulator(const LogHeader& header, ResimOptions options)
    : match_(std::make_unique<match::Match>(replay_scene(header, options), replay_config(header, options), header.match_id)) {}

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

VerifyResult verify_log(MatchLogReader& reader, const VerifyProgress& progress, std::uint64_t progress_every,
                        ResimOptions options) {
  using Clock = std::chrono::steady_clock;
  VerifyResult v;
  v.ticks_total = reader.scan().ticks;
  const auto t0 = Clock::now();
  Resimulator sim(reader.header(), options);
  reader.rewind();
  TickRecord t;
  std::uint64_t done = 0;
  while (reader.next(t)) {
    if (t.tick != sim.tick() + 1) {
      v.stopped_at_gap = true;
      v.gap_first_tick = sim.tick() + 1;
      break;
    }
    const std::uint64_t expected = t.state_hash;
    const std::uint64_t tick = t.tick;
    const std::uint64_t actual = sim.step(t);
    ++done;
    const match::TickReport& rep = sim.last_report();
    v.apply_ms += (rep.drain_us + rep.apply_us) / 1000.0;
    v.ai_ms += rep.ai_us / 1000.0;
    v.step_ms += rep.step_us / 1000.0;
    v.snapshots_ms += rep.snapshots_us / 1000.0;
    if (actual != expected) {
      v.mismatch = true;
      v.mismatch_tick = tick;
      v.expected_hash = expected;
      v.actual_hash = actual;
      break;
    }
    v.ticks_verified = done;
    if (progress && progress_every > 0 && done % progress_every == 0) progress(done, v.ticks_total);
  }
  // Ticks the writer dropped at the very end leave no later tick to trip over above.
  if (!v.mismatch && !v.stopped_at_gap && !reader.scan().gaps.empty()) {
    v.stopped_at_gap = true;
    v.gap_first_tick = reader.scan().gaps.front().first_tick;
  }
  v.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  if (progress) progress(done, v.ticks_total);
  if (v.seconds > 0) {
    v.ticks_per_second = static_cast<double>(done) / v.seconds;
    v.realtime_factor = v.ticks_per_second / static_cast<double>(reader.header().config.tick_hz);
  }
  return v;
}

}  // namespace throng::matchlog
