// LogPlayer: a Resimulator positioned anywhere in a log (see log_player.h).
#include "throng/matchlog/log_player.h"

#include <algorithm>
#include <chrono>

#include <fmt/format.h>

namespace throng::matchlog {

struct LogPlayer::Impl {
  explicit Impl(const std::string& path, PlayerOptions o) : reader(path), options(o) {
    const LogScan& s = reader.scan();
    base = start_keyframe_tick(s);
    last = s.ticks == 0 ? base : s.last_tick;
    if (const auto h = holes(s); !h.empty()) last = std::min(last, h.front().first_tick - 1);
    restart();
  }

  // A fresh Match before its first tick, the reader at tick 1; for a log that starts from a
  // checkpoint, the match restored from it, the reader at the tick after.
  void restart() {
    sim.reset();
    sim = std::make_unique<Resimulator>(reader.header(), options.resim);
    reader.rewind();
    rec = TickRecord{};
    matched = true;
    if (base == 0) return;
    const KeyframeInfo* k = reader.find_keyframe(base);
    try {
      read_into_sim(*k);
    } catch (const std::exception& e) {
      throw LogError(fmt::format("{}: the log starts from the keyframe of tick {}, which cannot be restored: {}",
                                 reader.path(), base, e.what()));
    }
    reader.seek(base + 1);
    rec.tick = base;
  }

  void read_into_sim(const KeyframeInfo& k) {
    reader.read_keyframe(k, checkpoint);
    if (!options.resim.exact_interest && !Resimulator::restores_with_fast_interest(checkpoint)) {
      // A version 1 keyframe (an earlier build's log) restores only into the logged interest
      // settings: from now on this player uses them.
      options.resim.exact_interest = true;
      sim = std::make_unique<Resimulator>(reader.header(), options.resim);
    }
    sim->restore(checkpoint);
  }

  // Jumps to a logged keyframe (in place: restore_checkpoint replaces the whole simulation state).
  // False if it cannot be restored (then keyframes are not used again; see keyframe_problem).
  bool restore(const KeyframeInfo& k) {
    if (k.tick == base) {  // the log's start: no record of its own
      restart();
      return true;
    }
    try {
      read_into_sim(k);
    } catch (const std::exception& e) {
      keyframe_problem = fmt::format("the keyframe of tick {} cannot be restored ({}); seeking re-simulates from tick 1",
                                     k.tick, e.what());
      restart();
      return false;
    }
    // The keyframe tick's own record (its logged hash), leaving the reader at the next tick.
    reader.seek(k.tick);
    read_record(k.tick);
    matched = true;
    return true;
  }

  bool step() {
    if (sim->tick() >= last) return false;
    read_record(sim->tick() + 1);
    const std::uint64_t expected = rec.state_hash;
    matched = sim->step(rec) == expected;
    return true;
  }

  // The reader's next record into `rec`; it must be `tick`'s.
  void read_record(std::uint64_t tick) {
    if (!reader.next(rec) || rec.tick != tick)
      throw LogError(fmt::format("{}: tick {} is not readable although the scan listed it", reader.path(), tick));
  }

  MatchLogReader reader;
  PlayerOptions options;
  std::unique_ptr<Resimulator> sim;
  std::uint64_t base = 0;  // the log starts after this tick, from its keyframe (0: from tick 1)
  std::uint64_t last = 0;
  TickRecord rec;
  bool matched = true;
  std::vector<std::uint8_t> checkpoint;
  std::string keyframe_problem;
  match::TickReport empty_report;  // last_report() before any step
};

LogPlayer::LogPlayer(const std::string& path, PlayerOptions options) : impl_(std::make_unique<Impl>(path, options)) {}
LogPlayer::~LogPlayer() = default;

const LogHeader& LogPlayer::header() const { return impl_->reader.header(); }
const LogScan& LogPlayer::scan() const { return impl_->reader.scan(); }
std::uint32_t LogPlayer::tick_hz() const { return impl_->reader.header().config.tick_hz; }
std::uint64_t LogPlayer::first_tick() const { return impl_->last <= impl_->base ? 0 : impl_->base + 1; }
std::uint64_t LogPlayer::last_tick() const { return impl_->last; }
std::uint64_t LogPlayer::tick() const { return impl_->sim->tick(); }

SeekResult LogPlayer::seek(std::uint64_t target) {
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  Impl& m = *impl_;
  target = std::max(std::min(target, m.last), m.base);
  SeekResult r;
  const KeyframeInfo* k = m.keyframe_problem.empty() ? m.reader.find_keyframe(target) : nullptr;
  if (k != nullptr && (k->tick > m.sim->tick() || target < m.sim->tick())) {
    if (m.restore(*k)) r.keyframe_tick = k->tick;
  } else if (target < m.sim->tick()) {
    m.restart();  // backwards without a keyframe: from the match start
  }
  while (m.sim->tick() < target) {
    m.step();
    ++r.ticks_simulated;
    if (!m.matched && r.hash_mismatches++ == 0) r.first_mismatch_tick = m.sim->tick();
  }
  r.tick = m.sim->tick();
  r.logged_hash = m.rec.tick == r.tick ? m.rec.state_hash : 0;
  r.ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
  return r;
}

bool LogPlayer::step() { return impl_->step(); }
const std::string& LogPlayer::keyframe_problem() const { return impl_->keyframe_problem; }
bool LogPlayer::last_hash_matched() const { return impl_->matched; }
const match::Match& LogPlayer::match() const { return impl_->sim->match(); }
const match::Outbox& LogPlayer::outbox() const { return impl_->sim->outbox(); }
const match::TickReport& LogPlayer::last_report() const {
  return impl_->sim->stepped() ? impl_->sim->last_report() : impl_->empty_report;
}

}  // namespace throng::matchlog
