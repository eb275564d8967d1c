#pragma once
// World's private state. Split from world.h so the public header stays free of FCL, the policy's
// internals and the solver's scratch arrays.
#include <cstdint>
#include <string>
#include <vector>

#include "broadphase/hier_grid.h"
#include "broadphase/point_grid.h"
#include "solver/pair_schedule.h"
#include "solver/solver_data.h"
#include "throng/core/byte_io.h"
#include "throng/geometry/static_scenery.h"
#include "throng/params/param_table.h"
#include "throng/params/push_policy.h"
#include "throng/world/world.h"
#include "world/body_store.h"

namespace throng::detail {
struct WorldState;
}

namespace throng {

struct World::Impl {
  enum class SlotKind : std::uint8_t { kFree, kBody, kFixed };
  struct Slot {
    std::uint32_t generation = 0;
    SlotKind kind = SlotKind::kFree;
    std::uint32_t ref = 0;  // dense body index or fixed shape index
  };

  WorldSettings settings;
  params::ParamTable table;
  params::PushPolicy policy;

  // Ids: one slot table for bodies and fixed objects, so an id names exactly one thing.
  std::vector<Slot> slots;
  std::vector<std::uint32_t> free_slots;  // LIFO: deterministic reuse

  // Fixed scenery: FCL shapes + per-shape id and parameters (softness).
  geom::StaticScenery scenery;
  std::vector<ObjectId> fixed_ids;
  std::vector<params::ObjectParams> fixed_params;
  bool scenery_dirty = false;
  double scenery_cell_m = 2.0;
  std::vector<std::uint64_t> scenery_cells;  // sorted keys of cells near any fixed shape
  double max_body_reach_m = 0.0;
  double scenery_reach_m = 0.0;  // reach the scenery cells were built for

  // Movable bodies.
  detail::BodyStore bodies;
  std::vector<params::ObjectParams> body_params;
  std::vector<Vec3> cameras;
  std::vector<std::array<double, 3>> camera_xyz;
  bool all_coefficients_dirty = true;

  // Groups (morale is dynamic, so the world owns its copy of the table's groups).
  params::GroupTable groups;
  std::vector<std::uint32_t> morale_allies, morale_enemies;  // counts of the current period
  detail::PointGrid morale_index;

  // Which dynamic parameters the current policy reads (recomputed when the policy changes).
  struct DynamicUse {
    bool speed_facing = false, height = false, camera = false, morale = false;
    bool slow_share = false;  // pair shares need more than the two resistances
    std::uint64_t policy_version = ~std::uint64_t{0};
  } dyn;
  std::uint64_t policy_version = 0;

  // Tick scratch, reused.
  detail::HierGrid grid;
  detail::SolverBodies sb;
  std::vector<detail::CandidatePair> candidates;
  std::vector<detail::SolverPair> pairs;
  detail::PairSchedule pair_schedule;
  std::size_t warm_pairs = 0;  // pairs of this tick that start with a warm-start push
  std::vector<detail::SolverPlane> planes;
  std::vector<geom::SceneryContact> contacts;
  std::vector<PushEvent> events;
  std::vector<double> start_x, start_y, start_z;
  std::vector<double> moved_x, moved_y;  // after the move phase, before the solve
  std::vector<double> median_scratch;
  // cell0_size() is a median over all radii; radii change only when bodies are created, destroyed
  // or restored, so it is recomputed only then (the nth_element cost ~0.1 ms a tick at 20,000).
  bool cell0_dirty = true;
  double cell0_cached_m = 1.0;
  std::vector<std::uint32_t> sgroup, smask;  // collision filter in solver order

  // Pile relief (pile_relief.cpp).
  static constexpr std::uint32_t kPileThreshold = 32;
  struct PileEntry {
    double dist2;
    std::uint32_t id;
    std::uint32_t dense;
  };
  std::vector<PileEntry> pile;
  double grid_cell0 = 1.0;

  // Spatial reordering of the dense arrays (world_step.cpp).
  static constexpr std::uint64_t kReorderPeriodTicks = 16;
  detail::BodyStore body_scratch;
  std::vector<params::ObjectParams> params_scratch;

  std::uint64_t tick = 0;
  StepStats stats;

  Impl(const WorldSettings& s, const params::ParamTable& t, const params::PushPolicy& p)
      : settings(s), table(t), policy(p), groups(t.groups()) {}

  // ids
  ObjectId allocate_slot(SlotKind kind, std::uint32_t ref);
  const Slot* find(ObjectId id) const;
  std::uint32_t body_index(ObjectId id, const char* what) const;  // throws on unknown id
  ObjectId add_fixed(std::uint32_t shape_index, const std::string& archetype);

  // phases of step()
  void update_dynamic_params();
  void refresh_dynamic_use();
  void update_morale_counts();
  void refresh_coefficients();
  void move_bodies();
  void build_pairs();
  bool relieve_piles();
  void build_scenery_planes();
  void solve();
  void verify_scenery_after_solve();
  void store_warm_start_and_events();
  void finish_tick();
  void reorder_dense();

  // checkpoints (world_checkpoint.cpp)
  std::uint64_t config_hash() const;
  void save_state(ByteWriter& w) const;
  void apply_state(detail::WorldState&& st);  // checks against this world, then commits

  // helpers
  void rebuild_scenery_cells(double reach);
  bool near_scenery(double x, double y) const;
  double cell0_size();
  double pair_share(std::uint32_t dense_a, std::uint32_t dense_b, double nx, double ny) const;
};

}  // namespace throng
