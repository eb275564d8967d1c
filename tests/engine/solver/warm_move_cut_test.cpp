// A body's net warm-start move is cut to kWarmStartMoveCapOverRadius of its radius
// (solver/pair_schedule.h): a guess whose pushes do not balance must not carry a body past bodies
// the pair search saw apart. Pushes that balance (pressure) pass whole, and the pairs keep their
// pushes, so the sweeps can give them back.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "solver/contact_solver.h"
#include "solver/pair_schedule.h"
#include "solver/solver_data.h"

namespace throng::detail {
namespace {

// Three bodies in a row, 0.6 m apart (radius 0.35: overlapping by 0.1 m). The pair (0, 1) carries
// `left` of warm push, the pair (1, 2) `right`; the middle body feels their difference.
struct Row {
  SolverBodies b;
  std::vector<SolverPair> pairs;
  Row(double left, double right) {
    b.resize(3);
    for (std::uint32_t i = 0; i < 3; ++i) {
      b.x[i] = 0.6 * i;
      b.y[i] = 0.0;
      b.z[i] = 0.5;
      b.r[i] = 0.35;
      b.hh[i] = 0.0;
      b.grounded[i] = 1;
      b.plane_begin[i] = 0;
      b.plane_count[i] = 0;
      b.id[i] = i + 1;
    }
    for (std::uint32_t i = 0; i < 2; ++i) {
      SolverPair p{};
      p.a = i;
      p.b = i + 1;
      p.target = 0.7;
      p.share_a = 0.5;
      p.lambda = i == 0 ? left : right;
      pairs.push_back(p);
    }
  }
  double moved(std::uint32_t i, double x0) const { return std::hypot(b.px(i) - x0, b.py(i)); }
};

const std::vector<SolverPlane> kNoPlanes;
constexpr double kCap = kWarmStartMoveCapOverRadius * 0.35;

TEST(WarmMoveCut, AnUnbalancedGuessMovesABodyNoFurtherThanTheCap) {
  // Unscheduled: the general pairs' cap (half a radius) lets 0.175 m of each push through.
  Row row(0.175, 0.0);
  apply_warm_start(row.b, row.pairs, kNoPlanes, 0.0);
  // Alone, pair (0, 1) would move the middle body 0.0875 m; the cut keeps it to the cap.
  EXPECT_NEAR(row.moved(1, 0.6), kCap, 1e-12);
  EXPECT_NEAR(row.moved(0, 0.0), kCap, 1e-12);
  EXPECT_DOUBLE_EQ(row.moved(2, 1.2), 0.0);
  EXPECT_DOUBLE_EQ(row.pairs[0].lambda, 0.175) << "the pair keeps its push";
}

TEST(WarmMoveCut, BalancedPressurePassesWhole) {
  // Scheduled (fast pairs carry up to 8 r): the middle body is pushed 0.5 m from each side and
  // stays; each outer body is pushed 0.5 m outwards with nothing against it, and is cut.
  Row row(1.0, 1.0);
  row.b.displaced = true;
  std::fill(row.b.u.begin(), row.b.u.end(), 0.0f);
  PairSchedule s;
  build_pair_schedule(row.b, row.pairs, 0.0, s);
  apply_warm_start(row.b, row.pairs, kNoPlanes, s, 0.0);
  EXPECT_LT(row.moved(1, 0.6), 1e-6) << "balanced pushes cancel, nothing to cut";
  EXPECT_NEAR(row.moved(0, 0.0), kCap, 1e-6);
  EXPECT_NEAR(row.moved(2, 1.2), kCap, 1e-6);
  // The pushes themselves are kept whole (1 m is under the fast cap of 8 r).
  for (std::size_t k = 0; k < s.fast_size(); ++k) {
    if (s.src[k] != PairSchedule::kNoPair) {
      EXPECT_FLOAT_EQ(s.lambda[k], 1.0f);
    }
  }
}

}  // namespace
}  // namespace throng::detail
