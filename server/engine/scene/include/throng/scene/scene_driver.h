#pragma once
// Gives every spawned body its desired velocity each tick, from its spawn group's behavior.
//
// This is the bench's (and later the bots') stand-in for AI: deliberately trivial and
// deterministic — bodies are visited in id order, velocities depend only on the body's position,
// and nothing is random — so two runs of a scene give the same input sequence to the World.
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "throng/core/object_id.h"
#include "throng/core/vec3.h"
#include "throng/scene/scene_def.h"

namespace throng {
class World;
}

namespace throng::scene {

// A Behavior with everything the driver needs precomputed (march direction as a unit vector).
struct ResolvedBehavior {
  BehaviorKind kind = BehaviorKind::idle;
  Vec2 target;
  Vec2 direction;  // unit, march only
  double speed_mps = 0.0;
};

// march-to-target takes its direction from the spawn shape's centre; path names the behavior in
// errors ("spawns[1].behaviour.target: must differ from the spawn shape's centre").
ResolvedBehavior resolve_behavior(const Behavior& b, const SpawnShape& shape, const std::string& path);

// Horizontal desired velocity (z = 0). seek_point: towards target at speed_mps, but never faster
// than distance / dt, so an unobstructed body lands on the target and then stands still instead
// of oscillating around it.
Vec3 desired_velocity(const ResolvedBehavior& b, Vec3 position, double dt_s);

class SceneDriver {
 public:
  struct Agent {
    ObjectId id;
    std::uint32_t behavior = 0;  // index into behaviors()
  };

  explicit SceneDriver(double dt_s);

  std::uint32_t add_behaviour(const ResolvedBehavior& b);
  void add_agent(ObjectId id, std::uint32_t behavior);  // kept sorted by id

  // Sets every agent's desired velocity, in id order. Idle agents get 0 each tick too, so a body
  // whose velocity was changed elsewhere is brought back under the scene's control.
  void apply(World& world) const;

  std::span<const Agent> agents() const { return agents_; }
  std::span<const ResolvedBehavior> behaviors() const { return behaviours_; }
  double dt_s() const { return dt_s_; }

 private:
  double dt_s_;
  std::vector<ResolvedBehavior> behaviours_;
  std::vector<Agent> agents_;
};

}  // namespace throng::scene
