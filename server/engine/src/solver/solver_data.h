#pragma once
// The solver's working set for one tick, in broadphase (spatial) order: bodies gathered from the
// world's dense arrays, candidate pairs with their push share and accumulated push, and the
// separating planes against fixed scenery. Reused between ticks: no allocation after warm-up.
#include <cmath>
#include <cstdint>
#include <vector>

#include "throng/core/object_id.h"

namespace throng::detail {

// Position of body i along one axis in either representation (see SolverBodies::u), and a move of
// it: shared by SolverBodies and BodyPtrs.
inline double displaced_coord(const double* start, const float* u, bool displaced, std::uint32_t i, int axis) {
  return displaced ? start[i] + static_cast<double>(u[2 * i + axis]) : start[i];
}
inline void shift_body(double* x, double* y, float* u, bool displaced, std::uint32_t i, double dx, double dy) {
  if (displaced) {
    u[2 * i] = static_cast<float>(static_cast<double>(u[2 * i]) + dx);
    u[2 * i + 1] = static_cast<float>(static_cast<double>(u[2 * i + 1]) + dy);
  } else {
    x[i] += dx;
    y[i] += dy;
  }
}

struct SolverBodies {
  // Positions; in a scheduled solve the positions at its start (see u below).
  std::vector<double> x, y;
  std::vector<double> z, r, hh;  // z is written directly by airborne pairs and planes
  std::vector<std::uint8_t> grounded;
  std::vector<std::uint32_t> plane_begin, plane_count;  // range in SolverPlanes
  std::vector<std::uint32_t> id;                        // ObjectId value (tie-breaks, directions)
  // In a scheduled (crowd) solve, the bodies' horizontal displacement this solve, (x, y)
  // interleaved, in single precision; x and y then keep the positions at the start of the solve.
  // Why: a crowd's sweep is bound by the bytes and instructions per pair, and a displacement needs
  // no more than float: it stays within a few radii, so float's 24 bits resolve it to ~1e-7 of its
  // size however far the crowd stands from the origin (positions themselves stay double). One
  // 8-byte load or store moves a body's x and y, and four pairs fit one SSE register. An
  // unscheduled solve (small or calm scenes) moves x and y themselves, exactly as before.
  std::vector<float> u;
  bool displaced = false;  // true: positions are x + u, y + u (see above)
  // Scratch of an unscheduled warm start: the positions before it (its move is cut per body).
  std::vector<double> warm_x0, warm_y0;

  void resize(std::size_t n) {
    x.resize(n); y.resize(n); z.resize(n); r.resize(n); hh.resize(n);
    grounded.resize(n); plane_begin.resize(n); plane_count.resize(n); id.resize(n);
    warm_x0.resize(n); warm_y0.resize(n);  // sized with the bodies: a solve never allocates them
    // Spare slots past body n for the pair schedule's padding pairs, which move them by zero (see
    // pad_body; ensure_pad_slots adds one per band).
    u.resize(2 * n + 2);
  }
  std::size_t size() const { return x.size(); }

  // The body that band c's padding pairs move (by zero). One per band, a cache line apart, so that
  // bands swept side by side on two threads (WorkerPool) never write the same line.
  static constexpr std::size_t kPadStride = 8;
  std::uint32_t pad_body(std::size_t band) const { return static_cast<std::uint32_t>(size() + kPadStride * band); }
  // Room in u for the padding bodies of `bands` bands (grows only at warm-up; new slots are zero).
  void ensure_pad_slots(std::size_t bands) {
    const std::size_t need = 2 * (size() + kPadStride * bands) + 2;
    if (u.size() < need) u.resize(need, 0.0f);
  }

  // Current position of body i and a move of it, for the general code (either representation).
  double px(std::uint32_t i) const { return displaced_coord(x.data(), u.data(), displaced, i, 0); }
  double py(std::uint32_t i) const { return displaced_coord(y.data(), u.data(), displaced, i, 1); }
  void shift(std::uint32_t i, double dx, double dy) { shift_body(x.data(), y.data(), u.data(), displaced, i, dx, dy); }
};

// Raw pointers into SolverBodies for the hot loops: taken once per solve so the compiler keeps them
// in registers instead of reloading each vector's data pointer around every store.
struct BodyPtrs {
  double* x;
  double* y;
  double* z;
  const double* r;
  const double* hh;
  const std::uint8_t* grounded;
  const std::uint32_t* id;
  float* u;
  bool displaced;

  explicit BodyPtrs(SolverBodies& b)
      : x(b.x.data()), y(b.y.data()), z(b.z.data()), r(b.r.data()), hh(b.hh.data()), grounded(b.grounded.data()),
        id(b.id.data()), u(b.u.data()), displaced(b.displaced) {}

  double px(std::uint32_t i) const { return displaced_coord(x, u, displaced, i, 0); }
  double py(std::uint32_t i) const { return displaced_coord(y, u, displaced, i, 1); }
  void shift(std::uint32_t i, double dx, double dy) const { shift_body(x, y, u, displaced, i, dx, dy); }
};

// SolverPair::target of two bodies whose radii sum to rsum and whose vertical core segments are
// gap_z apart (negative when they overlap in height): upright capsules at fixed heights need
// exactly this horizontal separation, the radius sum when their cores overlap in height (the
// common case); -1 unless both are grounded (resolved in 3D).
inline double separation_target(bool both_grounded, double rsum, double gap_z) {
  if (!both_grounded) return -1.0;
  if (gap_z <= 0.0) return rsum;
  const double target2 = rsum * rsum - gap_z * gap_z;
  return target2 > 0.0 ? std::sqrt(target2) : 0.0;
}

struct SolverPair {
  std::uint32_t a, b;     // solver indices
  // Horizontal centre distance at which the pair stops overlapping, when both bodies are grounded
  // (their heights do not change within a tick, so it is computed once per tick); negative when
  // a body is airborne and the pair is resolved in 3D.
  double target;
  double share_a;         // fraction of each push that moves a; b moves 1 - share_a
  double lambda;          // accumulated push this tick [m] (warm-started from last tick)
  double depth_start;     // penetration when the solve started [m], for push events
  // Set once the pair has been pushed apart this tick: a later push of the same pair resolves a
  // conflict (a third body drove them together again) and may use the moderated share.
  std::uint32_t resolved_once;
};

// A fixed body's separating plane for one movable body (the patent's virtual plane): the body must
// satisfy dot(n, p) >= offset. Soft fixed bodies get an offset that allows part of the current
// depth to remain this tick, so the mover sinks in and is pushed out over several ticks.
struct SolverPlane {
  double nx, ny, nz;
  double offset;
  double depth_start;
  double share;           // soft share of this tick (1 for rigid)
  std::uint32_t body;     // solver index
  ObjectId fixed;
};

}  // namespace throng::detail
