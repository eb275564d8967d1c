#include "throng/scene/scene_driver.h"

#include <algorithm>
#include <cmath>

#include "throng/scene/scene_error.h"
#include "throng/scene/spawn.h"
#include "throng/world/world.h"

namespace throng::scene {

ResolvedBehavior resolve_behavior(const Behavior& b, const SpawnShape& shape, const std::string& path) {
  ResolvedBehavior r;
  r.kind = b.kind;
  r.target = b.target;
  r.speed_mps = b.speed_mps;
  if (b.kind == BehaviorKind::march) {
    Vec2 d = b.direction;
    if (b.has_target) {
      const Vec2 c = shape_centre(shape);
      d = {b.target.x - c.x, b.target.y - c.y};
    }
    const double len = std::sqrt(d.x * d.x + d.y * d.y);
    if (!(len > 0.0))
      throw SceneError(path + (b.has_target ? ".target" : ".direction"),
                       b.has_target ? "must differ from the spawn shape's centre" : "must not be zero");
    r.direction = {d.x / len, d.y / len};
  }
  return r;
}

Vec3 desired_velocity(const ResolvedBehavior& b, Vec3 position, double dt_s) {
  switch (b.kind) {
    case BehaviorKind::idle:
      return {};
    case BehaviorKind::march:
      return {b.direction.x * b.speed_mps, b.direction.y * b.speed_mps, 0.0};
    case BehaviorKind::seek_point: {
      const double dx = b.target.x - position.x;
      const double dy = b.target.y - position.y;
      const double dist = std::sqrt(dx * dx + dy * dy);
      if (!(dist > 0.0)) return {};  // on target (or NaN position: stand still rather than spread NaN)
      const double speed = std::min(b.speed_mps, dist / dt_s);
      return {dx * (speed / dist), dy * (speed / dist), 0.0};
    }
  }
  return {};
}

SceneDriver::SceneDriver(double dt_s) : dt_s_(dt_s) {}

std::uint32_t SceneDriver::add_behaviour(const ResolvedBehavior& b) {
  behaviours_.push_back(b);
  return static_cast<std::uint32_t>(behaviours_.size() - 1);
}

void SceneDriver::add_agent(ObjectId id, std::uint32_t behavior) {
  const Agent a{id, behavior};
  // Bodies are normally created in increasing id order, so this is an append.
  auto it = std::upper_bound(agents_.begin(), agents_.end(), a, [](const Agent& l, const Agent& r) { return l.id < r.id; });
  agents_.insert(it, a);
}

void SceneDriver::apply(World& world) const {
  for (const Agent& a : agents_)
    world.set_desired_velocity(a.id, desired_velocity(behaviours_[a.behavior], world.position(a.id), dt_s_));
}

}  // namespace throng::scene
