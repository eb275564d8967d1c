// The move (for a world without scenery) and the tick's finish as vectorised passes.
//
// Why a file of its own: it is compiled with -fno-trapping-math (server/engine/CMakeLists.txt).
// GCC otherwise keeps every floating-point select as a branch (evaluating both sides could raise
// a flag the source would not), and a loop with a branch does not vectorise. Nothing here reads
// or sets floating-point flags, and the option changes no value: the kernels compute the scalar
// formulas' bits (tests/engine/world/body_passes_test.cpp, and the golden state hash).
// As a scalar loop the move waited on one division per body and reloaded every column's address
// after each store; as a vectorised pass it takes well under half the time (docs/design/solver.md).
#include "world/body_passes.h"

namespace throng::detail {
namespace {

// The columns are parameters, not locals copied from MoveColumns: GCC honours __restrict on
// parameters, and without it every store could alias every later load.
template <bool kCarry>
void move_all(std::size_t n, double dt, double carry, double* __restrict x, double* __restrict y,
              double* __restrict z, const double* __restrict vx, const double* __restrict vy,
              const double* __restrict vz, const double* __restrict push_x, const double* __restrict push_y,
              const std::uint8_t* __restrict grounded, double* __restrict sx, double* __restrict sy,
              double* __restrict sz, double* __restrict mx, double* __restrict my) {
  for (std::size_t i = 0; i < n; ++i) {
    const double x0 = x[i], y0 = y[i], z0 = z[i];
    sx[i] = x0; sy[i] = y0; sz[i] = z0;
    double dx = vx[i] * dt, dy = vy[i] * dt;
    if constexpr (kCarry) {
      const double keep = carried_step_share(dx, dy, push_x[i], push_y[i], carry);
      dx *= keep;
      dy *= keep;
    }
    // A grounded body's vertical step is +0 exactly, as the scalar loop's select gives.
    const double vz_dt = vz[i] * dt;
    const double dz = grounded[i] != 0 ? 0.0 : vz_dt;
    const double x1 = x0 + dx, y1 = y0 + dy;
    x[i] = x1; y[i] = y1; z[i] = z0 + dz;
    mx[i] = x1; my[i] = y1;
  }
}

void finish_all(std::size_t n, double inv_dt, const double* __restrict x, const double* __restrict y,
                const double* __restrict z, const double* __restrict mx, const double* __restrict my,
                const double* __restrict sx, const double* __restrict sy, const double* __restrict sz,
                double* __restrict push_x, double* __restrict push_y, double* __restrict ax, double* __restrict ay,
                double* __restrict az) {
  for (std::size_t i = 0; i < n; ++i) {
    push_x[i] = x[i] - mx[i];
    push_y[i] = y[i] - my[i];
    ax[i] = (x[i] - sx[i]) * inv_dt;
    ay[i] = (y[i] - sy[i]) * inv_dt;
    az[i] = (z[i] - sz[i]) * inv_dt;
  }
}

}  // namespace

void finish_bodies(const FinishColumns& c, std::size_t n, double inv_dt) {
  finish_all(n, inv_dt, c.x, c.y, c.z, c.moved_x, c.moved_y, c.start_x, c.start_y, c.start_z, c.push_x, c.push_y, c.ax, c.ay,
             c.az);
}

void move_free_bodies(const MoveColumns& c, std::size_t n, double dt, double carry) {
  auto* move = carry > 0.0 ? &move_all<true> : &move_all<false>;
  move(n, dt, carry, c.x, c.y, c.z, c.vx, c.vy, c.vz, c.push_x, c.push_y, c.grounded, c.start_x, c.start_y, c.start_z,
       c.moved_x, c.moved_y);
}

}  // namespace throng::detail
