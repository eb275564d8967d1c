#pragma once
// Whole-crowd passes of the tick over body columns, vectorised (body_passes.cpp): the move of a
// world without scenery, and the velocities and pushes the tick ends with.
#include <cstddef>
#include <cstdint>

namespace throng::detail {

// The share of a step kept after last tick's push (see WorldSettings::blocked_motion_carry):
// keep = 1 - carry * clamp(blocked, 0, step) / step with blocked = -(push . step) / step, written
// over step^2 so that it needs no square root and no branch (whether a body was pushed back is
// data-dependent; the branches mispredicted and the sqrt was on the path). The clamp is two
// selects on values: std::clamp returns a reference, which kept the loop from vectorising.
inline double carried_step_share(double dx, double dy, double push_x, double push_y, double carry) {
  const double step2 = dx * dx + dy * dy;
  double blocked_times_step = -(push_x * dx + push_y * dy);
  blocked_times_step = blocked_times_step < 0.0 ? 0.0 : blocked_times_step;
  blocked_times_step = step2 < blocked_times_step ? step2 : blocked_times_step;
  return 1.0 - carry * blocked_times_step / (step2 > 0.0 ? step2 : 1.0);
}

// The body columns the move reads and writes (dense order, n each).
struct MoveColumns {
  double* x; double* y; double* z;
  const double* vx; const double* vy; const double* vz;
  const double* push_x; const double* push_y;  // last tick's push
  const std::uint8_t* grounded;
  double* start_x; double* start_y; double* start_z;  // written: the positions before the move
  double* moved_x; double* moved_y;                   // written: the positions after it
  // The columns from body i on (a range of bodies for one thread).
  MoveColumns from(std::size_t i) const {
    return {x + i, y + i, z + i, vx + i, vy + i, vz + i, push_x + i, push_y + i, grounded + i,
            start_x + i, start_y + i, start_z + i, moved_x + i, moved_y + i};
  }
};

// Moves every body by its desired velocity times dt, shortened by the carry (0 = off); a grounded
// body keeps its height. Bit-identical to the scalar loop in World::Impl::move_bodies (which runs
// for worlds with scenery) with nothing hit (frac = 1).
void move_free_bodies(const MoveColumns& c, std::size_t n, double dt, double carry);

// What the tick ends with, per body: the push (final - moved) and the actual velocity
// (final - start) / dt. Bit-identical to the scalar loop it replaced.
struct FinishColumns {
  const double* x; const double* y; const double* z;  // final positions
  const double* moved_x; const double* moved_y;
  const double* start_x; const double* start_y; const double* start_z;
  double* push_x; double* push_y;
  double* ax; double* ay; double* az;
  FinishColumns from(std::size_t i) const {
    return {x + i, y + i, z + i, moved_x + i, moved_y + i, start_x + i, start_y + i, start_z + i,
            push_x + i, push_y + i, ax + i, ay + i, az + i};
  }
};
void finish_bodies(const FinishColumns& c, std::size_t n, double inv_dt);

}  // namespace throng::detail
