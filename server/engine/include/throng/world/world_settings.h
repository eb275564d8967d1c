#pragma once
// Settings of a World, with units, defaults and valid ranges. validate() throws
// std::invalid_argument naming the field, so a bad scene file or CLI flag fails loudly at load time
// instead of producing NaNs mid-match.
#include <cstdint>

namespace throng {

struct WorldSettings {
  double dt_s = 1.0 / 60.0;              // fixed tick length [1e-4, 1]
  std::uint32_t iterations = 8;          // solver iteration budget per tick [1, 256]
  // Sweeps the solve may add to `iterations` while its last sweep met a pair deeper than a tenth of
  // the smaller radius (kDeepPairOverRadius, solver/pair_schedule.h). Why: a jam pressed against a
  // fixed body needs its pressure carried through many bodies to the fixed one, and at full speed
  // into the jam (blocked_motion_carry 0) `iterations` sweeps left single pairs a quarter of a
  // radius deep near posts and pillars; more sweeps everywhere would cost every crowd, while deep
  // pairs are rare elsewhere (a packed crush adds about a tenth of a sweep a tick on average).
  // Bounds the solve at iterations + extra_iterations sweeps. 0 = off. [0, 256]
  std::uint32_t extra_iterations = 16;
  // Pairs closer than r_a + r_b + margin are kept as contact candidates for the whole tick, so that
  // contacts created by pushes during the iterations are still seen. [0, 10] m
  double contact_margin_m = 0.05;
  // Pair list skin (a Verlet list): in a world without fixed scenery whose shares need only the two
  // resistances, with warm start on, the candidate pairs are searched within r_a + r_b + margin +
  // skin (the skin capped at the finest grid cell plus the margin) and the list is
  // kept across ticks until two bodies together have moved more than the skin since the search.
  // Each tick takes from it the pairs a search with the margin would find (every one of them is in
  // it, see world_pair_list.cpp), with last tick's pushes, in the order of that search. 0 = search
  // every tick. 0.3 since the crowd solve carries a jam's pressure (fast_pair_kernel.h): its core
  // shuffles a little more, so a thinner skin is outrun sooner, and a thicker one carries more
  // pairs and did worse in the worst case over twelve crowds (docs/design/solver.md).
  // [0, 1] m
  double pair_list_skin_m = 0.3;
  // Early exit: stop iterating once no pair penetrates deeper than this fraction of the smaller
  // radius. 0 = always use the full budget. [0, 1]
  double converged_pen_over_radius = 1e-4;
  // Fill push_events() every tick (the publisher, log and viewer read them). Benchmarks may turn it
  // off to measure the solver alone.
  bool record_push_events = true;
  // Reuse last tick's per-pair push (warm starting). Off only for experiments/benchmarks; off, every
  // solve also runs in the pairs' own order on double positions (the crowd solve is chosen by how
  // many pairs start warm, see solver/contact_solver.h).
  bool warm_start = true;
  // Blocked-motion warm start: a body that was pushed back against its own step last tick starts
  // this tick with that much less step (times this factor), so a jammed crowd does not re-create
  // the whole jam's overlap every tick. Only ever shortens a body's own step, never pushes it
  // sideways or backwards; a body released from a jam regains full speed within a few ticks
  // (the remaining shortening decays by this factor per tick). 0 = off. [0, 0.99]
  double blocked_motion_carry = 0.9;
  // Conflict share limit (ratio mode only): a pair's first push in a tick uses its exact share
  // (the patent's ratio); any later push of the same pair in that tick — the pair was driven
  // together again by a third body — uses the share clamped into [limit, 1 - limit], and so does a
  // pair that starts the tick held together by its neighbours (a jam's pressure carried from last
  // tick). Without it a light body caught between a heavy body and a jam is only ever moved
  // itself, and Gauss-Seidel flips it between the two; with it the jam pushes back on the heavy
  // body. 0 = off. [0, 0.5]
  double conflict_share_limit = 0.35;
  // Cap on neighbour candidates examined per body and tick. A normal crowd never reaches it; it is
  // what keeps the cost linear when thousands of bodies stand in one cell. [4, 4096]
  std::uint32_t max_candidates_per_body = 48;
  // Smallest broadphase cell edge. 0 = derive from the bodies (2 * (median radius + margin)). [0, 1000] m
  double cell_size_m = 0.0;
  // Radius of the neighbourhood counted for group morale, and how many ticks one full morale
  // refresh is spread over (1/period of the bodies are recounted each tick). [0.1, 1000] m, [1, 3600]
  double morale_radius_m = 5.0;
  std::uint32_t morale_refresh_ticks = 15;
  // Threads that sweep the crowd solve, the caller's included. The state is the same bits for any
  // number (the sweep's order does not depend on it), so this is the machine's choice, not the
  // match's: no part of a scene file, a checkpoint or the state hash. [1, 64]
  std::uint32_t threads = 1;

  void validate() const;
};

}  // namespace throng
