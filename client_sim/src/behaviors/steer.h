#pragma once
// Small helpers shared by the behaviors.
#include <algorithm>
#include <cmath>

#include "throng/client_sim/behavior.h"

namespace throng::client_sim::detail {

inline float facing_of(double dx, double dy, double fallback) {
  if (dx * dx + dy * dy < 1e-12) return static_cast<float>(std::clamp(fallback, -protocol::kPi, protocol::kPi));
  return static_cast<float>(std::atan2(dy, dx));
}

// Move towards (tx, ty) at `speed` (fraction of max speed), slowing within `slow_radius`.
inline Intent steer_to(const ObjectState& self, double tx, double ty, double speed, double slow_radius = 0.5) {
  const double dx = tx - self.x, dy = ty - self.y;
  const double d = std::sqrt(dx * dx + dy * dy);
  Intent i;
  i.facing_rad = facing_of(dx, dy, self.yaw);
  if (d < 1e-6) return i;
  const double s = std::min(speed, speed * d / std::max(slow_radius, 1e-6));
  i.move_x = static_cast<float>(dx / d * s);
  i.move_y = static_cast<float>(dy / d * s);
  return i;
}

// The simplest behavior whose commands are all honest: one per tick from intent().
class Mover : public Behavior {
 public:
  void act(const BehaviorContext& ctx, CommandSink& out) override { out.emit(intent(ctx)); }
  virtual Intent intent(const BehaviorContext& ctx) = 0;
};

std::unique_ptr<Behavior> make_wander();
std::unique_ptr<Behavior> make_charge();
std::unique_ptr<Behavior> make_waypoints();
std::unique_ptr<Behavior> make_idle();
std::unique_ptr<Behavior> make_nan();
std::unique_ptr<Behavior> make_flood();
std::unique_ptr<Behavior> make_hijack();
std::unique_ptr<Behavior> make_stale();

}  // namespace throng::client_sim::detail
