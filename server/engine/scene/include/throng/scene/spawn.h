#pragma once
// Where a spawn group's bodies start: deterministic horizontal positions from a seed.
//
// Why our own uniform mapping: std::uniform_real_distribution's output is implementation-defined
// (libstdc++ and libc++ differ), and a scene must place the same bodies on every platform that
// runs the same binary *and* on every standard library. mt19937_64's raw bits are specified, so
// uniform01() takes the top 53 bits — exactly representable, in [0, 1).
#include <cstdint>
#include <random>
#include <vector>

#include "throng/scene/scene_def.h"

namespace throng::scene {

inline double uniform01(std::mt19937_64& rng) {
  return static_cast<double>(rng() >> 11) * (1.0 / 9007199254740992.0);  // 2^-53
}

// Independent stream per spawn group (splitmix64 of seed and index), so adding a group at the end
// of a scene does not move the bodies of the groups before it.
std::uint64_t group_seed(std::uint64_t scene_seed, std::size_t group_index);

// count positions inside shape: disk and rect uniform in area (disk: r = R * sqrt(u)), point all
// at the centre, line evenly spaced from..to (segment midpoints, so count = 1 lands mid-line).
std::vector<Vec2> spawn_positions(const SpawnShape& shape, std::uint32_t count, std::uint64_t seed);

// Area of the shape in m^2 (0 for point and line): what --agents scaling keeps per body.
double shape_area(const SpawnShape& shape);

// Centre of the shape (line: its midpoint); march-to-target takes its direction from here.
Vec2 shape_centre(const SpawnShape& shape);

}  // namespace throng::scene
