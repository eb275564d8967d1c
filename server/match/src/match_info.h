#pragma once
// MatchInfo from the scene and the built world: scenery shapes, the roster of movable bodies
// (structure-of-arrays, in the world's dense order at construction), archetype names, world
// bounds, and the parameter table / push policy hashes.
//
// Hashes: FNV-1a 64 over a canonical text (not XXH3: the engine links xxhash privately, and FNV is
// a dozen lines with no dependency). The policy text is generated from the PushPolicy object
// itself (mode, home faction, terms, rules with every predicate field; numbers in shortest
// round-trip form), so the same policy hashes the same whether it came from the built-ins, a file,
// a scene's inline object or an operator's JSON with different whitespace. The table text is the
// defaults, every archetype (name order), the groups and the morale thresholds, followed by the
// source document's text when the table came from a file or an inline object (that also covers
// per-object overrides, which the table cannot list).
#include <cstdint>
#include <span>
#include <string>
#include <string_view>

#include "throng/core/object_id.h"
#include "throng/match/match_config.h"
#include "throng/params/object_params.h"
#include "throng/params/param_table.h"
#include "throng/params/push_policy.h"
#include "throng/protocol/messages.h"
#include "throng/scene/scene_def.h"

namespace throng {
class World;
}

namespace throng::match {

inline constexpr std::uint64_t kFnvOffset = 14695981039346656037ull;
std::uint64_t fnv1a64(std::string_view text, std::uint64_t h = kFnvOffset);

std::string canonical_policy_text(const params::PushPolicy& policy);
std::string canonical_table_text(const params::ParamTable& table, const scene::DocumentSource& source);
inline std::uint64_t policy_hash(const params::PushPolicy& p) { return fnv1a64(canonical_policy_text(p)); }

// World bounds margin around the bodies and the scenery.
inline constexpr double kWorldBoundsMargin_m = 10.0;

struct MatchInfoSource {
  const scene::SceneDef& scene;
  const params::ParamTable& table;
  const World& world;
  std::span<const ObjectId> scenery_ids;  // scene.scenery order
  std::span<const ObjectId> body_ids;     // creation order (scene.spawns order)
  const MatchConfig& config;
  const std::string& match_id;
};

protocol::MatchInfo build_match_info(const MatchInfoSource& src);

// After an operator changed a body's parameters: the roster's faction / character type.
void update_roster_entry(protocol::Roster& roster, std::size_t roster_index, const params::ObjectParams& p);

}  // namespace throng::match
