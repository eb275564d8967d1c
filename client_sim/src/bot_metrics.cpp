#include "throng/client_sim/bot_metrics.h"

#include <algorithm>

namespace throng::client_sim {

namespace {
// A command not applied within this many pending entries is forgotten (lost, or the server never
// applies it); keeps memory bounded for a client the server ignores.
constexpr std::size_t kMaxPending = 4096;
}  // namespace

void BotMetrics::on_command_sent(std::uint32_t sequence, Expect expect, TimePoint t) {
  ++commands_.sent;
  switch (expect) {
    case Expect::accept:
      ++commands_.expect_accept;
      if (pending_.size() >= kMaxPending) pending_.pop_front();
      pending_.push_back(Pending{sequence, t});
      break;
    case Expect::reject: ++commands_.expect_reject; break;
    case Expect::unknown: ++commands_.expect_unknown; break;
  }
}

void BotMetrics::on_snapshot_received(std::uint64_t tick, std::size_t wire_bytes, TimePoint t) {
  ++snapshots_.samples;
  snapshots_.bytes += wire_bytes;
  if (!first_snapshot_) first_snapshot_ = t;
  if (last_snapshot_) interarrival_ms_.add(ms_between(*last_snapshot_, t));
  last_snapshot_ = t;
  if (newest_tick_ && tick <= *newest_tick_) {
    ++snapshots_.out_of_order;
    return;
  }
  if (newest_tick_ && tick > *newest_tick_ + 1) {
    const std::uint64_t missed = tick - *newest_tick_ - 1;
    snapshots_.missed_ticks += missed;
    snapshots_.longest_gap_ticks = std::max(snapshots_.longest_gap_ticks, missed);
  }
  newest_tick_ = tick;
  if (tick_ms_ > 0) {
    const double offset = ms_between(TimePoint{}, t) - static_cast<double>(tick) * tick_ms_;
    if (!min_offset_ms_ || offset < *min_offset_ms_) min_offset_ms_ = offset;
    staleness_ms_.add(offset - *min_offset_ms_);
  }
}

void BotMetrics::on_applied_sequence(std::uint32_t last_applied_sequence, TimePoint t) {
  while (!pending_.empty() && pending_.front().sequence <= last_applied_sequence) {
    const double ms = ms_between(pending_.front().sent, t);
    latency_ms_.add(ms);
    window_latency_ms_.add(ms);
    ++commands_.applied;
    pending_.pop_front();
  }
}

void BotMetrics::on_rejoin() {
  pending_.clear();
  newest_tick_.reset();
}

std::optional<double> BotMetrics::join_ms() const {
  if (!launch_ || !first_snapshot_) return std::nullopt;
  return ms_between(*launch_, *first_snapshot_);
}

Samples BotMetrics::take_window_latency() {
  Samples out;
  std::swap(out, window_latency_ms_);
  return out;
}

}  // namespace throng::client_sim
