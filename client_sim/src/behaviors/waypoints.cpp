// waypoints: a fixed closed path around the spawn point — the corners of a square of half-size
// kHalf metres, walked anticlockwise. The next corner is taken within kReach metres, or after
// kGiveUp seconds when a crowd blocks the way.
#include <array>

#include "steer.h"

namespace throng::client_sim::detail {
namespace {

constexpr double kHalf = 5.0;
constexpr double kReach = 0.75;
constexpr double kGiveUp = 6.0;
constexpr std::array<std::array<double, 2>, 4> kCorners{{{kHalf, -kHalf}, {kHalf, kHalf}, {-kHalf, kHalf}, {-kHalf, -kHalf}}};

class Waypoints final : public Mover {
 public:
  std::string_view name() const override { return "waypoints"; }

  Intent intent(const BehaviorContext& ctx) override {
    auto target = [&] { return std::array<double, 2>{ctx.spawn.x + kCorners[next_][0], ctx.spawn.y + kCorners[next_][1]}; };
    auto t = target();
    const double dx = t[0] - ctx.self.x, dy = t[1] - ctx.self.y;
    if (dx * dx + dy * dy < kReach * kReach || ctx.time_s - since_s_ > kGiveUp) {
      next_ = (next_ + 1) % kCorners.size();
      since_s_ = ctx.time_s;
      t = target();
    }
    return steer_to(ctx.self, t[0], t[1], 0.8, 0.0);
  }

 private:
  std::size_t next_ = 0;
  double since_s_ = 0.0;
};

}  // namespace

std::unique_ptr<Behavior> make_waypoints() { return std::make_unique<Waypoints>(); }

}  // namespace throng::client_sim::detail
