#include "throng/scene/scene_def.h"

namespace throng::scene {
namespace {

// WorldSettings has no operator==; compared here field by field. A field added there and not here
// only makes round-trip tests weaker, never wrong — the state-hash round-trip test still covers it.
bool settings_equal(const WorldSettings& a, const WorldSettings& b) {
  return a.dt_s == b.dt_s && a.iterations == b.iterations && a.contact_margin_m == b.contact_margin_m &&
         a.converged_pen_over_radius == b.converged_pen_over_radius && a.warm_start == b.warm_start &&
         a.max_candidates_per_body == b.max_candidates_per_body && a.cell_size_m == b.cell_size_m &&
         a.morale_radius_m == b.morale_radius_m && a.morale_refresh_ticks == b.morale_refresh_ticks;
}

}  // namespace

bool SceneDef::operator==(const SceneDef& o) const {
  return name == o.name && description == o.description && ticks == o.ticks && seed == o.seed &&
         settings_equal(settings, o.settings) && params == o.params && policy == o.policy && scenery == o.scenery &&
         spawns == o.spawns;
}

}  // namespace throng::scene
