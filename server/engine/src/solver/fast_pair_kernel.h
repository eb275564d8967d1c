#pragma once
// Projection and warm start of the fast pairs of the schedule (pair_schedule.h), a level or a run
// of whole levels at a time: both bodies grounded, neither touching fixed scenery, resolved in the
// ground plane at the pair's target distance, in single precision on the bodies' displacements
// (SolverBodies::u), four pairs at a time in SSE.
//
// Each fast pair keeps the normal it had at the start of the tick (PairSchedule::nx, ny): its
// separating plane (the patent's VP1 at the ratio point) turns with the pair between ticks, not
// between projections, as in the contact solvers of rigid-body engines. Its penetration is then
// linear in the displacements, pen = pen0 - n . (u_b - u_a), so a projection needs no square root
// or division. More important, the warm start becomes a plain sum of last tick's pushes along fixed
// directions, whatever order the pairs are applied in, so it can carry the whole push: in a packed
// crowd the pushes grow towards the middle like pressure in a fluid (several radii per pair in the
// core; figures in docs/design/solver.md). Along directions
// re-taken after each push, warm pushes that large throw the bodies about (the warm start was cut
// at 0.5 r for that reason), and the solve had to rebuild the core's pressure every tick in K
// sweeps: most of the residual penetration sat there (see kFastWarmStartCapOverRadius).
// The solution differs from a solve along re-taken directions only by how far a pair turns within
// one tick; true distance >= n . separation, so a pair the solve leaves at its target along n is
// at least at its target.
//
// The four-lane path and the scalar path give the same bits (IEEE add, sub and mul are correctly
// rounded in both, and there is no FMA), so which path a pair takes never changes the result. SSE
// is part of baseline x86-64. An eight-lane AVX2 path behind run-time dispatch gained next to
// nothing (the sweep is bound by the level-to-level dependency and the bodies' loads and stores).
#include <algorithm>
#include <cmath>
#include <cstdint>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "solver/pair_schedule.h"
#include "solver/solver_data.h"

namespace throng::detail {

#if defined(__SSE2__)
// Two bodies' (x, y) displacements as (x0, y0, x1, y1): one 8-byte load or store per body (__m64
// is declared may_alias, so this reads the float array legally).
inline __m128 load_body_pair(const float* u, std::uint32_t i0, std::uint32_t i1) {
  return _mm_loadh_pi(_mm_loadl_pi(_mm_setzero_ps(), reinterpret_cast<const __m64*>(u + 2 * i0)),
                      reinterpret_cast<const __m64*>(u + 2 * i1));
}
inline void store_body_pair(float* u, std::uint32_t i0, std::uint32_t i1, __m128 v) {
  _mm_storel_pi(reinterpret_cast<__m64*>(u + 2 * i0), v);
  _mm_storeh_pi(reinterpret_cast<__m64*>(u + 2 * i1), v);
}

// Four consecutive fast pairs k..k+3 of a level, one lane each: their bodies and the bodies'
// displacements.
struct FourPairs {
  std::uint32_t a0, a1, a2, a3, b0, b1, b2, b3;
  __m128 ax, ay, bx, by;

  FourPairs(const float* u, const PairSchedule& s, std::uint32_t k)
      : a0(s.a[k]), a1(s.a[k + 1]), a2(s.a[k + 2]), a3(s.a[k + 3]),
        b0(s.b[k]), b1(s.b[k + 1]), b2(s.b[k + 2]), b3(s.b[k + 3]) {
    const __m128 a01 = load_body_pair(u, a0, a1), a23 = load_body_pair(u, a2, a3);
    const __m128 b01 = load_body_pair(u, b0, b1), b23 = load_body_pair(u, b2, b3);
    ax = _mm_shuffle_ps(a01, a23, _MM_SHUFFLE(2, 0, 2, 0));
    ay = _mm_shuffle_ps(a01, a23, _MM_SHUFFLE(3, 1, 3, 1));
    bx = _mm_shuffle_ps(b01, b23, _MM_SHUFFLE(2, 0, 2, 0));
    by = _mm_shuffle_ps(b01, b23, _MM_SHUFFLE(3, 1, 3, 1));
  }

  // The pairs' current penetrations along their normals, lane by lane (fast_penetration).
  __m128 penetration(const PairSchedule& s, std::uint32_t k) const {
    const __m128 along = _mm_add_ps(_mm_mul_ps(_mm_loadu_ps(s.nx.data() + k), _mm_sub_ps(bx, ax)),
                                    _mm_mul_ps(_mm_loadu_ps(s.ny.data() + k), _mm_sub_ps(by, ay)));
    return _mm_sub_ps(_mm_loadu_ps(s.pen0.data() + k), along);
  }

  // Moves a by -n * move_a and b by +n * move_b, lane by lane, and stores the displacements.
  void push_apart(float* u, __m128 nx, __m128 ny, __m128 move_a, __m128 move_b) const {
    const __m128 ax2 = _mm_sub_ps(ax, _mm_mul_ps(nx, move_a)), ay2 = _mm_sub_ps(ay, _mm_mul_ps(ny, move_a));
    const __m128 bx2 = _mm_add_ps(bx, _mm_mul_ps(nx, move_b)), by2 = _mm_add_ps(by, _mm_mul_ps(ny, move_b));
    store_body_pair(u, a0, a1, _mm_unpacklo_ps(ax2, ay2));
    store_body_pair(u, a2, a3, _mm_unpackhi_ps(ax2, ay2));
    store_body_pair(u, b0, b1, _mm_unpacklo_ps(bx2, by2));
    store_body_pair(u, b2, b3, _mm_unpackhi_ps(bx2, by2));
  }
};
#endif

// Fast pair k's current penetration along its normal: the start penetration less the part of the
// displacement difference along the normal (> 0: overlapping), scalar.
inline float fast_penetration(const float* u, const PairSchedule& s, std::uint32_t k) {
  const std::uint32_t ia = s.a[k], ib = s.b[k];
  return s.pen0[k] - (s.nx[k] * (u[2 * ib] - u[2 * ia]) + s.ny[k] * (u[2 * ib + 1] - u[2 * ia + 1]));
}

// Moves a by -n * move_a and b by +n * move_b, scalar (FourPairs::push_apart's lane).
inline void move_pair_apart(float* u, std::uint32_t ia, std::uint32_t ib, float nx, float ny, float move_a, float move_b) {
  u[2 * ia] -= nx * move_a; u[2 * ia + 1] -= ny * move_a;
  u[2 * ib] += nx * move_b; u[2 * ib + 1] += ny * move_b;
}

// One fast pair, scalar. Returns the penetration before the projection over the smaller radius
// (0 if separated), and raises `moved` to the size of the projection's change of push (a push or a
// pull) over the smaller radius. The ratios are taken with a stored reciprocal: they only steer
// the early exit, which bands a sweep visits, and StepStats.
inline float project_fast_pair(const BodyPtrs& b, PairSchedule& s, std::uint32_t k, float& moved) {
  const float pen = fast_penetration(b.u, s, k);
  const float lambda = s.lambda[k];
  if (pen <= 0.0f && lambda == 0.0f) return 0.0f;
  const float new_lambda = std::max(0.0f, lambda + pen);
  const float step = new_lambda - lambda;
  s.lambda[k] = new_lambda;
  moved = std::max(moved, std::fabs(step) * s.inv_r_min[k]);
  const float move_a = step * s.share_now[k];
  move_pair_apart(b.u, s.a[k], s.b[k], s.nx[k], s.ny[k], move_a, step - move_a);
  if (pen > 0.0f) {
    s.share_now[k] = std::clamp(s.share_now[k], s.conflict_lo, s.conflict_hi);
    return pen * s.inv_r_min[k];
  }
  return 0.0f;
}

// Projects fast pairs [begin, end), four at a time, in order or (kReverse) in reverse: one level
// (its pairs share no body, so the order within it does not matter), or a run of whole levels
// whose fast ranges are padded to multiples of four (pair_schedule.h), so that no four-pair group
// straddles two levels and going through the groups in order (or in reverse) goes through the
// levels in order (or in reverse). Returns the largest penetration over the smaller radius seen
// before projecting, and raises `moved` as project_fast_pair does.
template <bool kReverse>
inline float project_fast_span(const BodyPtrs& b, PairSchedule& s, std::uint32_t begin, std::uint32_t end,
                               float& moved) {
  float worst = 0.0f;
  std::uint32_t whole_end = end;  // end of the four-pair groups
#if defined(__SSE2__)
  whole_end = begin + (end - begin) / 4 * 4;
  // Plain local pointers, so that stores through them need not reload the vectors' members.
  float* const u = b.u;
  const float* const nx_p = s.nx.data();
  const float* const ny_p = s.ny.data();
  float* const lambda_p = s.lambda.data();
  float* const share_p = s.share_now.data();
  const float* const inv_r_min_p = s.inv_r_min.data();
  const __m128 zero = _mm_setzero_ps();
  const __m128 conflict_lo = _mm_set1_ps(s.conflict_lo), conflict_hi = _mm_set1_ps(s.conflict_hi);
  const __m128 abs_mask = _mm_castsi128_ps(_mm_set1_epi32(0x7FFFFFFF));
  __m128 worst4 = zero, moved4 = zero;
  auto group = [&](std::uint32_t k) {
    const FourPairs q(u, s, k);
    const __m128 pen = q.penetration(s, k);
    const __m128 lambda = _mm_loadu_ps(lambda_p + k);
    // Lanes the scalar path returns from early: separated with nothing to take back.
    const __m128 skip = _mm_and_ps(_mm_cmple_ps(pen, zero), _mm_cmpeq_ps(lambda, zero));
    if (_mm_movemask_ps(skip) == 15) return;
    const __m128 new_lambda = _mm_max_ps(_mm_add_ps(lambda, pen), zero);  // std::max(0.0f, v)
    // Skipped lanes move by exactly zero and keep their lambda (a select: the scalar path never
    // touches them).
    const __m128 step = _mm_andnot_ps(skip, _mm_sub_ps(new_lambda, lambda));
    const __m128 nx = _mm_loadu_ps(nx_p + k), ny = _mm_loadu_ps(ny_p + k);
    const __m128 share = _mm_loadu_ps(share_p + k);
    const __m128 move_a = _mm_mul_ps(step, share);
    const __m128 move_b = _mm_sub_ps(step, move_a);
    q.push_apart(u, nx, ny, move_a, move_b);
    _mm_storeu_ps(lambda_p + k, _mm_or_ps(_mm_and_ps(skip, lambda), _mm_andnot_ps(skip, new_lambda)));
    // Branch-free from here: whether a lane pushed is data-dependent and mispredicts often.
    const __m128 pushed = _mm_andnot_ps(skip, _mm_cmpgt_ps(pen, zero));
    // std::clamp(share, lo, hi), operand order chosen so that ties and bounds give the same bits.
    const __m128 conflict = _mm_max_ps(_mm_min_ps(share, conflict_hi), conflict_lo);
    _mm_storeu_ps(share_p + k, _mm_or_ps(_mm_and_ps(pushed, conflict), _mm_andnot_ps(pushed, share)));
    const __m128 inv_r_min = _mm_loadu_ps(inv_r_min_p + k);
    worst4 = _mm_max_ps(worst4, _mm_mul_ps(_mm_and_ps(pushed, pen), inv_r_min));
    moved4 = _mm_max_ps(moved4, _mm_mul_ps(_mm_and_ps(step, abs_mask), inv_r_min));  // a skipped lane's step is 0
  };
  if constexpr (!kReverse) {
    for (std::uint32_t k = begin; k < whole_end; k += 4) group(k);
  }
#endif
  // Pairs past the last whole group, one by one (last first in reverse).
  if constexpr (kReverse) {
    for (std::uint32_t k = end; k > whole_end; --k) worst = std::max(worst, project_fast_pair(b, s, k - 1, moved));
  } else {
    for (std::uint32_t k = whole_end; k < end; ++k) worst = std::max(worst, project_fast_pair(b, s, k, moved));
  }
#if defined(__SSE2__)
  if constexpr (kReverse) {
    for (std::uint32_t k = whole_end; k > begin; k -= 4) group(k - 4);
  }
  float lanes[4];
  _mm_storeu_ps(lanes, worst4);
  worst = std::max({worst, lanes[0], lanes[1], lanes[2], lanes[3]});
  _mm_storeu_ps(lanes, moved4);
  moved = std::max({moved, lanes[0], lanes[1], lanes[2], lanes[3]});
#endif
  return worst;
}

// One level, or any pairs sharing no body, in order.
inline float project_fast_range(const BodyPtrs& b, PairSchedule& s, std::uint32_t begin, std::uint32_t end,
                                float& moved) {
  return project_fast_span<false>(b, s, begin, end, moved);
}

// Applies a fast pair's warm-start push (its lambda, already capped when the schedule was built)
// along its normal, at the pair's exact share (nothing has pushed it yet this tick).
inline void warm_start_fast(const BodyPtrs& b, const PairSchedule& s, std::uint32_t f) {
  const float lambda = s.lambda[f];
  if (lambda == 0.0f) return;
  const float move_a = lambda * s.share_now[f];
  move_pair_apart(b.u, s.a[f], s.b[f], s.nx[f], s.ny[f], move_a, lambda - move_a);
}

// warm_start_fast over fast pairs [begin, end) of one level, four at a time (same bits). A lane
// without a warm push moves its bodies by zero, which leaves a displacement's bits as they are:
// displacements start at +0 and a sum that cancels is +0, so none is ever -0.
inline void warm_start_fast_range(const BodyPtrs& b, const PairSchedule& s, std::uint32_t begin, std::uint32_t end) {
  std::uint32_t f = begin;
#if defined(__SSE2__)
  float* const u = b.u;
  const __m128 zero = _mm_setzero_ps();
  for (; f + 4 <= end; f += 4) {
    const __m128 lambda = _mm_loadu_ps(s.lambda.data() + f);
    if (_mm_movemask_ps(_mm_cmpeq_ps(lambda, zero)) == 15) continue;
    const FourPairs q(u, s, f);
    const __m128 nx = _mm_loadu_ps(s.nx.data() + f), ny = _mm_loadu_ps(s.ny.data() + f);
    const __m128 move_a = _mm_mul_ps(lambda, _mm_loadu_ps(s.share_now.data() + f));
    const __m128 move_b = _mm_sub_ps(lambda, move_a);
    q.push_apart(u, nx, ny, move_a, move_b);
  }
#endif
  for (; f < end; ++f) warm_start_fast(b, s, f);
}

}  // namespace throng::detail
