// wander: a new random heading and pace every 1.5–3 s; turns back towards its spawn when more
// than kLeash metres away and towards the world's centre near its bounds.
#include <cmath>

#include "steer.h"

namespace throng::client_sim::detail {
namespace {

constexpr double kLeash = 20.0;   // metres from spawn
constexpr double kMargin = 5.0;   // metres from the world bounds

class Wander final : public Mover {
 public:
  std::string_view name() const override { return "wander"; }

  Intent intent(const BehaviorContext& ctx) override {
    if (ctx.time_s >= next_turn_s_) {
      std::uniform_real_distribution<double> angle(-protocol::kPi, protocol::kPi), pace(0.5, 1.0), hold(1.5, 3.0);
      heading_ = angle(ctx.rng);
      speed_ = pace(ctx.rng);
      next_turn_s_ = ctx.time_s + hold(ctx.rng);
    }
    double heading = heading_;
    const double sx = ctx.spawn.x - ctx.self.x, sy = ctx.spawn.y - ctx.self.y;
    if (sx * sx + sy * sy > kLeash * kLeash) heading = std::atan2(sy, sx);
    if (const MatchView* m = ctx.world.match(); m && m->has_bounds()) {
      if (ctx.self.x < m->min_x() + kMargin || ctx.self.x > m->max_x() - kMargin ||
          ctx.self.y < m->min_y() + kMargin || ctx.self.y > m->max_y() - kMargin) {
        heading = std::atan2(0.5 * (m->min_y() + m->max_y()) - ctx.self.y, 0.5 * (m->min_x() + m->max_x()) - ctx.self.x);
      }
    }
    Intent i;
    i.move_x = static_cast<float>(std::cos(heading) * speed_);
    i.move_y = static_cast<float>(std::sin(heading) * speed_);
    i.facing_rad = static_cast<float>(heading);
    return i;
  }

 private:
  double next_turn_s_ = -1.0;
  double heading_ = 0.0;
  double speed_ = 0.0;
};

}  // namespace

std::unique_ptr<Behavior> make_wander() { return std::make_unique<Wander>(); }

}  // namespace throng::client_sim::detail
