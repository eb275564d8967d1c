// A match kept in step with a primary from its tick entries and checkpoints (follower.h).
#include "throng/matchlog/follower.h"

#include <fmt/format.h>

#include "throng/matchlog/format.h"

namespace throng::matchlog {

MatchFollower::MatchFollower(const LogHeader& header, FollowerOptions options)
    : options_(options), resim_(header, options.resim) {}

MatchFollower::~MatchFollower() = default;

std::uint64_t MatchFollower::tick() const { return resim_.tick(); }

FollowState MatchFollower::state() const {
  return diverged_ || !held_.empty() ? FollowState::needs_checkpoint : FollowState::following;
}

void MatchFollower::on_tick_entry(std::span<const std::uint8_t> entry) {
  TickRecord t;
  std::size_t pos = 0;
  decode_tick(entry, pos, t, kFormatVersion);  // throws LogError on a malformed entry
  if (pos != entry.size()) {
    throw LogError(fmt::format("tick entry of tick {} is followed by {} more bytes: one entry expected", t.tick,
                               entry.size() - pos));
  }
  if (t.tick == 0) throw LogError("tick entry of tick 0: ticks start at 1");
  if (t.tick <= tick()) {
    ++stats_.stale_entries;
    return;
  }
  if (t.tick - 1 != tick() && !held_.contains(t.tick - 1) && !held_.contains(t.tick)) ++stats_.gaps;
  hold(std::move(t));
  apply_held();
}

void MatchFollower::on_checkpoint(std::span<const std::uint8_t> checkpoint) {
  // A checkpoint behind a match that still follows would step it back past ticks it no longer
  // holds (a late answer to an earlier request): it brings nothing.
  if (!diverged_ && match::checkpoint_sections(checkpoint).tick < tick()) {
    ++stats_.stale_checkpoints;
    return;
  }
  if (diverged_) explain_divergence(checkpoint);
  resim_.restore(checkpoint);  // throws with the match unchanged (the restore stages before it commits)
  ++stats_.checkpoints;
  diverged_ = false;
  // An entry further ahead of the primary's own checkpoint than the hold limit cannot be the
  // primary's next ticks (a damaged entry, another server's): held, it would keep the follower
  // waiting for ticks that never come.
  for (auto it = held_.upper_bound(tick() + options_.max_held_ticks); it != held_.end(); it = held_.erase(it))
    ++stats_.held_dropped;
  apply_held();
}

// The diverged match, stepped on with the primary's entries to the checkpoint's tick, against the
// checkpoint: which objects went wrong (the match is replaced right after, so stepping it costs
// nothing that matters).
void MatchFollower::explain_divergence(std::span<const std::uint8_t> checkpoint) {
  divergence_ = Divergence{};
  divergence_.first_tick = stats_.first_mismatch_tick;
  try {
    const std::uint64_t at = match::checkpoint_sections(checkpoint).tick;
    if (at < tick()) {
      divergence_.note = fmt::format("the checkpoint (tick {}) is older than the diverged match (tick {})", at, tick());
      return;
    }
    for (std::uint64_t t = tick() + 1; t <= at; ++t) {
      const auto it = held_.find(t);
      if (it == held_.end()) {
        divergence_.note = fmt::format("tick {}'s entry never arrived: the match cannot be brought to tick {}", t, at);
        return;
      }
      TickRecord copy = it->second;  // held entries after `at` are still applied after the restore
      resim_.step(copy);
    }
    resim_.match().save_checkpoint(mine_);
    divergence_.compared_at = at;
    divergence_.differences = match::diff_checkpoints(checkpoint, mine_);
    if (divergence_.differences.empty())
      divergence_.note = fmt::format("the worlds are equal at tick {}: the difference was outside the world, or vanished", at);
  } catch (const std::exception& e) {
    divergence_.compared_at = 0;
    divergence_.note = fmt::format("cannot compare with the checkpoint: {}", e.what());
  }
}

void MatchFollower::hold(TickRecord&& t) {
  const std::uint64_t at = t.tick;
  held_.insert_or_assign(at, std::move(t));  // a repeated entry replaces the held one
  while (held_.size() > options_.max_held_ticks) {
    held_.erase(held_.begin());
    ++stats_.held_dropped;
  }
}

// Applies held entries while the next tick is there and the match still follows; drops those a
// checkpoint or an earlier apply already covers.
void MatchFollower::apply_held() {
  while (!held_.empty()) {
    auto it = held_.begin();
    if (it->first <= tick()) {
      ++stats_.stale_entries;
      held_.erase(it);
      continue;
    }
    if (diverged_ || it->first != tick() + 1) return;
    TickRecord t = std::move(it->second);
    held_.erase(it);
    const std::uint64_t primary_hash = t.state_hash;
    last_flags_ = t.flags;
    if (resim_.step(t) == primary_hash) {
      ++stats_.applied;
      if (options_.on_applied) options_.on_applied(t.tick, primary_hash, t.flags, resim_.match().last_inputs());
    } else {
      ++stats_.mismatches;
      stats_.first_mismatch_tick = t.tick;
      diverged_ = true;
    }
  }
}

}  // namespace throng::matchlog
