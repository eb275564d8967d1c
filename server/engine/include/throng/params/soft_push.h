#pragma once
// Soft fixed bodies (the patent's modified example, FIG. 10): a bush, a cushion or a hay bale is
// fixed, but a body pressing into it may sink in and is pushed out gradually over several ticks,
// more strongly the deeper it is — and it can never pass through.
//
// Formula. With softness s in [0, 1], penetration depth d >= 0 and mover radius r > 0, the share of
// the current depth the mover is pushed out THIS tick is
//
//     share(d) = 1 - s * r / (r + d)
//
// so the push distance and the depth left after the push are
//
//     push(d)      = d * share(d)
//     remaining(d) = d - push(d) = s * r * d / (r + d)
//
// Properties (tested in tests/engine/params/soft_push_test.cpp):
//   * s = 0 gives share 1: a rigid fixed body (the patent's normal FIG. 10(a) case).
//   * share grows with depth (FIG. 10(c) vs (b): deeper -> larger share).
//   * push(d) is strictly increasing: d/dd push = 1 - s * r^2 / (r + d)^2 > 0 for d > 0.
//   * remaining(d) < s * r = max_sink for every d: the mover sinks in at most max_sink = s * r
//     (at most its own radius), so it can never pass through.
//   * With no further pushing, d_{n+1} = remaining(d_n) < s * d_n, and d_{n+1} >= s * d_n / 2 while
//     d_n <= r: a geometric decay by a factor between s/2 and s per tick — gradual, never in one tick
//     (for s = 1 it decays like r / n, slower still).
// Why this shape rather than a linear ramp clamped at max_sink: a clamp has a kink where the
// share suddenly changes slope, which shows up as a visible "bump" as a body walks into a bush; the
// rational form is smooth everywhere and needs no tuning parameter besides softness.
//
// Degenerate input (softness <= 0 or NaN, depth <= 0 or NaN, radius <= 0 or not finite) returns
// 1: behave like a rigid body rather than let a body sink into something on bad data.
#include <cmath>

namespace throng::params {

// Deepest a mover can remain inside a soft fixed body after a push.
inline double soft_max_sink_m(double softness, double mover_radius_m) {
  const double s = softness < 0.0 ? 0.0 : (softness > 1.0 ? 1.0 : softness);
  return s * mover_radius_m;
}

inline double soft_push_share(double softness, double depth_m, double mover_radius_m) {
  if (!(softness > 0.0) || !(depth_m > 0.0) || !(mover_radius_m > 0.0) || !std::isfinite(mover_radius_m)) {
    return 1.0;
  }
  const double s = softness > 1.0 ? 1.0 : softness;
  if (!std::isfinite(depth_m)) return 1.0;
  return 1.0 - s * mover_radius_m / (mover_radius_m + depth_m);
}

}  // namespace throng::params
