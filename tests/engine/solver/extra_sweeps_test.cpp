// The solve adds sweeps (WorldSettings::extra_iterations) only while its last sweep met a pair
// deeper than kDeepPairOverRadius: a row of bodies squeezed together needs more sweeps than the
// budget to spread, and gets them; a row that is barely touching gets none, and its bits are those
// of a solve without extra sweeps.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <vector>

#include "solver/contact_solver.h"
#include "solver/pair_schedule.h"
#include "solver/solver_data.h"

namespace throng::detail {
namespace {

constexpr double kR = 0.5;

// `n` grounded bodies on the x axis, each `overlap` (over the radius) into the next, with the pairs
// of neighbours in order (an unscheduled solve sweeps them in that order, alternating).
struct Row {
  SolverBodies bodies;
  std::vector<SolverPair> pairs;
};

Row squeezed_row(std::uint32_t n, double overlap) {
  Row row;
  row.bodies.resize(n);
  for (std::uint32_t i = 0; i < n; ++i) {
    row.bodies.x[i] = i * (2.0 - overlap) * kR;
    row.bodies.y[i] = 0.0;
    row.bodies.z[i] = 0.5;
    row.bodies.r[i] = kR;
    row.bodies.hh[i] = 0.0;
    row.bodies.grounded[i] = 1;
    row.bodies.plane_begin[i] = 0;
    row.bodies.plane_count[i] = 0;
    row.bodies.id[i] = i + 1;
  }
  for (std::uint32_t i = 0; i + 1 < n; ++i) {
    SolverPair p{};
    p.a = i;
    p.b = i + 1;
    p.target = 2.0 * kR;
    p.share_a = 0.5;
    row.pairs.push_back(p);
  }
  return row;
}

double deepest_over_radius(const SolverBodies& b) {
  double worst = 0.0;
  for (std::size_t i = 0; i + 1 < b.size(); ++i) worst = std::max(worst, (2.0 * kR - (b.x[i + 1] - b.x[i])) / kR);
  return worst;
}

SolveResult solve(Row& row, std::uint32_t extra) {
  PairSchedule unused;
  const std::vector<SolverPlane> no_planes;
  return solve_contacts(row.bodies, row.pairs, no_planes, 8, extra, 0.0, 0.25, unused, false);
}

TEST(ExtraSweeps, ADeepJamGetsMoreSweepsUntilNoPairIsDeep) {
  Row budget = squeezed_row(40, 0.6);
  const SolveResult r0 = solve(budget, 0);
  // The setup: eight sweeps leave deep pairs.
  ASSERT_EQ(r0.iterations_used, 8u);
  ASSERT_GT(r0.max_pen_over_radius, kDeepPairOverRadius);
  const double left_by_budget = deepest_over_radius(budget.bodies);
  ASSERT_GT(left_by_budget, kDeepPairOverRadius);

  Row extra = squeezed_row(40, 0.6);
  const SolveResult r1 = solve(extra, 16);
  EXPECT_GT(r1.iterations_used, 8u);
  EXPECT_LE(r1.iterations_used, 24u);
  // It stopped because no pair was deep any more, or at the bound.
  EXPECT_TRUE(r1.max_pen_over_radius <= kDeepPairOverRadius || r1.iterations_used == 24u) << r1.max_pen_over_radius;
  EXPECT_LT(deepest_over_radius(extra.bodies), left_by_budget);
  // The bound: a row that needed more than one extra sweep gets exactly one when one is allowed.
  ASSERT_GT(r1.iterations_used, 9u);
  Row capped = squeezed_row(40, 0.6);
  EXPECT_EQ(solve(capped, 1).iterations_used, 9u);
}

TEST(ExtraSweeps, AShallowRowGetsNoneAndTheSameBits) {
  Row a = squeezed_row(40, 0.05);
  Row b = squeezed_row(40, 0.05);
  const SolveResult ra = solve(a, 0);
  const SolveResult rb = solve(b, 16);
  EXPECT_EQ(ra.iterations_used, rb.iterations_used);
  EXPECT_LE(rb.iterations_used, 8u);
  EXPECT_EQ(std::memcmp(a.bodies.x.data(), b.bodies.x.data(), a.bodies.size() * sizeof(double)), 0);
}

// A body deep in a fixed plane, its pairs shallow: the plane's depth is reported, but only pairs
// ask for more sweeps (the planes take back what a sweep pushed into them). With one sweep as the
// budget, a rule that counted planes would sweep again.
TEST(ExtraSweeps, ADeepPlaneAloneAddsNone) {
  Row row = squeezed_row(3, 0.05);
  // Body 0 stands 0.2 m (0.4 r) on the wrong side of the plane -x >= 0.2, which pushes it away
  // from the row.
  row.bodies.plane_begin[0] = 0;
  row.bodies.plane_count[0] = 1;
  const std::vector<SolverPlane> planes{{-1.0, 0.0, 0.0, 0.2, 0.0, 1.0, 0, ObjectId{}}};
  PairSchedule unused;
  const SolveResult r = solve_contacts(row.bodies, row.pairs, planes, 1, 16, 0.0, 0.25, unused, false);
  EXPECT_GT(r.max_pen_over_radius, 0.3);  // the plane's depth, met in the one sweep
  EXPECT_EQ(r.iterations_used, 1u);
  EXPECT_LE(row.bodies.x[0], -0.2 + 1e-12);  // and projected out
}

}  // namespace
}  // namespace throng::detail
