// Operator parameter changes (the patent's S15/S17 "parameters changed during play").
//
// Two forms:
//  - policy_json non-empty: the whole push policy is replaced (parse_push_policy; entity must be 0
//    and param empty). A parse or validation error is replied with the parser's message.
//  - otherwise: parameter `param` (a name of params::Param, or the alias "weight") of object
//    `entity` (a movable body or a fixed scenery object) is set to `value` through the engine's
//    validated setter; its std::invalid_argument message is the reply's error.
// A rejected update leaves the world exactly as it was. An applied one bumps param_version and
// republishes the match info (the roster / scenery / policy hash may have changed).
//
// On an entity a client controls, an applied character_type / importance / weight_kg takes effect
// at once and is also the value the entity keeps when the client leaves (instead of the NPC value
// saved at takeover); a held brace keeps doubling the new weight.
#include <exception>
#include <stdexcept>

#include <fmt/format.h>

#include "match_impl.h"
#include "match_info.h"
#include "throng/params/object_params.h"
#include "throng/params/params_json.h"
#include "throng/params/push_policy.h"
#include "throng/world/world.h"

namespace throng::match {

void Match::Impl::apply_params(std::uint64_t tick, Outbox& out) {
  for (const protocol::ParamUpdate& u : inputs.params) {
    protocol::ParamReply reply = apply_param_update(u, tick);
    if (reply.ok) {
      ++report.param_updates_applied;
      out.match_info_changed = true;
    } else {
      ++report.param_updates_rejected;
    }
    out.param_replies.push_back(std::move(reply));
  }
}

protocol::ParamReply Match::Impl::apply_param_update(const protocol::ParamUpdate& u, std::uint64_t tick) {
  protocol::ParamReply reply;
  reply.request_id = u.request_id;
  reply.tick = tick;
  reply.param_version = info.param_version;
  const auto fail = [&](std::string why) {
    reply.ok = false;
    reply.error = std::move(why);
    return reply;
  };

  World& w = world();
  if (!u.policy_json.empty()) {
    if (u.entity != 0 || !u.param.empty()) {
      return fail("policy_json replaces the whole push policy: entity must be 0 and param empty");
    }
    try {
      const params::PushPolicy policy = params::parse_push_policy(u.policy_json, "policy_json");
      w.set_policy(policy);
      info.push_policy_hash = policy_hash(policy);
    } catch (const std::exception& e) {
      return fail(e.what());
    }
  } else {
    const ObjectId id{u.entity};
    const bool body = w.is_body(id);
    if (!body && !w.is_fixed(id)) return fail(fmt::format("unknown entity {}", u.entity));
    const std::optional<params::Param> param = params::try_parse_param(u.param);
    if (!param) return fail(fmt::format("unknown parameter '{}' (known: {})", u.param, params::param_names_list()));
    const std::uint32_t dense = body ? dense_of(id) : kNoDense;
    ClientRecord* owner = dense != kNoDense && controller[dense] != 0 ? clients.find(controller[dense]) : nullptr;
    try {
      if (owner != nullptr && (*param == params::Param::character_type || *param == params::Param::importance ||
                               *param == params::Param::weight_kg)) {
        if (auto why = params::check_param_value(*param, u.value)) {
          throw std::invalid_argument(fmt::format("{}: {}", params::param_name(*param), *why));
        }
        if (*param == params::Param::character_type) {
          w.set_param(id, *param, u.value);
          owner->npc_character_type = u.value;
        } else if (*param == params::Param::importance) {
          w.set_param(id, *param, u.value);
          owner->npc_importance = u.value;
        } else {
          w.set_param(id, *param, owner->bracing ? braced_weight(u.value) : u.value);
          owner->base_weight_kg = u.value;
        }
      } else {
        w.set_param(id, *param, u.value);
      }
    } catch (const std::invalid_argument& e) {
      return fail(e.what());
    }
    if (body) {
      if (*param == params::Param::faction || *param == params::Param::group_id) {
        ai.reassign(w, dense);
        if (owner != nullptr) owner->faction = w.params(id).faction;
      }
      const std::uint32_t k = roster_of_slot[id.index()];
      update_roster_entry(info.roster, k, w.params(id));
      if (owner != nullptr) info.roster.character_type[k] = static_cast<std::uint8_t>(owner->npc_character_type);
    } else if (*param == params::Param::softness) {
      for (protocol::SceneryShape& s : info.scenery) {
        if (s.id == id.value) s.softness = static_cast<float>(w.params(id).softness);
      }
    }
  }
  ++info.param_version;
  reply.ok = true;
  reply.param_version = info.param_version;
  return reply;
}

}  // namespace throng::match
