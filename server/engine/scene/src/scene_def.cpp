#include "throng/scene/scene_def.h"

#include "world/settings_fields.h"

namespace throng::scene {
namespace {

// WorldSettings has no operator==; compared over the fields a scene can set (settings_fields.h).
bool settings_equal(const WorldSettings& a, const WorldSettings& b) {
  for (const auto& f : throng::detail::kSettingFields) {
    switch (f.type) {
      case throng::detail::SettingField::Type::f64: if (a.*f.f64 != b.*f.f64) return false; break;
      case throng::detail::SettingField::Type::u32: if (a.*f.u32 != b.*f.u32) return false; break;
      case throng::detail::SettingField::Type::boolean: if (a.*f.boolean != b.*f.boolean) return false; break;
    }
  }
  return true;
}

}  // namespace

bool SceneDef::operator==(const SceneDef& o) const {
  return name == o.name && description == o.description && ticks == o.ticks && seed == o.seed &&
         scale_scenery == o.scale_scenery &&
         settings_equal(settings, o.settings) && params == o.params && policy == o.policy && scenery == o.scenery &&
         spawns == o.spawns;
}

}  // namespace throng::scene
