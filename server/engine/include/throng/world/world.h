#pragma once
// The authoritative world: movable characters (kinematic upright capsules), fixed scenery, the
// parameter table and the push policy, advanced one fixed tick at a time.
//
// Everything that changes the world between ticks goes through the setters below; they validate
// their input (throwing std::invalid_argument with a clear message and changing nothing) and are
// the single place the match log will record inputs from. step() is deterministic: the same
// sequence of calls on the same binary gives a bit-identical state_hash() every tick.
#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "throng/core/object_id.h"
#include "throng/core/vec3.h"
#include "throng/world/body_def.h"
#include "throng/world/push_event.h"
#include "throng/world/step_stats.h"
#include "throng/world/world_settings.h"

namespace throng::params {
class ParamTable;
class PushPolicy;
class GroupTable;
struct ObjectParams;
enum class Param : std::uint8_t;
}  // namespace throng::params

namespace throng {

class ByteWriter;
class ByteReader;
namespace detail {
struct WorldProbe;  // read access to the internals, for the engine's own tests
}

class World {
 public:
  World(const WorldSettings& settings, const params::ParamTable& table, const params::PushPolicy& policy);
  ~World();
  World(World&&) noexcept;
  World& operator=(World&&) noexcept;
  World(const World&) = delete;
  World& operator=(const World&) = delete;

  // --- scenery (fixed bodies; never move) -----------------------------------------------------
  ObjectId add_fixed_box(Vec3 centre, Vec3 half_extents_m, double yaw_rad, const std::string& archetype = "wall");
  ObjectId add_fixed_cylinder(Vec3 centre, double radius_m, double half_height_m, const std::string& archetype = "wall");
  ObjectId add_fixed_mesh(std::vector<Vec3> vertices, std::vector<std::array<std::uint32_t, 3>> triangles,
                          const std::string& archetype = "wall");

  // --- characters ------------------------------------------------------------------------------
  ObjectId create_body(const BodyDef& def);
  void destroy_body(ObjectId id);
  bool is_body(ObjectId id) const;
  bool is_fixed(ObjectId id) const;

  // --- inputs of the tick ------------------------------------------------------------------------
  void set_desired_velocity(ObjectId id, Vec3 velocity_mps);
  void set_position(ObjectId id, Vec3 position);  // teleport (spawn points, ledges, tests)
  void set_grounded(ObjectId id, bool grounded);
  void set_param(ObjectId id, params::Param param, double value);
  void set_policy(const params::PushPolicy& policy);
  void set_group_base_morale(std::uint32_t group_id, double morale);
  void set_cameras(std::span<const Vec3> camera_positions);
  // Whether steps record push events (push_events()), as WorldSettings::record_push_events says
  // unless turned off here. A machine-side switch, like WorldSettings::threads: the state does not
  // depend on it (events steer nothing), so it is not in checkpoints or the config hash, and a
  // re-simulation that reads no events turns it off (recording them is about a twentieth of a
  // battle's step). Turning it off also empties push_events().
  void set_push_events_recorded(bool on);
  void set_iterations(std::uint32_t iterations);

  // --- the tick ---------------------------------------------------------------------------------
  const StepStats& step();

  // --- read access ------------------------------------------------------------------------------
  std::uint64_t tick() const;
  std::uint64_t state_hash() const;
  std::size_t body_count() const;
  // Dense views in the world's internal order. The order changes when bodies are created or
  // destroyed AND at most once every 16 ticks inside step() (spatial re-sort for cache locality,
  // published by last_reorder()), so never keep per-body arrays in dense order across a step
  // without remapping; id_at() maps a dense index back to the id.
  std::span<const double> pos_x() const;
  std::span<const double> pos_y() const;
  std::span<const double> pos_z() const;
  std::span<const double> radius() const;
  std::span<const double> half_height() const;
  ObjectId id_at(std::size_t dense_index) const;
  // The dense index of body `id` now, or nullopt when id is not a body of this world.
  std::optional<std::size_t> dense_index(ObjectId id) const;
  // The re-sort the last step() made: reorder[new dense index] = old dense index, or empty when it
  // made none (a re-sort may also leave the order as it was). Callers that keep per-body arrays in dense order permute them with it after
  // each step instead of comparing ids. Only step() re-sorts on its own; create_body,
  // destroy_body and restore_state change the order at the caller's request (use id_at then), and
  // they empty this.
  std::span<const std::uint32_t> last_reorder() const;
  Vec3 position(ObjectId id) const;
  Vec3 velocity(ObjectId id) const;  // actual velocity over the last tick
  const params::ObjectParams& params(ObjectId id) const;
  const params::PushPolicy& policy() const;
  const params::GroupTable& groups() const;
  const WorldSettings& settings() const;
  std::span<const PushEvent> push_events() const;
  // --- checkpoints (layout: server/engine/src/world/CHECKPOINT.md) ---------------------------------
  // Everything that influences future steps, in the current dense order. A world restored from
  // it (built from the same settings and scenery) steps bit-identically to the one it was taken
  // from. save_state(vector) clears `out` first and reuses its capacity (a warm buffer does not
  // allocate); the ByteWriter form appends one world section. Const: safe beside other readers.
  void save_state(std::vector<std::uint8_t>& out) const;
  void save_state(ByteWriter& out) const;
  // Throws CheckpointError (core/byte_io.h) for truncated or malformed bytes, another version or
  // a world with other settings / scenery; the world is unchanged then. push_events() and the
  // last StepStats are empty afterwards (they describe a step, not the state).
  void restore_state(std::span<const std::uint8_t> bytes);  // exactly one world section
  // The same, with a check of the bodies the section holds (their ids, in its dense order) that
  // runs once it has decoded and before anything changes: it may throw CheckpointError (a match
  // checks that its NPC AI's state names exactly these bodies).
  void restore_state(std::span<const std::uint8_t> bytes,
                     const std::function<void(std::span<const ObjectId> body_ids)>& check_bodies);
  void restore_state(ByteReader& in);                       // reads one section, leaves the rest

  // Fixed scenery access for metrics and tools (penetration of a capsule into scenery).
  double scenery_max_penetration(std::size_t dense_index) const;

 private:
  friend struct detail::WorldProbe;
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace throng
