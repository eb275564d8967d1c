#include "throng/scene/spawn.h"

#include <cmath>
#include <numbers>

namespace throng::scene {

std::uint64_t group_seed(std::uint64_t scene_seed, std::size_t group_index) {
  // splitmix64 finaliser: nearby (seed, index) pairs give unrelated mt19937_64 seeds.
  std::uint64_t z = scene_seed + 0x9E3779B97F4A7C15ull * (static_cast<std::uint64_t>(group_index) + 1u);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

std::vector<Vec2> spawn_positions(const SpawnShape& shape, std::uint32_t count, std::uint64_t seed) {
  std::vector<Vec2> out;
  out.reserve(count);
  std::mt19937_64 rng(seed);
  constexpr double kDegToRad = std::numbers::pi / 180.0;
  switch (shape.kind) {
    case SpawnAreaKind::disk:
      for (std::uint32_t i = 0; i < count; ++i) {
        // Draw order (u then v) is part of the format: changing it moves every body of every scene.
        const double u = uniform01(rng);
        const double v = uniform01(rng);
        const double r = shape.radius_m * std::sqrt(u);
        const double a = 2.0 * std::numbers::pi * v;
        out.push_back({shape.centre.x + r * std::cos(a), shape.centre.y + r * std::sin(a)});
      }
      break;
    case SpawnAreaKind::rect: {
      const double c = std::cos(shape.yaw_deg * kDegToRad);
      const double s = std::sin(shape.yaw_deg * kDegToRad);
      for (std::uint32_t i = 0; i < count; ++i) {
        const double lx = (2.0 * uniform01(rng) - 1.0) * shape.half_extents_m.x;
        const double ly = (2.0 * uniform01(rng) - 1.0) * shape.half_extents_m.y;
        out.push_back({shape.centre.x + (c * lx - s * ly), shape.centre.y + (s * lx + c * ly)});
      }
      break;
    }
    case SpawnAreaKind::point:
      out.assign(count, shape.centre);
      break;
    case SpawnAreaKind::line:
      for (std::uint32_t i = 0; i < count; ++i) {
        const double t = (static_cast<double>(i) + 0.5) / static_cast<double>(count);
        out.push_back({shape.from.x + t * (shape.to.x - shape.from.x), shape.from.y + t * (shape.to.y - shape.from.y)});
      }
      break;
  }
  return out;
}

double shape_area(const SpawnShape& shape) {
  switch (shape.kind) {
    case SpawnAreaKind::disk:
      return std::numbers::pi * shape.radius_m * shape.radius_m;
    case SpawnAreaKind::rect:
      return 4.0 * shape.half_extents_m.x * shape.half_extents_m.y;
    case SpawnAreaKind::point:
    case SpawnAreaKind::line:
      break;
  }
  return 0.0;
}

Vec2 shape_centre(const SpawnShape& shape) {
  if (shape.kind == SpawnAreaKind::line) return {0.5 * (shape.from.x + shape.to.x), 0.5 * (shape.from.y + shape.to.y)};
  return shape.centre;
}

}  // namespace throng::scene
