// charge: run at full speed at the nearest enemy in the bot's ClientWorld (an object whose roster
// faction differs from the bot's own), re-picking the nearest every kRetarget seconds (a scan of
// the whole ClientWorld every tick would cost more than everything else a bot does) and at once
// when the target is gone. With no enemy in view it walks towards the world's centre (or stands
// when the bounds are unknown).
#include <limits>
#include <optional>

#include "steer.h"

namespace throng::client_sim::detail {
namespace {

constexpr double kRetarget = 0.25;

class Charge final : public Mover {
 public:
  std::string_view name() const override { return "charge"; }

  Intent intent(const BehaviorContext& ctx) override {
    const MatchView* m = ctx.world.match();
    if (!m) return Intent{0, 0, static_cast<float>(ctx.self.yaw), 0};
    std::optional<ObjectState> target;
    if (target_ != 0) target = ctx.world.object(target_);
    if (ctx.time_s >= retarget_at_ || (target_ != 0 && !target)) {
      target = nearest_enemy(ctx, *m);
      target_ = target ? target->id : 0;
      retarget_at_ = ctx.time_s + kRetarget;
    }
    if (target) return steer_to(ctx.self, target->x, target->y, 1.0, 0.0);
    if (m->has_bounds())
      return steer_to(ctx.self, 0.5 * (m->min_x() + m->max_x()), 0.5 * (m->min_y() + m->max_y()), 0.6, 2.0);
    return Intent{0, 0, static_cast<float>(ctx.self.yaw), 0};
  }

 private:
  static std::optional<ObjectState> nearest_enemy(const BehaviorContext& ctx, const MatchView& m) {
    double best = std::numeric_limits<double>::infinity();
    std::optional<ObjectState> out;
    ctx.world.for_each([&](const ObjectState& o) {
      if (o.id == ctx.entity) return;
      const double dx = o.x - ctx.self.x, dy = o.y - ctx.self.y;
      const double d2 = dx * dx + dy * dy;
      if (d2 > best || (d2 == best && out && o.id > out->id)) return;  // ties by id: independent of map order
      const RosterEntry* r = m.find(o.id);
      if (!r || r->faction == ctx.faction) return;
      best = d2;
      out = o;
    });
    return out;
  }

  std::uint32_t target_ = 0;
  double retarget_at_ = 0;
};

}  // namespace

std::unique_ptr<Behavior> make_charge() { return std::make_unique<Charge>(); }

}  // namespace throng::client_sim::detail
