#pragma once
// Projection of one body pair onto its separating plane, placed at the share point (the patent's
// virtual plane VP1 at the ratio point): a moves share_a of the correction, b the rest.
//
// The correction is accumulated in pair.lambda and clamped at zero (projected Gauss-Seidel): a pair
// may pull its bodies back together only by as much as it pushed them apart this tick, which is
// what makes warm starting safe. Grounded pairs are resolved in the ground plane, using the exact
// horizontal separation that upright capsules at their heights need; pairs with an airborne body
// are resolved along the 3D normal between the core segments.
//
// Hot loop: one square root and one division per overlapping pair; separated pairs with no push to
// take back cost a multiply-add and a compare.
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "solver/solver_data.h"

namespace throng::detail {

// A direction for bodies whose cores coincide: derived from both ids only, so it is deterministic,
// different for different pairs (a pile at one point spreads out in all directions) and never NaN.
inline void coincident_direction(std::uint32_t id_a, std::uint32_t id_b, double& nx, double& ny) {
  std::uint64_t h = (static_cast<std::uint64_t>(id_a) << 32) | id_b;
  h ^= h >> 33; h *= 0xff51afd7ed558ccdULL; h ^= h >> 33; h *= 0xc4ceb9fe1a85ec53ULL; h ^= h >> 33;
  const double hx = static_cast<double>(static_cast<std::int16_t>(h & 0xFFFF)) + 0.5;
  const double hy = static_cast<double>(static_cast<std::int16_t>((h >> 16) & 0xFFFF)) + 0.5;
  const double len = std::sqrt(hx * hx + hy * hy);
  nx = hx / len;
  ny = hy / len;
}

// Returns the penetration before the projection (0 if separated), in metres. share_a is passed
// separately from p.share_a because a body pinned against a fixed plane takes at most the smaller
// share (pinned_share in contact_solver.cpp).
// Always inlined: the general sweep calls it for every pair, and as a call (it outgrew the
// inliner's budget with the two position representations) the pair-order sweep ran much slower.
[[gnu::always_inline]] inline double project_pair(const BodyPtrs& b, SolverPair& p, double share_a) {
  const std::uint32_t ia = p.a, ib = p.b;
  const double dx = b.px(ib) - b.px(ia);
  const double dy = b.py(ib) - b.py(ia);
  if (p.target >= 0.0) {
    const double d2 = dx * dx + dy * dy;
    if (d2 >= p.target * p.target && p.lambda == 0.0) return 0.0;
    const double dist = std::sqrt(d2);
    const double pen = p.target - dist;
    const double new_lambda = std::max(0.0, p.lambda + pen);
    const double step = new_lambda - p.lambda;
    p.lambda = new_lambda;
    double nx, ny;
    if (dist > 1e-9 * p.target) {
      const double inv = 1.0 / dist;
      nx = dx * inv;
      ny = dy * inv;
    } else {
      coincident_direction(b.id[ia], b.id[ib], nx, ny);
    }
    const double move_a = step * share_a;
    const double move_b = step - move_a;
    b.shift(ia, -(nx * move_a), -(ny * move_a));
    b.shift(ib, nx * move_b, ny * move_b);
    return pen > 0.0 ? pen : 0.0;
  }
  const double rsum = b.r[ia] + b.r[ib];
  const double gap_z = std::fabs(b.z[ib] - b.z[ia]) - b.hh[ia] - b.hh[ib];
  // 3D: closest points of two vertical segments differ by (dx, dy, dz) with dz the vertical gap.
  const double dz = gap_z > 0.0 ? (b.z[ib] > b.z[ia] ? gap_z : -gap_z) : 0.0;
  const double d2 = dx * dx + dy * dy + dz * dz;
  if (d2 >= rsum * rsum && p.lambda == 0.0) return 0.0;
  const double dist = std::sqrt(d2);
  const double pen = rsum - dist;
  const double new_lambda = std::max(0.0, p.lambda + pen);
  const double step = new_lambda - p.lambda;
  p.lambda = new_lambda;
  double nx, ny, nz = 0.0;
  if (dist > 1e-9 * rsum) { nx = dx / dist; ny = dy / dist; nz = dz / dist; }
  else coincident_direction(b.id[ia], b.id[ib], nx, ny);
  const double move_a = step * share_a;
  const double move_b = step - move_a;
  // A grounded body cannot leave its support: it keeps only the horizontal part of its push.
  b.shift(ia, -(nx * move_a), -(ny * move_a));
  if (!b.grounded[ia]) b.z[ia] -= nz * move_a;
  b.shift(ib, nx * move_b, ny * move_b);
  if (!b.grounded[ib]) b.z[ib] += nz * move_b;
  return pen > 0.0 ? pen : 0.0;
}

}  // namespace throng::detail
