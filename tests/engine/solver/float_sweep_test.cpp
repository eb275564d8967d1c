// The scheduled (crowd) solve moves float displacements four pairs at a time along normals fixed
// at the start of the solve (solver/fast_pair_kernel.h). The level order keeps every body's pairs
// in their relative order, so in exact arithmetic it gives what the same method gives in the
// pairs' own order: here the two must agree to float rounding on a packed, overlapping crowd, and
// the four-lane path must give the scalar path's bits.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "solver/contact_solver.h"
#include "solver/fast_pair_kernel.h"
#include "solver/pair_projection.h"
#include "solver/pair_schedule.h"
#include "solver/solver_data.h"

namespace throng::detail {
namespace {

struct Crowd {
  SolverBodies bodies;
  std::vector<SolverPair> pairs;
};

// Bodies per square metre of the crowd, relative to one body per 0.38 m^2. Uniformly random
// positions at this density overlap by up to a radius and move ~1 m in one solve.
constexpr double kDensity = 0.6;

// n grounded spheres of radius 0.3-0.4 m at random in a square `offset` metres from the origin,
// and every pair closer than its radius sum, with random shares and some warm-start pushes (up to
// `warm_m`). Bodies 0 and 1 share one position: their pair needs the id-derived direction.
Crowd packed_crowd(std::size_t n, double offset, std::uint64_t seed, double warm_m = 0.05) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Crowd c;
  c.bodies.resize(n);
  const double side = std::sqrt(static_cast<double>(n) * 0.38 / kDensity);
  for (std::uint32_t i = 0; i < n; ++i) {
    c.bodies.x[i] = offset + side * unit(rng);
    c.bodies.y[i] = offset + side * unit(rng);
    c.bodies.r[i] = 0.3 + 0.1 * unit(rng);
    c.bodies.z[i] = 0.5;
    c.bodies.hh[i] = 0.0;
    c.bodies.grounded[i] = 1;
    c.bodies.plane_begin[i] = 0;
    c.bodies.plane_count[i] = 0;
    c.bodies.id[i] = i + 1;
  }
  c.bodies.x[1] = c.bodies.x[0];
  c.bodies.y[1] = c.bodies.y[0];
  for (std::uint32_t i = 0; i < n; ++i) {
    for (std::uint32_t j = i + 1; j < n; ++j) {
      const double dx = c.bodies.x[j] - c.bodies.x[i], dy = c.bodies.y[j] - c.bodies.y[i];
      const double rsum = c.bodies.r[i] + c.bodies.r[j];
      if (dx * dx + dy * dy >= rsum * rsum) continue;
      SolverPair p{};
      p.a = i;
      p.b = j;
      p.target = rsum;
      p.share_a = 0.1 + 0.8 * unit(rng);
      p.lambda = unit(rng) < 0.5 ? 0.0 : warm_m * unit(rng);  // some pairs warm-started
      c.pairs.push_back(p);
    }
  }
  return c;
}

// The fast pairs' method written out in double precision and the pairs' own order: each pair's
// normal and penetration taken once from the start positions, the warm start (cut to the fast
// cap) along the normals and each body's net move cut, then sweeps alternating in direction, each projection moving the two
// bodies along the normal by the change of the pair's clamped push. Returns the largest
// penetration over the smaller radius seen before a projection in the last sweep.
double fixed_normal_reference_solve(Crowd& c, int sweeps) {
  const std::size_t np = c.pairs.size();
  std::vector<double> nx(np), ny(np), pen0(np), ux(c.bodies.size(), 0.0), uy(c.bodies.size(), 0.0);
  for (std::size_t k = 0; k < np; ++k) {
    SolverPair& p = c.pairs[k];
    double dx = c.bodies.x[p.b] - c.bodies.x[p.a], dy = c.bodies.y[p.b] - c.bodies.y[p.a];
    const double dist = std::sqrt(dx * dx + dy * dy);
    if (dist > 1e-9 * p.target) {
      dx /= dist;
      dy /= dist;
    } else {
      coincident_direction(c.bodies.id[p.a], c.bodies.id[p.b], dx, dy);
    }
    nx[k] = dx;
    ny[k] = dy;
    pen0[k] = p.target - dist;
    p.lambda = std::min(p.lambda, fast_warm_cap(std::min(c.bodies.r[p.a], c.bodies.r[p.b])));
  }
  auto move = [&](std::size_t k, double step) {
    const SolverPair& p = c.pairs[k];
    const double move_a = step * p.share_a, move_b = step - move_a;
    ux[p.a] -= nx[k] * move_a; uy[p.a] -= ny[k] * move_a;
    ux[p.b] += nx[k] * move_b; uy[p.b] += ny[k] * move_b;
  };
  for (std::size_t k = 0; k < np; ++k) move(k, c.pairs[k].lambda);
  // Each body's net warm-start move is cut to kWarmStartMoveCapOverRadius of its radius.
  for (std::size_t i = 0; i < c.bodies.size(); ++i) {
    const double cap = kWarmStartMoveCapOverRadius * c.bodies.r[i];
    const double len = std::sqrt(ux[i] * ux[i] + uy[i] * uy[i]);
    if (len > cap) {
      ux[i] *= cap / len;
      uy[i] *= cap / len;
    }
  }
  double worst = 0.0;
  for (int it = 0; it < sweeps; ++it) {
    worst = 0.0;
    for (std::size_t j = 0; j < np; ++j) {
      const std::size_t k = it % 2 == 0 ? j : np - 1 - j;
      SolverPair& p = c.pairs[k];
      const double pen = pen0[k] - (nx[k] * (ux[p.b] - ux[p.a]) + ny[k] * (uy[p.b] - uy[p.a]));
      if (pen <= 0.0 && p.lambda == 0.0) continue;
      const double lambda = std::max(0.0, p.lambda + pen);
      move(k, lambda - p.lambda);
      p.lambda = lambda;
      if (pen > 0.0) worst = std::max(worst, pen / std::min(c.bodies.r[p.a], c.bodies.r[p.b]));
    }
  }
  for (std::size_t i = 0; i < c.bodies.size(); ++i) {
    c.bodies.x[i] += ux[i];
    c.bodies.y[i] += uy[i];
  }
  return worst;
}

// Exact shares throughout (conflict limit 0): the conflict share is a discrete rule (a pair whose
// depth is ~0 switches to it or not), and float and double rounding can decide it differently,
// after which both solves are equally valid but apart. With exact shares the scheduled solve (float
// displacements, four lanes, level order) and the double reference agree to float rounding. Warm
// pushes of up to 5 m (~14 r): those within 8 r are carried whole, the others are cut to it
// (fast_warm_cap), and both solves must cut the same ones.
TEST(FloatSweep, ScheduledSolveAgreesWithTheDoubleSolveToFloatRounding) {
  for (const double offset : {0.0, 10000.0}) {
    const Crowd start = packed_crowd(1500, offset, 11, 5.0);
    ASSERT_GT(start.pairs.size(), 1500u);
    const std::vector<SolverPlane> no_planes;

    Crowd exact = start;  // double positions, pair order
    const double worst_exact = fixed_normal_reference_solve(exact, 8);

    Crowd fast = start;  // float displacements, level order
    PairSchedule schedule;
    fast.bodies.displaced = true;
    std::fill(fast.bodies.u.begin(), fast.bodies.u.end(), 0.0f);
    build_pair_schedule(fast.bodies, fast.pairs, 0.0, schedule);
    schedule.calm_push_over_radius = 0.0f;  // every band in every sweep, as the reference does
    ASSERT_EQ(static_cast<std::size_t>(std::count_if(schedule.src.begin(), schedule.src.end(),
                                                     [](std::uint32_t k) { return k != PairSchedule::kNoPair; })),
              fast.pairs.size());
    apply_warm_start(fast.bodies, fast.pairs, no_planes, schedule, 0.0);
    const SolveResult rf = solve_contacts(fast.bodies, fast.pairs, no_planes, 8, 0, 0.0, 0.0, schedule, true);
    write_back_pair_schedule(schedule, fast.pairs);

    double worst = 0.0, moved = 0.0;
    for (std::uint32_t i = 0; i < start.bodies.size(); ++i) {
      worst = std::max({worst, std::fabs(fast.bodies.px(i) - exact.bodies.x[i]),
                        std::fabs(fast.bodies.py(i) - exact.bodies.y[i])});
      moved = std::max(moved, std::fabs(exact.bodies.x[i] - start.bodies.x[i]));
    }
    std::printf("offset %.0f m: %zu pairs, largest move %.4f m, largest float/double difference %.3g m\n", offset,
                start.pairs.size(), moved, worst);
    EXPECT_GT(moved, 0.5);  // the crowd really was pushed apart
    // Float keeps ~6e-8 of each displacement; eight sweeps over a jam amplify that, but not
    // beyond 1e-5 of the largest move (the measured difference is far below it: docs/engine.md).
    const double tolerance = 1e-5 * moved;
    EXPECT_LT(worst, tolerance);
    EXPECT_NEAR(rf.max_pen_over_radius, worst_exact, 1e-3);
    for (std::size_t k = 0; k < start.pairs.size(); ++k) {
      ASSERT_NEAR(fast.pairs[k].lambda, exact.pairs[k].lambda, tolerance) << "pair " << k;
    }
    // Both kinds of cap were in play, and the coincident pair moved its bodies apart.
    int carried = 0, cut = 0;
    for (const SolverPair& p : start.pairs) {
      const double r_min = std::min(start.bodies.r[p.a], start.bodies.r[p.b]);
      if (p.lambda > kWarmStartCapOverRadius * r_min) (fast_warm_cap(r_min) > p.lambda ? carried : cut) += 1;
    }
    EXPECT_GT(carried, 100);
    EXPECT_GT(cut, 100);
    EXPECT_GT(std::hypot(fast.bodies.px(1) - fast.bodies.px(0), fast.bodies.py(1) - fast.bodies.py(0)), 0.1);
  }
}

// A fast pair's start depth, read back from the schedule for push events (target - pen0), is the
// pair's depth at the start positions; the coincident pair's normal is the id-derived direction.
TEST(FloatSweep, ScheduleKeepsEachPairsStartDepthAndAFiniteNormal) {
  Crowd c = packed_crowd(1500, 10000.0, 3);
  c.bodies.displaced = true;
  std::fill(c.bodies.u.begin(), c.bodies.u.end(), 0.0f);
  PairSchedule s;
  build_pair_schedule(c.bodies, c.pairs, 0.25, s);
  std::size_t checked = 0;
  for (std::uint32_t f = 0; f < s.fast_size(); ++f) {
    ASSERT_TRUE(std::isfinite(s.nx[f]) && std::isfinite(s.ny[f]) && std::isfinite(s.pen0[f])) << "slot " << f;
    ASSERT_NEAR(std::hypot(s.nx[f], s.ny[f]), 1.0, 1e-6) << "slot " << f;
    if (s.src[f] == PairSchedule::kNoPair) continue;
    const SolverPair& p = c.pairs[s.src[f]];
    ASSERT_NEAR(fast_pair_start_depth(c.bodies, s, f), pair_depth(c.bodies, p), 1e-6) << "pair " << s.src[f];
    if (p.a == 0 && p.b == 1) {
      double nx, ny;
      coincident_direction(1, 2, nx, ny);
      EXPECT_FLOAT_EQ(s.nx[f], static_cast<float>(nx));
      EXPECT_FLOAT_EQ(s.ny[f], static_cast<float>(ny));
      EXPECT_NEAR(fast_pair_start_depth(c.bodies, s, f), p.target, 1e-6);
    }
    ++checked;
  }
  EXPECT_EQ(checked, c.pairs.size());
}

// The crowd set up for a scheduled solve (displacements zero) and its schedule, conflict limit 0.25.
PairSchedule start_scheduled_solve(Crowd& c) {
  c.bodies.displaced = true;
  std::fill(c.bodies.u.begin(), c.bodies.u.end(), 0.0f);
  PairSchedule s;
  build_pair_schedule(c.bodies, c.pairs, 0.25, s);
  return s;
}

// Warm start and sweeps, with conflict shares.
TEST(FloatSweep, FourLanePathGivesTheScalarBits) {
  Crowd c = packed_crowd(1500, 500.0, 5);
  PairSchedule simd = start_scheduled_solve(c);
  PairSchedule scalar = simd;
  SolverBodies scalar_bodies = c.bodies;
  const BodyPtrs bs(c.bodies), bp(scalar_bodies);
  for (const PairSchedule::Level& lv : simd.levels) {
    warm_start_fast_range(bs, simd, lv.fast_begin, lv.fast_end);
    for (std::uint32_t k = lv.fast_begin; k < lv.fast_end; ++k) warm_start_fast(bp, scalar, k);
  }
  ASSERT_EQ(c.bodies.u, scalar_bodies.u);
  for (int sweep = 0; sweep < 4; ++sweep) {
    for (const PairSchedule::Level& lv : simd.levels) {
      float moved4 = 0.0f, moved1 = 0.0f;
      const float w4 = project_fast_range(bs, simd, lv.fast_begin, lv.fast_end, moved4);
      float w1 = 0.0f;
      for (std::uint32_t k = lv.fast_begin; k < lv.fast_end; ++k) {
        w1 = std::max(w1, project_fast_pair(bp, scalar, k, moved1));
      }
      ASSERT_EQ(w4, w1);
      ASSERT_EQ(moved4, moved1);
    }
  }
  EXPECT_EQ(c.bodies.u, scalar_bodies.u);
  EXPECT_EQ(simd.lambda, scalar.lambda);
  EXPECT_EQ(simd.share_now, scalar.share_now);
}

// A band's levels in one span (forward and in reverse) give the level-by-level bits: padding
// keeps every four-pair group inside one level.
TEST(FloatSweep, BandSpansGiveTheLevelByLevelBits) {
  Crowd c = packed_crowd(3000, 0.0, 9);
  PairSchedule by_span = start_scheduled_solve(c);
  ASSERT_GE(by_span.band_count(), 2u);
  for (const PairSchedule::Level& lv : by_span.levels) ASSERT_EQ((lv.fast_end - lv.fast_begin) % 4, 0u);
  PairSchedule by_level = by_span;
  SolverBodies level_bodies = c.bodies;
  const BodyPtrs bs(c.bodies), bl(level_bodies);
  float moved_span = 0.0f, moved_level = 0.0f, worst_span = 0.0f, worst_level = 0.0f;
  for (int sweep = 0; sweep < 6; ++sweep) {
    const bool forward = sweep % 2 == 0;
    for (std::size_t i = 0; i < by_span.band_count(); ++i) {
      const std::size_t band = forward ? i : by_span.band_count() - 1 - i;
      const std::uint32_t l0 = by_span.band_level[band], l1 = by_span.band_level[band + 1];
      const std::uint32_t begin = by_span.levels[l0].fast_begin, end = by_span.levels[l1 - 1].fast_end;
      worst_span = std::max(worst_span, forward ? project_fast_span<false>(bs, by_span, begin, end, moved_span)
                                                : project_fast_span<true>(bs, by_span, begin, end, moved_span));
      for (std::uint32_t k = 0; k < l1 - l0; ++k) {
        const PairSchedule::Level& lv = by_level.levels[forward ? l0 + k : l1 - 1 - k];
        worst_level = std::max(worst_level, project_fast_range(bl, by_level, lv.fast_begin, lv.fast_end, moved_level));
      }
    }
  }
  EXPECT_GT(worst_level, 0.1f);  // a real jam
  EXPECT_EQ(c.bodies.u, level_bodies.u);
  EXPECT_EQ(by_span.lambda, by_level.lambda);
  EXPECT_EQ(worst_span, worst_level);
  EXPECT_EQ(moved_span, moved_level);
}

}  // namespace
}  // namespace throng::detail
