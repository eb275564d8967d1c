// The misbehaviours: every command they spoil carries a large move, so a server that wrongly
// applied one would visibly move an entity.
//  nan    — one command per tick with NaN moves (every third also a NaN facing): non_finite.
//  flood  — kFloodPerTick commands per tick, honest content (standing still): beyond the server's
//           per-tick limit they are rate_limited.
//  hijack — one command per tick for someone else's entity (another client's, learnt from its
//           JoinReply, else any roster object that is not its own): not_your_entity.
//  stale  — kHonest honest standing-still commands, then replays of those old sequence numbers
//           with a full move: stale_sequence (duplicate_sequence for the newest one).
#include <algorithm>
#include <limits>

#include "steer.h"

namespace throng::client_sim::detail {
namespace {

constexpr int kFloodPerTick = 20;
constexpr std::uint32_t kHonest = 15;

Intent stand(const BehaviorContext& ctx) { return Intent{0, 0, facing_of(0, 0, ctx.self.yaw), 0}; }
Intent full_move() { return Intent{1.0f, 0.0f, 0.0f, 0}; }

class Nan final : public Behavior {
 public:
  std::string_view name() const override { return "nan"; }
  void act(const BehaviorContext&, CommandSink& out) override {
    protocol::Command& c = out.emit(full_move(), Expect::reject);
    c.move_x = std::numeric_limits<float>::quiet_NaN();
    c.move_y = std::numeric_limits<float>::quiet_NaN();
    if (++n_ % 3 == 0) c.facing_rad = std::numeric_limits<float>::quiet_NaN();
  }

 private:
  std::uint64_t n_ = 0;
};

class Flood final : public Behavior {
 public:
  std::string_view name() const override { return "flood"; }
  void act(const BehaviorContext& ctx, CommandSink& out) override {
    for (int i = 0; i < kFloodPerTick; ++i) out.emit(stand(ctx), i == 0 ? Expect::accept : Expect::unknown);
  }
};

class Hijack final : public Behavior {
 public:
  std::string_view name() const override { return "hijack"; }
  void act(const BehaviorContext& ctx, CommandSink& out) override {
    const std::uint32_t target = pick(ctx);
    protocol::Command& c = out.emit(full_move(), Expect::reject);
    c.entity = target;
  }

 private:
  std::uint32_t pick(const BehaviorContext& ctx) {
    const auto& others = ctx.other_client_entities;
    const bool still_client = target_ != 0 && std::find(others.begin(), others.end(), target_) != others.end();
    if (still_client) return target_;
    for (std::uint32_t e : others) {
      if (e != ctx.entity) return target_ = e;
    }
    if (target_ != 0) return target_;  // a roster object picked earlier
    if (const MatchView* m = ctx.world.match(); m && m->ids().size() > 1) {
      std::uniform_int_distribution<std::size_t> any(0, m->ids().size() - 1);
      for (int tries = 0; tries < 16; ++tries) {
        const std::uint32_t id = m->ids()[any(ctx.rng)];
        if (id != ctx.entity) return target_ = id;
      }
    }
    return ctx.entity + 1;  // blind guess until the roster is known
  }
  std::uint32_t target_ = 0;
};

class Stale final : public Behavior {
 public:
  std::string_view name() const override { return "stale"; }
  void act(const BehaviorContext& ctx, CommandSink& out) override {
    if (honest_ < kHonest) {
      ++honest_;
      out.emit(stand(ctx));
      return;
    }
    protocol::Command& c = out.emit(full_move(), Expect::reject);
    c.sequence = 1 + static_cast<std::uint32_t>(replay_++ % kHonest);
  }

 private:
  std::uint32_t honest_ = 0;
  std::uint64_t replay_ = 0;
};

}  // namespace

std::unique_ptr<Behavior> make_nan() { return std::make_unique<Nan>(); }
std::unique_ptr<Behavior> make_flood() { return std::make_unique<Flood>(); }
std::unique_ptr<Behavior> make_hijack() { return std::make_unique<Hijack>(); }
std::unique_ptr<Behavior> make_stale() { return std::make_unique<Stale>(); }

}  // namespace throng::client_sim::detail
