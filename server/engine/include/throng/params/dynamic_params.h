#pragma once
// Dynamic parameters (the patent's FIG. 9 step S15/S17: parameters that change with the game's
// progress) derived from simulation state. Pure functions: the engine owns positions, velocities,
// cameras and the ground, does any spatial counting, and writes the results into ObjectParams.
//
// Conventions: z is up; facing is planar (xy); all lengths in metres, speeds in m/s.
#include <array>
#include <cmath>
#include <span>
#include <stdexcept>

#include "throng/params/object_params.h"

namespace throng::params {

struct Facing {
  double x;
  double y;
};

// Below this horizontal speed a body keeps its previous facing: the direction of a near-zero
// velocity is noise, and a body standing still does not spin around.
inline constexpr double kMinFacingSpeed_mps = 0.05;
// Largest speed a body can report (the speed_mps range); faster readings are clamped, not
// rejected, because a teleport must not make the parameter update throw.
inline constexpr double kMaxSpeed_mps = 1000.0;

inline double speed_from_velocity(double vx, double vy, double vz) {
  const double v = std::sqrt(vx * vx + vy * vy + vz * vz);
  return v > kMaxSpeed_mps ? kMaxSpeed_mps : v;
}

inline Facing facing_from_velocity(double vx, double vy, Facing previous,
                                   double min_speed_mps = kMinFacingSpeed_mps) {
  const double h = std::sqrt(vx * vx + vy * vy);
  if (!(h > min_speed_mps) || !std::isfinite(h)) return previous;
  return {vx / h, vy / h};
}

// Distance from (x, y, z) to the nearest camera, capped at kCameraDistanceCap_m; with no camera at
// all the cap is returned (a body nobody watches counts as "far").
inline double camera_distance_m(std::span<const std::array<double, 3>> cameras, double x, double y, double z) {
  double best2 = kCameraDistanceCap_m * kCameraDistanceCap_m;
  for (const std::array<double, 3>& c : cameras) {
    const double dx = c[0] - x;
    const double dy = c[1] - y;
    const double dz = c[2] - z;
    const double d2 = dx * dx + dy * dy + dz * dz;
    if (d2 < best2) best2 = d2;
  }
  return std::sqrt(best2);
}

// Height of the body's base above the ground under it (negative = below, e.g. wading in a ditch).
inline double height_above_ground_m(double base_z, double ground_z) { return base_z - ground_z; }

// Writes speed and facing from a velocity (throws std::invalid_argument on a non-finite velocity).
inline void apply_velocity(ObjectParams& o, double vx, double vy, double vz,
                           double min_speed_for_facing_mps = kMinFacingSpeed_mps) {
  if (!std::isfinite(vx) || !std::isfinite(vy) || !std::isfinite(vz)) {
    throw std::invalid_argument("speed_mps: velocity is not finite");
  }
  o.set(Param::speed_mps, speed_from_velocity(vx, vy, vz));
  const Facing f = facing_from_velocity(vx, vy, {o.facing_x, o.facing_y}, min_speed_for_facing_mps);
  o.facing_x = f.x;
  o.facing_y = f.y;
}

}  // namespace throng::params
