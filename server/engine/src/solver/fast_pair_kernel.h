#pragma once
// Projection of the fast pairs of one schedule level (pair_schedule.h): both bodies grounded,
// neither touching fixed scenery, resolved in the ground plane at the pair's target distance.
//
// Bit-for-bit the same arithmetic as the grounded branch of project_pair (pair_projection.h), in
// the same operation order, for every pair: the two-lane SSE2 path and the scalar path give the
// same bits (IEEE add, mul, div and sqrt are correctly rounded on both; no FMA), so which path a
// pair takes never changes the result. SSE2 is part of baseline x86-64; wider vectors (AVX2) would
// need run-time dispatch and were not tried.
#include <algorithm>
#include <cmath>
#include <cstdint>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "solver/pair_projection.h"
#include "solver/pair_schedule.h"
#include "solver/solver_data.h"

namespace throng::detail {

// One fast pair, scalar. Returns the penetration before the projection over the smaller radius
// (0 if separated). The ratio is taken with a stored reciprocal: it only steers the early exit
// and StepStats, and a division per pair and sweep was a third of the divider's work.
inline double project_fast_pair(const BodyPtrs& b, PairSchedule& s, std::uint32_t k) {
  const std::uint32_t ia = s.a[k], ib = s.b[k];
  const double dx = b.x[ib] - b.x[ia];
  const double dy = b.y[ib] - b.y[ia];
  const double target = s.target[k];
  const double lambda = s.lambda[k];
  const double d2 = dx * dx + dy * dy;
  if (d2 >= target * target && lambda == 0.0) return 0.0;
  const double dist = std::sqrt(d2);
  const double pen = target - dist;
  const double new_lambda = std::max(0.0, lambda + pen);
  const double step = new_lambda - lambda;
  s.lambda[k] = new_lambda;
  double nx, ny;
  if (dist > 1e-9 * target) {
    const double inv = 1.0 / dist;
    nx = dx * inv;
    ny = dy * inv;
  } else {
    coincident_direction(b.id[ia], b.id[ib], nx, ny);
  }
  const double move_a = step * s.share_now[k];
  const double move_b = step - move_a;
  b.x[ia] -= nx * move_a; b.y[ia] -= ny * move_a;
  b.x[ib] += nx * move_b; b.y[ib] += ny * move_b;
  if (pen > 0.0) {
    s.share_now[k] = std::clamp(s.share_now[k], s.conflict_lo, s.conflict_hi);
    return pen * s.inv_r_min[k];
  }
  return 0.0;
}

// Projects fast pairs [begin, end) of one level (they share no body). Returns the largest
// penetration over the smaller radius seen before projecting.
inline double project_fast_range(const BodyPtrs& b, PairSchedule& s, std::uint32_t begin, std::uint32_t end) {
  double worst = 0.0;
  std::uint32_t k = begin;
#if defined(__SSE2__)
  // Plain local pointers, so that stores through them need not reload the vectors' members.
  double* const x = b.x;
  double* const y = b.y;
  const std::uint32_t* const ia = s.a.data();
  const std::uint32_t* const ib = s.b.data();
  const double* const target_p = s.target.data();
  double* const lambda_p = s.lambda.data();
  double* const share_p = s.share_now.data();
  const double* const inv_r_min_p = s.inv_r_min.data();
  const __m128d zero = _mm_setzero_pd();
  const __m128d eps = _mm_set1_pd(1e-9);
  const __m128d one = _mm_set1_pd(1.0);
  const __m128d conflict_lo = _mm_set1_pd(s.conflict_lo), conflict_hi = _mm_set1_pd(s.conflict_hi);
  __m128d worst2 = zero;
  for (; k + 2 <= end; k += 2) {
    const std::uint32_t a0 = ia[k], a1 = ia[k + 1], b0 = ib[k], b1 = ib[k + 1];
    const __m128d xa = _mm_set_pd(x[a1], x[a0]), ya = _mm_set_pd(y[a1], y[a0]);
    const __m128d xb = _mm_set_pd(x[b1], x[b0]), yb = _mm_set_pd(y[b1], y[b0]);
    const __m128d dx = _mm_sub_pd(xb, xa), dy = _mm_sub_pd(yb, ya);
    const __m128d d2 = _mm_add_pd(_mm_mul_pd(dx, dx), _mm_mul_pd(dy, dy));
    const __m128d target = _mm_loadu_pd(target_p + k);
    const __m128d lambda = _mm_loadu_pd(lambda_p + k);
    // Lanes the scalar path returns from early: separated with nothing to take back.
    const __m128d skip = _mm_and_pd(_mm_cmpge_pd(d2, _mm_mul_pd(target, target)), _mm_cmpeq_pd(lambda, zero));
    const int skip_bits = _mm_movemask_pd(skip);
    const __m128d dist = _mm_sqrt_pd(d2);
    // Coincident cores need the id-derived direction: leave both lanes to the scalar path.
    const __m128d apart = _mm_cmpgt_pd(dist, _mm_mul_pd(eps, target));
    if ((_mm_movemask_pd(apart) | skip_bits) != 3) {
      worst = std::max(worst, project_fast_pair(b, s, k));
      worst = std::max(worst, project_fast_pair(b, s, k + 1));
      continue;
    }
    const __m128d pen = _mm_sub_pd(target, dist);
    const __m128d new_lambda = _mm_max_pd(_mm_add_pd(lambda, pen), zero);  // std::max(0.0, v)
    const __m128d step = _mm_sub_pd(new_lambda, lambda);
    const __m128d inv = _mm_div_pd(one, dist);
    const __m128d nx = _mm_mul_pd(dx, inv), ny = _mm_mul_pd(dy, inv);
    const __m128d share = _mm_loadu_pd(share_p + k);
    const __m128d move_a = _mm_mul_pd(step, share);
    const __m128d move_b = _mm_sub_pd(step, move_a);
    // Skipped lanes keep every value they had (a select, not an add of zero: -0.0 stays -0.0).
    auto keep = [&](__m128d old_v, __m128d new_v) {
      return _mm_or_pd(_mm_and_pd(skip, old_v), _mm_andnot_pd(skip, new_v));
    };
    const __m128d xa2 = keep(xa, _mm_sub_pd(xa, _mm_mul_pd(nx, move_a)));
    const __m128d ya2 = keep(ya, _mm_sub_pd(ya, _mm_mul_pd(ny, move_a)));
    const __m128d xb2 = keep(xb, _mm_add_pd(xb, _mm_mul_pd(nx, move_b)));
    const __m128d yb2 = keep(yb, _mm_add_pd(yb, _mm_mul_pd(ny, move_b)));
    _mm_storel_pd(x + a0, xa2); _mm_storeh_pd(x + a1, xa2);
    _mm_storel_pd(y + a0, ya2); _mm_storeh_pd(y + a1, ya2);
    _mm_storel_pd(x + b0, xb2); _mm_storeh_pd(x + b1, xb2);
    _mm_storel_pd(y + b0, yb2); _mm_storeh_pd(y + b1, yb2);
    _mm_storeu_pd(lambda_p + k, keep(lambda, new_lambda));
    // Branch-free from here: whether a lane pushed is data-dependent and mispredicts often.
    const __m128d pushed = _mm_andnot_pd(skip, _mm_cmpgt_pd(pen, zero));
    // std::clamp(share, lo, hi), operand order chosen so that ties and bounds give the same bits.
    const __m128d conflict = _mm_max_pd(_mm_min_pd(share, conflict_hi), conflict_lo);
    _mm_storeu_pd(share_p + k, _mm_or_pd(_mm_and_pd(pushed, conflict), _mm_andnot_pd(pushed, share)));
    worst2 = _mm_max_pd(worst2, _mm_mul_pd(_mm_and_pd(pushed, pen), _mm_loadu_pd(inv_r_min_p + k)));
  }
  double lanes[2];
  _mm_storeu_pd(lanes, worst2);
  worst = std::max(worst, std::max(lanes[0], lanes[1]));
#endif
  for (; k < end; ++k) worst = std::max(worst, project_fast_pair(b, s, k));
  return worst;
}

}  // namespace throng::detail
