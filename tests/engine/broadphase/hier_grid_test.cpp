// HierGrid::find_pairs against brute force, with the build's margin and with a wider search margin
// (a pair list's skin, two cells out): every pair within reach is found exactly once, and the pairs
// of a wider search that are within the build's margin come in exactly the order, and the
// orientation, of the build margin's own search (the pair list relies on it).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <set>
#include <stdexcept>
#include <utility>
#include <vector>

#include "broadphase/cell_key.h"
#include "broadphase/hier_grid.h"
#include "throng/core/worker_pool.h"

namespace throng::detail {
namespace {

struct Crowd {
  std::vector<double> x, y, z, r, hh;
  std::vector<std::uint32_t> group, mask;
};

// Bodies in a square of side `side`, radii drawn from `radii`, a few airborne (z raised) and a few
// pass-through ones (group 2, mask 0).
Crowd random_crowd(std::size_t n, double side, const std::vector<double>& radii, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Crowd c;
  for (std::size_t i = 0; i < n; ++i) {
    const double r = radii[static_cast<std::size_t>(u(rng) * static_cast<double>(radii.size())) % radii.size()];
    c.x.push_back(side * u(rng) - 0.5 * side);
    c.y.push_back(side * u(rng) - 0.5 * side);
    c.z.push_back(u(rng) < 0.1 ? r + 0.5 + u(rng) : r);
    c.r.push_back(r);
    c.hh.push_back(u(rng) < 0.5 ? 0.5 : 0.0);
    const bool ghost = u(rng) < 0.02;
    c.group.push_back(ghost ? 2u : 1u);
    c.mask.push_back(ghost ? 0u : 0xffffffffu);
  }
  return c;
}

// Appends `clumps` to `c`, every third body shifted to x + x_third (the others x + x_other), every
// second to y + y_even (the others y + y_odd): a few dense clumps in a sparse crowd.
void add_clumps(Crowd& c, const Crowd& clumps, double x_third, double x_other, double y_even, double y_odd) {
  for (std::size_t i = 0; i < clumps.x.size(); ++i) {
    c.x.push_back(clumps.x[i] + (i % 3 == 0 ? x_third : x_other));
    c.y.push_back(clumps.y[i] + (i % 2 == 0 ? y_even : y_odd));
    c.z.push_back(clumps.z[i]); c.r.push_back(clumps.r[i]); c.hh.push_back(clumps.hh[i]);
    c.group.push_back(clumps.group[i]); c.mask.push_back(clumps.mask[i]);
  }
}

struct Sorted {
  Crowd c;  // solver order
  std::vector<std::uint32_t> order;
};

Sorted in_solver_order(const Crowd& d, const HierGrid& g) {
  Sorted s;
  s.order = g.order();
  for (const std::uint32_t i : s.order) {
    s.c.x.push_back(d.x[i]); s.c.y.push_back(d.y[i]); s.c.z.push_back(d.z[i]);
    s.c.r.push_back(d.r[i]); s.c.hh.push_back(d.hh[i]);
    s.c.group.push_back(d.group[i]); s.c.mask.push_back(d.mask[i]);
  }
  return s;
}

// The grid's candidate test (hier_grid.cpp, scan_one).
bool within(const Crowd& c, std::uint32_t i, std::uint32_t j, double margin) {
  const double dx = c.x[j] - c.x[i], dy = c.y[j] - c.y[i];
  const double reach = c.r[i] + c.r[j] + margin;
  const double gap_z = std::fabs(c.z[j] - c.z[i]) - c.hh[i] - c.hh[j];
  return !(dx * dx + dy * dy >= reach * reach) && !(gap_z >= reach) && (c.group[i] & c.mask[j]) != 0 &&
         (c.group[j] & c.mask[i]) != 0;
}

std::set<std::pair<std::uint32_t, std::uint32_t>> brute_force(const Crowd& c, double margin) {
  std::set<std::pair<std::uint32_t, std::uint32_t>> out;
  const auto n = static_cast<std::uint32_t>(c.x.size());
  for (std::uint32_t i = 0; i < n; ++i) {
    for (std::uint32_t j = i + 1; j < n; ++j) {
      if (within(c, i, j, margin)) out.insert({i, j});
    }
  }
  return out;
}

void check(const Crowd& dense, double margin, double cell0) {
  HierGrid g;
  g.build(dense.x.data(), dense.y.data(), dense.r.data(), dense.x.size(), margin, cell0);
  const Sorted s = in_solver_order(dense, g);
  const GridBodyView v{s.c.x.data(), s.c.y.data(), s.c.z.data(), s.c.r.data(), s.c.hh.data(), s.c.group.data(),
                       s.c.mask.data()};
  std::vector<CandidatePair> narrow;
  ASSERT_EQ(g.find_pairs(v, margin, 4096, narrow), 0u);
  const double widest = HierGrid::max_extra_margin(cell0, margin);
  for (const double extra : {0.0, 0.1, 0.4, widest}) {
    SCOPED_TRACE(extra);
    std::vector<CandidatePair> wide;
    ASSERT_EQ(g.find_pairs(v, margin + extra, 4096, wide), 0u);
    std::set<std::pair<std::uint32_t, std::uint32_t>> found;
    for (const CandidatePair& p : wide) {
      ASSERT_TRUE(within(s.c, p.a, p.b, margin + extra));  // every candidate is a hit
      ASSERT_TRUE(found.insert({std::min(p.a, p.b), std::max(p.a, p.b)}).second) << "listed twice";
    }
    EXPECT_EQ(found, brute_force(s.c, margin + extra));
    // Within the build's margin: the narrow search's list, in its order and orientation.
    std::vector<std::pair<std::uint32_t, std::uint32_t>> kept, expected;
    for (const CandidatePair& p : wide) {
      if (within(s.c, p.a, p.b, margin)) kept.push_back({p.a, p.b});
    }
    for (const CandidatePair& p : narrow) expected.push_back({p.a, p.b});
    EXPECT_EQ(kept, expected);
  }
}

// A dense crowd of one size: counting-sorted, one level.
TEST(HierGrid, WiderSearchOneSize) {
  const Crowd c = random_crowd(2500, 30.0, {0.35}, 1);
  check(c, 0.05, 0.8);
}

// Three sizes (foot, mounts, giants): three levels and pairs across them.
TEST(HierGrid, WiderSearchMixedSizes) {
  const Crowd c = random_crowd(2500, 40.0, {0.35, 0.35, 0.35, 0.7, 1.4}, 2);
  check(c, 0.05, 0.8);
}

// Bodies spread thinly over a wide area: the key range is large next to the body count, so the
// levels are radix-sorted and neighbours are found through the cell list.
TEST(HierGrid, WiderSearchSparseLevels) {
  Crowd c = random_crowd(1500, 600.0, {0.35, 0.7}, 3);
  // A few clumps so that there are pairs at all.
  add_clumps(c, random_crowd(600, 6.0, {0.35, 0.7}, 4), 200.0, -150.0, 100.0, -220.0);
  check(c, 0.05, 0.8);
}

// A search on a pool is cut into pieces of cells and of coarser bodies, scanned side by side and
// joined in order: the same list, in the same order and orientation, and the same capped count as
// the search on one thread, for any margin and candidate budget.
void check_pool_search(const Crowd& dense, double margin, double cell0) {
  HierGrid g;
  g.build(dense.x.data(), dense.y.data(), dense.r.data(), dense.x.size(), margin, cell0);
  const Sorted s = in_solver_order(dense, g);
  const GridBodyView v{s.c.x.data(), s.c.y.data(), s.c.z.data(), s.c.r.data(), s.c.hh.data(), s.c.group.data(),
                       s.c.mask.data()};
  WorkerPool two(2), three(3);
  for (const double extra : {0.0, HierGrid::max_extra_margin(cell0, margin)}) {
    for (const std::uint32_t budget : {4096u, 6u}) {
      SCOPED_TRACE(testing::Message() << "extra " << extra << ", budget " << budget);
      std::vector<CandidatePair> one, many;
      const std::uint32_t capped = g.find_pairs(v, margin + extra, budget, one);
      if (budget == 6u) {
        EXPECT_GT(capped, 0u);  // the budget bites: the capped counts are compared
      }
      for (WorkerPool* pool : {&two, &three}) {
        for (int round = 0; round < 2; ++round) {
          many.clear();
          ASSERT_EQ(g.find_pairs(v, margin + extra, budget, many, pool), capped);
          ASSERT_EQ(many.size(), one.size());
          for (std::size_t k = 0; k < one.size(); ++k) {
            ASSERT_TRUE(one[k].a == many[k].a && one[k].b == many[k].b) << "pair " << k;
          }
        }
      }
      // In two parts (a pair list searched across a tick boundary), on one thread or a pool, even
      // one of another size for the rest: the first part is a proper prefix, both together are the
      // whole search, and their capped counts add up to its.
      for (WorkerPool* first_pool : {static_cast<WorkerPool*>(nullptr), &two}) {
        for (WorkerPool* rest_pool : {static_cast<WorkerPool*>(nullptr), &three}) {
          many.clear();
          const std::uint32_t capped_first =
              g.find_pairs(v, margin + extra, budget, many, first_pool, HierGrid::SearchPart::kFirst);
          const std::size_t first = many.size();
          EXPECT_GT(first, 0u);
          EXPECT_LT(first, one.size());
          const std::uint32_t capped_rest =
              g.find_pairs(v, margin + extra, budget, many, rest_pool, HierGrid::SearchPart::kRest);
          ASSERT_EQ(capped_first + capped_rest, capped);
          ASSERT_EQ(many.size(), one.size());
          for (std::size_t k = 0; k < one.size(); ++k) {
            ASSERT_TRUE(one[k].a == many[k].a && one[k].b == many[k].b) << "pair " << k;
          }
          // The rest is scanned once: a second one is refused.
          EXPECT_THROW(g.find_pairs(v, margin + extra, budget, many, rest_pool, HierGrid::SearchPart::kRest),
                       std::logic_error);
        }
      }
    }
  }
}

// The rest of a search needs its first part on the same grid: never begun, or the grid built again
// since, is refused rather than scanning half a grid.
TEST(HierGrid, RestOfASearchNeedsItsFirstPartOnTheSameGrid) {
  const Crowd c = random_crowd(2000, 30.0, {0.35}, 9);
  HierGrid g;
  g.build(c.x.data(), c.y.data(), c.r.data(), c.x.size(), 0.05, 0.8);
  const Sorted s = in_solver_order(c, g);
  const GridBodyView v{s.c.x.data(), s.c.y.data(), s.c.z.data(), s.c.r.data(), s.c.hh.data(), s.c.group.data(),
                       s.c.mask.data()};
  std::vector<CandidatePair> out;
  EXPECT_THROW(g.find_pairs(v, 0.3, 48, out, nullptr, HierGrid::SearchPart::kRest), std::logic_error);
  g.find_pairs(v, 0.3, 48, out, nullptr, HierGrid::SearchPart::kFirst);
  g.build(c.x.data(), c.y.data(), c.r.data(), c.x.size(), 0.05, 0.8);
  EXPECT_THROW(g.find_pairs(v, 0.3, 48, out, nullptr, HierGrid::SearchPart::kRest), std::logic_error);
  // A whole search in between ends the begun one too.
  g.find_pairs(v, 0.3, 48, out, nullptr, HierGrid::SearchPart::kFirst);
  g.find_pairs(v, 0.3, 48, out);
  EXPECT_THROW(g.find_pairs(v, 0.3, 48, out, nullptr, HierGrid::SearchPart::kRest), std::logic_error);
}

TEST(HierGrid, SearchOnAPoolGivesTheSameListOneSize) {
  check_pool_search(random_crowd(30000, 100.0, {0.35}, 5), 0.05, 0.8);
}

TEST(HierGrid, SearchOnAPoolGivesTheSameListMixedSizes) {
  check_pool_search(random_crowd(30000, 130.0, {0.35, 0.35, 0.35, 0.7, 1.4}, 6), 0.05, 0.8);
}

TEST(HierGrid, SearchOnAPoolGivesTheSameListSparseLevels) {
  Crowd c = random_crowd(12000, 3000.0, {0.35, 0.7}, 7);
  add_clumps(c, random_crowd(12000, 40.0, {0.35, 0.7}, 8), 900.0, -700.0, 500.0, -1100.0);
  check_pool_search(c, 0.05, 0.8);
}

}  // namespace
// cell_coord computes floor by truncation (no library call): the same cell as clamp(floor(v * inv))
// for every finite coordinate and the infinities, at cell edges, around zero and at the clamp.
TEST(CellCoord, IsTheClampedFloor) {
  auto reference = [](double v, double inv) {
    return static_cast<std::int64_t>(std::clamp(std::floor(v * inv), -kCellCoordLimit, kCellCoordLimit));
  };
  std::vector<double> values = {0.0, -0.0, 0.5, -0.5, 1.0, -1.0, 0.7999999999999999, -0.8, 2.4, -2.4, 1e-300, -1e-300,
                                std::nextafter(0.8, 0.0), std::nextafter(-0.8, 0.0), 8.6e8, -8.6e8, 1e12, -1e12,
                                std::numeric_limits<double>::max(), -std::numeric_limits<double>::max(),
                                std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
  for (int k = -2000; k <= 2000; ++k) {
    const double edge = 0.8 * k;
    values.push_back(edge);
    values.push_back(std::nextafter(edge, -1e300));
    values.push_back(std::nextafter(edge, 1e300));
  }
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> wide(-1e9, 1e9), near(-50.0, 50.0);
  for (int k = 0; k < 20000; ++k) values.push_back(k % 2 == 0 ? wide(rng) : near(rng));
  for (const double inv : {1.0 / 0.8, 1.0, 0.5, 1.0 / 2.0, 1.0 / 0.35}) {
    for (const double v : values) ASSERT_EQ(cell_coord(v, inv), reference(v, inv)) << v << " * " << inv;
  }
}

}  // namespace throng::detail
