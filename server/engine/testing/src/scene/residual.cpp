// Independent residual-penetration measurement (definitions in residual.h).
#include "throng/scene/residual.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <stdexcept>
#include <vector>

namespace throng::scene {
namespace {

// Hash combine with a full avalanche (murmur3's fmix64). Table slots are the low bits, and a bare
// multiply leaves those depending only on the key's low bits — for a packed cell key, only on the
// y coordinate — so a whole row of cells piled into one probe chain (several times slower in a
// large crowd; docs/design/solver.md).
std::uint64_t mix(std::uint64_t h, std::uint64_t v) {
  h ^= v + 0x9E3779B97F4A7C15ull + (h << 6) + (h >> 2);
  h ^= h >> 33;
  h *= 0xFF51AFD7ED558CCDull;
  h ^= h >> 33;
  h *= 0xC4CEB9FE1A85EC53ull;
  return h ^ (h >> 33);
}

std::uint64_t bits(double d) { return std::bit_cast<std::uint64_t>(d + 0.0); }  // + 0.0: -0 == +0

std::size_t table_capacity(std::size_t n) { return std::bit_ceil(std::max<std::size_t>(16, 2 * n)); }

// Bodies with identical position and shape, merged: the one_cell start (N bodies at one point)
// becomes one class of multiplicity N instead of N^2/2 pairs.
struct Classes {
  std::vector<double> x, y, z, r, hh;
  std::vector<std::uint64_t> mult;
  std::vector<std::uint32_t> of_body;  // class of each measured body
};

Classes merge_identical(const BodyArrays& b, const std::vector<std::uint32_t>& finite) {
  Classes c;
  const std::size_t cap = table_capacity(finite.size());
  std::vector<std::uint32_t> slot(cap, UINT32_MAX);
  for (const std::uint32_t i : finite) {
    const double key[5] = {b.x[i], b.y[i], b.z[i], b.radius[i], b.half_height[i]};
    std::uint64_t h = 0;
    for (const double k : key) h = mix(h, bits(k));
    std::size_t s = h & (cap - 1);
    for (;; s = (s + 1) & (cap - 1)) {
      const std::uint32_t ci = slot[s];
      if (ci == UINT32_MAX) {
        slot[s] = static_cast<std::uint32_t>(c.x.size());
        c.x.push_back(key[0]);
        c.y.push_back(key[1]);
        c.z.push_back(key[2]);
        c.r.push_back(key[3]);
        c.hh.push_back(key[4]);
        c.mult.push_back(1);
        c.of_body.push_back(slot[s]);
        break;
      }
      if (c.x[ci] == key[0] && c.y[ci] == key[1] && c.z[ci] == key[2] && c.r[ci] == key[3] && c.hh[ci] == key[4]) {
        ++c.mult[ci];
        c.of_body.push_back(ci);
        break;
      }
    }
  }
  return c;
}

// Uniform grid over the classes, cell edge = 2 * largest radius, so any overlapping pair lies in
// the same or an adjacent cell (horizontal distance never exceeds the 3D distance).
struct Grid {
  std::vector<std::uint64_t> cell_key;       // per occupied cell, in order of first appearance
  std::vector<std::uint32_t> start;          // members of cell k: order[start[k] .. start[k+1])
  std::vector<std::uint32_t> order;
  std::vector<std::uint32_t> slot;           // hash table: slot -> cell index
  std::size_t mask = 0;

  std::uint32_t find(std::uint64_t key) const {
    for (std::size_t s = mix(0, key) & mask;; s = (s + 1) & mask) {
      if (slot[s] == UINT32_MAX || cell_key[slot[s]] == key) return slot[s];
    }
  }
};

constexpr std::int64_t kCellLimit = std::int64_t{1} << 30;

std::int64_t cell_coord(double v, double inv_cell) {
  const double c = std::floor(v * inv_cell);
  return static_cast<std::int64_t>(std::clamp(c, -static_cast<double>(kCellLimit), static_cast<double>(kCellLimit)));
}

std::uint64_t pack(std::int64_t cx, std::int64_t cy) {
  return (static_cast<std::uint64_t>(cx + 2 * kCellLimit) << 32) | static_cast<std::uint64_t>(cy + 2 * kCellLimit);
}

Grid build_grid(const Classes& c, double inv_cell) {
  Grid g;
  const std::size_t n = c.x.size();
  g.slot.assign(table_capacity(n), UINT32_MAX);
  g.mask = g.slot.size() - 1;
  std::vector<std::uint32_t> cell_of(n);
  std::vector<std::uint32_t> count;
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint64_t key = pack(cell_coord(c.x[i], inv_cell), cell_coord(c.y[i], inv_cell));
    std::size_t s = mix(0, key) & g.mask;
    while (g.slot[s] != UINT32_MAX && g.cell_key[g.slot[s]] != key) s = (s + 1) & g.mask;
    if (g.slot[s] == UINT32_MAX) {
      g.slot[s] = static_cast<std::uint32_t>(g.cell_key.size());
      g.cell_key.push_back(key);
      count.push_back(0);
    }
    cell_of[i] = g.slot[s];
    ++count[g.slot[s]];
  }
  g.start.assign(count.size() + 1, 0);
  for (std::size_t k = 0; k < count.size(); ++k) g.start[k + 1] = g.start[k] + count[k];
  g.order.resize(n);
  std::vector<std::uint32_t> fill(g.start.begin(), g.start.end() - 1);
  for (std::size_t i = 0; i < n; ++i) g.order[fill[cell_of[i]]++] = static_cast<std::uint32_t>(i);
  return g;
}

struct Accumulator {
  const Classes& c;
  std::vector<double> deepest;  // per class
  ResidualStats& out;

  void pair(std::uint32_t a, std::uint32_t b) {
    ++out.pair_tests;
    const double pen =
        pair_pen_over_radius(c.x[a], c.y[a], c.z[a], c.r[a], c.hh[a], c.x[b], c.y[b], c.z[b], c.r[b], c.hh[b]);
    if (pen <= 0.0) return;
    out.max_pen_over_radius = std::max(out.max_pen_over_radius, pen);
    if (pen > 0.01) out.pairs_over_1pct += c.mult[a] * c.mult[b];
    deepest[a] = std::max(deepest[a], pen);
    deepest[b] = std::max(deepest[b], pen);
  }
};

}  // namespace

double pair_pen_over_radius(double ax, double ay, double az, double ar, double ahh, double bx, double by, double bz,
                            double br, double bhh) {
  const double dx = bx - ax;
  const double dy = by - ay;
  // Gap between the vertical core segments; 0 when their z ranges overlap.
  const double gap_z = std::max(0.0, std::max((bz - bhh) - (az + ahh), (az - ahh) - (bz + bhh)));
  const double dist = std::sqrt(dx * dx + dy * dy + gap_z * gap_z);
  const double pen = (ar + br) - dist;
  return pen > 0.0 ? pen / std::min(ar, br) : 0.0;
}

ResidualStats measure_residual(const BodyArrays& b) {
  const std::size_t n = b.x.size();
  if (b.y.size() != n || b.z.size() != n || b.radius.size() != n || b.half_height.size() != n)
    throw std::invalid_argument("measure_residual: body arrays differ in length");
  ResidualStats out;
  std::vector<std::uint32_t> finite;
  finite.reserve(n);
  double max_r = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const bool ok = std::isfinite(b.x[i]) && std::isfinite(b.y[i]) && std::isfinite(b.z[i]) &&
                    std::isfinite(b.radius[i]) && std::isfinite(b.half_height[i]) && b.radius[i] > 0.0;
    if (!ok) {
      ++out.nan_count;
      continue;
    }
    finite.push_back(static_cast<std::uint32_t>(i));
    max_r = std::max(max_r, b.radius[i]);
  }
  out.bodies = finite.size();
  if (finite.empty()) return out;

  const Classes c = merge_identical(b, finite);
  Accumulator acc{c, std::vector<double>(c.x.size(), 0.0), out};
  for (std::size_t k = 0; k < c.x.size(); ++k) {
    if (c.mult[k] < 2) continue;
    // m identical bodies: every pair at distance 0, pen = (2r - 0) / r = 2.
    out.coincident_bodies += c.mult[k];
    const double pen = pair_pen_over_radius(c.x[k], c.y[k], c.z[k], c.r[k], c.hh[k], c.x[k], c.y[k], c.z[k], c.r[k], c.hh[k]);
    out.max_pen_over_radius = std::max(out.max_pen_over_radius, pen);
    if (pen > 0.01) out.pairs_over_1pct += c.mult[k] * (c.mult[k] - 1) / 2;
    acc.deepest[k] = std::max(acc.deepest[k], pen);
  }

  const double inv_cell = 1.0 / (2.0 * max_r);
  const Grid g = build_grid(c, inv_cell);
  // Half neighbourhood (self, E, NW, N, NE) so every pair of cells is visited once.
  constexpr std::int64_t kNeighbours[4][2] = {{1, 0}, {-1, 1}, {0, 1}, {1, 1}};
  for (std::size_t cell = 0; cell < g.cell_key.size(); ++cell) {
    const std::uint32_t begin = g.start[cell], end = g.start[cell + 1];
    for (std::uint32_t i = begin; i < end; ++i)
      for (std::uint32_t j = i + 1; j < end; ++j) acc.pair(g.order[i], g.order[j]);
    const std::int64_t cx = static_cast<std::int64_t>(g.cell_key[cell] >> 32) - 2 * kCellLimit;
    const std::int64_t cy = static_cast<std::int64_t>(g.cell_key[cell] & 0xFFFFFFFFull) - 2 * kCellLimit;
    for (const auto& d : kNeighbours) {
      const std::uint32_t other = g.find(pack(cx + d[0], cy + d[1]));
      if (other == UINT32_MAX) continue;
      for (std::uint32_t i = begin; i < end; ++i)
        for (std::uint32_t j = g.start[other]; j < g.start[other + 1]; ++j) acc.pair(g.order[i], g.order[j]);
    }
  }

  // Nearest-rank 99th percentile over bodies: the value at rank ceil(0.99 n) in ascending order.
  std::vector<double> per_body(finite.size());
  for (std::size_t i = 0; i < finite.size(); ++i) per_body[i] = acc.deepest[c.of_body[i]];
  const std::size_t rank = (99 * per_body.size() + 99) / 100;  // ceil(0.99 n), >= 1
  std::nth_element(per_body.begin(), per_body.begin() + static_cast<std::ptrdiff_t>(rank - 1), per_body.end());
  out.p99_pen_over_radius = per_body[rank - 1];
  return out;
}

}  // namespace throng::scene
