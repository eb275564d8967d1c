#pragma once
// Dense structure-of-arrays storage of the movable bodies. Index = dense index; destroying a body
// moves the last body into its place (deterministic, keeps the arrays packed). What every tick
// touches lives here; the parameter records (cold, rarely written) live beside it in World::Impl.
#include <cstdint>
#include <vector>

#include "throng/core/object_id.h"

namespace throng::detail {

// Last tick's accumulated push of one pair, kept by the body with the smaller id.
struct WarmEntry {
  std::uint32_t partner;  // ObjectId value
  double lambda;
};
inline constexpr std::uint32_t kWarmSlots = 8;

struct BodyStore {
  std::vector<double> x, y, z;        // centre [m]
  std::vector<double> vx, vy, vz;     // desired velocity [m/s] (an input)
  std::vector<double> ax, ay, az;     // actual velocity over the last tick [m/s]
  std::vector<double> px, py;         // solver push of the last tick (final - moved) [m]
  std::vector<double> r, hh;          // radius, half height of the core segment [m]
  std::vector<std::uint8_t> grounded;
  std::vector<ObjectId> id;
  // Push coefficients from the policy, refreshed when parameters change.
  std::vector<double> resistance;
  std::vector<std::uint32_t> rule_lhs, rule_rhs, group, mask;
  std::vector<std::uint8_t> coeff_dirty;
  std::vector<std::int8_t> morale_level;  // -1 low, 0 normal, +1 high
  std::vector<WarmEntry> warm;            // kWarmSlots per body
  std::vector<std::uint8_t> warm_count;

  std::size_t size() const { return x.size(); }

  template <class F>
  void for_each_column(F&& f) {
    f(x); f(y); f(z); f(vx); f(vy); f(vz); f(ax); f(ay); f(az); f(px); f(py); f(r); f(hh); f(grounded); f(id);
    f(resistance); f(rule_lhs); f(rule_rhs); f(group); f(mask); f(coeff_dirty); f(morale_level); f(warm_count);
  }
  void push_back_default() {
    for_each_column([](auto& col) { col.emplace_back(); });
    warm.resize(warm.size() + kWarmSlots);
  }
  // Moves the last body into slot i and shrinks by one.
  void swap_remove(std::size_t i) {
    const std::size_t last = size() - 1;
    for_each_column([&](auto& col) { col[i] = col[last]; col.pop_back(); });
    for (std::uint32_t k = 0; k < kWarmSlots; ++k) warm[i * kWarmSlots + k] = warm[last * kWarmSlots + k];
    warm.resize(warm.size() - kWarmSlots);
  }
};

}  // namespace throng::detail
