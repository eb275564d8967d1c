#include "throng/scene/scale.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "throng/core/object_id.h"
#include "throng/scene/scene_error.h"

namespace throng::scene {
namespace {

Vec2 scaled(Vec2 v, double s) { return {v.x * s, v.y * s}; }
Vec3 scaled_xy(Vec3 v, double s) { return {v.x * s, v.y * s, v.z}; }
double scaled_size(double v, double s) { return std::max(v * s, std::min(v, kMinScaledScenery_m)); }

void scale_shape(SpawnShape& sh, double s) {
  sh.centre = scaled(sh.centre, s);
  sh.radius_m *= s;
  sh.half_extents_m = scaled(sh.half_extents_m, s);
  if (sh.kind == SpawnAreaKind::line) {
    // Midpoint moves with the map (s), the rank's length keeps its spacing (s^2).
    const Vec2 mid{0.5 * (sh.from.x + sh.to.x), 0.5 * (sh.from.y + sh.to.y)};
    const Vec2 half{0.5 * (sh.to.x - sh.from.x), 0.5 * (sh.to.y - sh.from.y)};
    const Vec2 m = scaled(mid, s);
    const Vec2 h = scaled(half, s * s);
    sh.from = {m.x - h.x, m.y - h.y};
    sh.to = {m.x + h.x, m.y + h.y};
  }
}

void scale_scenery(Scenery& x, double s) {
  x.centre = scaled_xy(x.centre, s);
  x.half_extents_m.x = scaled_size(x.half_extents_m.x, s);
  x.half_extents_m.y = scaled_size(x.half_extents_m.y, s);
  x.radius_m = scaled_size(x.radius_m, s);
  for (auto& v : x.vertices) v = scaled_xy(v, s);
}

}  // namespace

std::vector<std::uint32_t> proportional_counts(const std::vector<std::uint32_t>& weights, std::uint64_t total) {
  const std::uint64_t sum = std::accumulate(weights.begin(), weights.end(), std::uint64_t{0});
  std::vector<std::uint32_t> out(weights.size(), 0);
  if (sum == 0) return out;
  std::vector<std::uint64_t> remainder(weights.size());
  std::uint64_t given = 0;
  for (std::size_t i = 0; i < weights.size(); ++i) {
    // Exact integer arithmetic: weights <= 2^22 and total <= 2^22, so the product fits easily.
    const std::uint64_t p = static_cast<std::uint64_t>(weights[i]) * total;
    out[i] = static_cast<std::uint32_t>(p / sum);
    remainder[i] = p % sum;
    given += out[i];
  }
  std::vector<std::size_t> idx(weights.size());
  std::iota(idx.begin(), idx.end(), std::size_t{0});
  std::stable_sort(idx.begin(), idx.end(), [&](std::size_t a, std::size_t b) { return remainder[a] > remainder[b]; });
  for (std::size_t k = 0; given < total; ++k, ++given) ++out[idx[k]];
  return out;
}

SceneDef scale_scene(const SceneDef& scene, std::uint64_t agents) {
  const std::uint64_t old_total = scene.agent_count();
  if (agents == 0) throw SceneError("agents", "must be >= 1");
  if (agents > ObjectId::kMaxIndex) throw SceneError("agents", "must be <= " + std::to_string(ObjectId::kMaxIndex));
  if (old_total == 0) throw SceneError("spawns", "the scene has no bodies to scale");
  SceneDef out = scene;
  if (agents == old_total) return out;
  std::vector<std::uint32_t> weights;
  for (const auto& g : scene.spawns) weights.push_back(g.count);
  const auto counts = proportional_counts(weights, agents);
  const double s = std::sqrt(static_cast<double>(agents) / static_cast<double>(old_total));
  for (std::size_t i = 0; i < out.spawns.size(); ++i) {
    auto& g = out.spawns[i];
    g.count = counts[i];
    scale_shape(g.shape, s);
    g.behavior.target = scaled(g.behavior.target, s);
  }
  if (scene.scale_scenery) {
    for (auto& x : out.scenery) scale_scenery(x, s);
  }
  return out;
}

}  // namespace throng::scene
