#pragma once
// World's private state. Split from world.h so the public header stays free of FCL, the policy's
// internals and the solver's scratch arrays.
#include <algorithm>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "broadphase/hier_grid.h"
#include "broadphase/point_grid.h"
#include "solver/pair_schedule.h"
#include "solver/solver_data.h"
#include "throng/core/worker_pool.h"
#include "throng/core/byte_io.h"
#include "throng/geometry/static_scenery.h"
#include "throng/params/param_table.h"
#include "throng/params/push_policy.h"
#include "throng/world/world.h"
#include "world/body_store.h"
#include "world/world_state.h"

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
  // The same cells as a bitmap over their bounding box (cells bx0.., by0.., bw x bh), so that
  // near_scenery, asked for every body twice a tick, is one load instead of a binary search;
  // empty when that box would be too large (scenery far apart), and then the keys are searched.
  std::vector<std::uint8_t> scenery_bitmap;
  std::int64_t scenery_bx0 = 0, scenery_by0 = 0, scenery_bw = 0, scenery_bh = 0;
  double max_body_reach_m = 0.0;
  double scenery_reach_m = 0.0;  // reach the scenery cells were built for

  // Movable bodies.
  detail::BodyStore bodies;
  // Per-body parameter records, read through params_of: a re-sort leaves them in the order before
  // it (params_order maps dense index -> record) until a tick without search work settles them.
  std::vector<params::ObjectParams> body_params;
  std::vector<std::uint32_t> params_order;  // empty: body_params is in dense order
  params::ObjectParams& params_of(std::size_t d) { return body_params[params_order.empty() ? d : params_order[d]]; }
  const params::ObjectParams& params_of(std::size_t d) const {
    return body_params[params_order.empty() ? d : params_order[d]];
  }
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
  std::unique_ptr<WorkerPool> pool;  // WorldSettings::threads > 1
  // fn(begin, end) over [0, n) in fixed ranges of kPerTask, on the pool's threads if there is one:
  // for passes in which every item (a body, a pair list's entry) is on its own (the same bits
  // however the ranges are shared out: the ranges do not depend on the thread count).
  static constexpr std::size_t kBodiesPerTask = 16384;
  static constexpr std::size_t kEntriesPerTask = 16384;
  template <std::size_t kPerTask, class Fn>
  void for_fixed_ranges(std::size_t n, Fn&& fn) {
    const auto tasks = static_cast<std::uint32_t>((n + kPerTask - 1) / kPerTask);
    auto task = [&](std::uint32_t t) { fn(t * kPerTask, std::min(n, (t + 1) * kPerTask)); };
    run_tasks(pool.get(), tasks, task);
  }
  template <class Fn>
  void for_body_ranges(std::size_t n, Fn&& fn) { for_fixed_ranges<kBodiesPerTask>(n, fn); }
  template <class Fn>
  void for_entry_ranges(std::size_t m, Fn&& fn) { for_fixed_ranges<kEntriesPerTask>(m, fn); }
  std::size_t warm_pairs = 0;  // pairs of this tick that start with a warm-start push
  // The second solve of a tick (World::step), and whether the first was the scheduled one.
  bool second_solve = false;
  bool first_solve_scheduled = false;
  std::vector<detail::SolverPlane> planes;
  std::vector<geom::SceneryContact> contacts;
  // This tick's push events: the first event_count (the buffer keeps its high-water size).
  std::vector<PushEvent> events;
  std::size_t event_count = 0;
  bool push_events_off = false;  // World::set_push_events_recorded(false)
  bool records_push_events() const { return settings.record_push_events && !push_events_off; }
  std::vector<double> start_x, start_y, start_z;
  std::vector<double> moved_x, moved_y;  // after the move phase, before the solve
  std::vector<double> median_scratch;
  // cell0_size() uses the median of all radii; radii change only when bodies are created, destroyed
  // or restored, so it is recomputed only then (the nth_element cost ~0.1 ms a tick at 20,000).
  bool cell0_dirty = true;
  double median_radius_m = 0.5;
  std::vector<std::uint32_t> sgroup, smask;  // collision filter in solver order
  // What the fine grid's search reads of the solver's bodies.
  detail::GridBodyView solver_view() const {
    return {sb.x.data(), sb.y.data(), sb.z.data(), sb.r.data(), sb.hh.data(), sgroup.data(), smask.data()};
  }
  // The next pair list's fine grid and the columns its search reads, in its order, built while the
  // kept list still serves a step (search_ahead_begin); they become `grid`, sb's and sgroup/smask's
  // when the kept list ends (search_ahead_finish), by swapping.
  struct AheadGrid {
    detail::HierGrid grid;
    std::vector<double> x, y, z, r, hh;
    std::vector<std::uint32_t> group, mask;
  } next_grid;

  // Pile relief (pile_relief.cpp).
  static constexpr std::uint32_t kPileThreshold = 32;
  struct PileEntry {
    double dist2;
    std::uint32_t id;
    std::uint32_t dense;
  };
  std::vector<PileEntry> pile;
  double grid_cell0 = 1.0;

  // Solver index -> dense index: the broadphase order of the last search (identity once
  // reorder_dense has put the dense arrays into that order).
  std::vector<std::uint32_t> solver_order;
  // World::last_reorder: the permutation of the last step's re-sort, empty when it made none.
  std::vector<std::uint32_t> last_reorder;
  // This tick's pairs are the kept list's taken entries (list.of_pair), not yet in `pairs`.
  bool pairs_in_list = false;

  // The pair list kept across ticks (world_pair_list.cpp, WorldSettings::pair_list_skin_m).
  struct PairList {
    // A list kept for fewer ticks than this before motion outran its skin is followed by `backoff`
    // ticks of searching with the margin alone, kCooldownTicks after a list that paid and twice
    // as many after each one in a row that did not, up to kMaxCooldownTicks (the list's search
    // costs more than a plain search; `mixed`, whose cavalry and giants shove the crowd, kept its
    // lists ~1 tick: 40% slower searching one every other tick, still 3% (19% at p95) with a fixed
    // 8-tick cooldown, within 3% at the median with the doubling).
    static constexpr std::uint32_t kMinKeptTicks = 2;
    static constexpr std::uint32_t kCooldownTicks = detail::kPairListCooldownTicks;
    static constexpr std::uint32_t kMaxCooldownTicks = detail::kPairListMaxCooldownTicks;
    std::uint32_t backoff = kCooldownTicks;
    bool valid = false;  // kept: nothing but motion changed since its search
    std::uint32_t kept_ticks = 0;  // ticks the current (or last) list was kept after its search
    std::uint32_t cooldown = 0;    // ticks still to search without a list
    std::vector<std::uint32_t> a, b;   // solver indices, in the order of the fine grid's search
    std::vector<double> target;        // SolverPair::target (heights and radii do not change)
    // The margin's reach r_a + r_b + margin, or 0 for a pair of grounded bodies whose heights keep
    // it apart (heights and radii do not change while the list is kept).
    std::vector<double> reach;
    std::vector<double> share;         // SolverPair::share_a, recomputed when a resistance changed
    bool shares_stale = false;         // a resistance changed since the shares were computed
    std::vector<double> resistance;    // the bodies' resistances in solver order (share scratch)
    std::vector<float> lambda;         // last tick's push (0: none kept)
    // Per entry, what its schedule slot holds apart from the push, computed once per search (and
    // the share and warm-start cap per refresh, refresh_list_shares) with the schedule's own
    // arithmetic (pair_schedule_build.h): one 32-byte read per pair when the schedule is built
    // instead of six scattered ones.
    struct Slot {
      std::uint32_t a, b;
      float target, share, inv_r_min;
      double warm_cap;  // fast_warm_cap(smaller radius), set by refresh_list_shares
    };
    std::vector<Slot> slot;
    std::vector<double> x, y, z;       // positions of the search, solver order
    std::vector<std::uint32_t> of_pair;  // this tick's pair k -> list entry
    // A restored world searches again at the saved positions (dense order) before its next step.
    bool restore_pending = false;
    std::vector<double> restored_x, restored_y, restored_z;
    // Searched ahead (World::Impl::search_ahead, at the end of the last step): restored_x, restored_y
    // hold where that step's final positions and velocities place the bodies a little ahead
    // (restored_z their heights as they were), the fine grid and the solver's bodies are built
    // there, and `found` holds the first part of the search; the next step's search there only
    // finishes it.
    bool searched_ahead = false;
    std::uint32_t ahead_capped = 0;  // bodies the parts scanned so far capped
    bool scan_complete = false;      // search_ahead_finish scanned it all: the next step sets it up
    // Begun a step earlier (search_ahead_begin): the step that forecast the kept list outrun at the
    // step after next began the next list's search on a grid and columns of its own (`next_grid`), so
    // that the kept list still serves the next step; the next step's end finishes the scan
    // (search_ahead_finish) and records the list as above. ahead_begun is what a checkpoint and
    // the state hash hold of it: ahead_x, ahead_y, ahead_z (dense order) follow from the bodies'
    // positions and velocities at the step's end, and a restored world computes them there and
    // builds the grid when it finishes (ahead_built false).
    bool ahead_begun = false;
    bool ahead_built = false;  // the grid is built at ahead_x... and its first part scanned
    std::vector<double> ahead_x, ahead_y, ahead_z;
    // This step's forecast of the next step's check: the two largest displacements since the list's
    // search if every body went on at its last tick's velocity, summed (0 if the step checked none).
    double moved_next = 0.0;
    double moved_next2 = 0.0;  // the same for the check of the step after next
    bool fresh = false;  // searched this tick: the pushes are still to be looked up in the cache
    bool all_fast = false;  // every entry is between grounded bodies (no scenery: no planes either)
    std::size_t live = 0;   // entries taken this tick: of_pair[0, live)
    std::vector<detail::CandidatePair> found;  // search scratch
    // moved_within_skin: each range's two largest squared displacements, then its two largest forecasts
    std::vector<double> range_top;
    std::vector<std::uint32_t> range_taken, range_warm;  // take_list_pairs: per range of entries
    // Anything but motion changed a pair: no list is kept, and a restored world does not search
    // the saved one again either (the saved world dropped it too).
    void drop() {
      valid = false;
      restore_pending = false;
      searched_ahead = false;
      scan_complete = false;
      ahead_begun = false;
      ahead_built = false;
    }
    // The kept list ends to make way for one searched ahead (search_ahead, search_ahead_finish), as
    // find_pairs ends a list that paid and that motion outran; the next list is recorded as a
    // restored world's.
    void end_for_next() {
      backoff = kCooldownTicks;
      valid = false;
      kept_ticks = 0;
      restore_pending = true;
    }
    // A list that did not pay: the next `backoff` ticks search without one, and the next such
    // cooldown is twice as long.
    void back_off() {
      cooldown = backoff;
      backoff = std::min(2 * backoff, kMaxCooldownTicks);
    }
  } list;
  // What a checkpoint and the state hash hold of the pair list: nothing, the kept list's search
  // positions, or the restored ones a world not stepped since its restore will search again.
  enum class ListRecord { kNone, kKept, kPending };
  ListRecord list_record() const;
  // The byte a checkpoint and the state hash hold for it: 0 none, 1 kept (or to be searched again),
  // 2 kept and the next list's search begun in three parts (list.ahead_begun).
  std::uint8_t list_record_byte() const {
    return list_record() == ListRecord::kNone ? 0 : list.ahead_begun ? 2 : 1;
  }

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
  void find_pairs();
  void build_pairs();
  bool fine_grid(const double* x, const double* y, const double* z, bool allow_relief);
  void search_candidates();
  void setup_pairs();
  double pair_target(std::uint32_t a, std::uint32_t b) const;
  float warm_push(std::uint32_t a, std::uint32_t b) const;
  bool pair_list_eligible() const;
  // ahead: search_ahead has begun this search (at x, y, z, the restored positions).
  bool search_pair_list(const double* x, const double* y, const double* z, bool ahead);
  double pair_list_skin();
  template <bool kFresh>
  void take_list_pairs();
  void materialize_list_pairs();
  void refresh_list_shares();
  void gather_list_resistances();
  void set_list_share(std::size_t e);
  void set_up_entries(std::size_t begin, std::size_t end, double margin);
  void schedule_list_pairs(double conflict);
  void pairs_from_list(bool gathered);  // gathered: sb already holds the bodies' positions
  bool moved_within_skin(bool restored);
  // ticks: 1 forecasts the next step's check, 2 the check of the step after.
  bool search_ahead_due(int ticks);
  bool reorder_due(bool searching_ahead) const;
  bool surely_no_search_work(bool searching_ahead) const;
  void search_ahead();
  void search_ahead_begin();
  void predict_begun_ahead();  // list.ahead_x... for a search_ahead_begin at this state
  void search_ahead_finish();
  void predict_ahead(double lead_ticks, std::vector<double>& x, std::vector<double>& y, std::vector<double>& z);
  void build_ahead();
  bool relieve_piles();
  void build_scenery_planes();
  // apply_warm_start: false for the second solve of a tick, whose bodies already carry the pushes.
  void solve(bool apply_warm_start);
  // Whether the solve moved any body further than the contact margin from where the tick searched.
  bool moved_past_margin() const;
  void verify_scenery_after_solve();
  void store_warm_start_and_events();
  void finish_tick();
  void reorder_dense();
  // Puts body_params into dense order (no-op when it is); no allocation once params_scratch has
  // reached the body count.
  void settle_params();
  void size_reorder_scratch();

  // checkpoints (world_checkpoint.cpp)
  std::uint64_t config_hash() const;
  void save_state(ByteWriter& w) const;
  void apply_state(detail::WorldState&& st);  // checks against this world, then commits

  // helpers
  void rebuild_scenery_cells(double reach);
  inline bool near_scenery(double x, double y) const;  // defined (inline) in world_scenery.cpp, its only user
  double cell0_size(double search_margin);
  double pair_share(std::uint32_t dense_a, std::uint32_t dense_b, double nx, double ny) const;
};

}  // namespace throng
