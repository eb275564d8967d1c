#pragma once
// Small builders shared by the params tests (not part of the engine).
#include <string>

#include "throng/params/config_error.h"
#include "throng/params/push_policy.h"

namespace throng::params::test {

inline ObjectParams npc(double weight_kg = 80.0) {
  ObjectParams o;
  o.character_type = CharacterType::npc;
  o.weight_kg = weight_kg;
  return o;
}

inline ObjectParams player() {
  ObjectParams o;
  o.character_type = CharacterType::player;
  return o;
}

inline PairView view(const PushPolicy& policy, const ObjectParams& o, const GroupTable& groups, std::uint32_t id,
                     double to_other_x = 1.0, double to_other_y = 0.0, double to_other_z = 0.0) {
  return PairView{policy.coefficients(o, groups), &o, id, to_other_x, to_other_y, to_other_z};
}

// Share of a's penetration depth for a contact along +x from a to b.
inline double share_of_a(const PushPolicy& policy, const ObjectParams& a, const ObjectParams& b,
                         const GroupTable& groups = GroupTable{}) {
  return policy.share_a(view(policy, a, groups, 1, 1.0, 0.0, 0.0), view(policy, b, groups, 2, -1.0, 0.0, 0.0), groups);
}

// A ratio policy with a single term.
inline PushPolicy single_term(TermInput input, double weight, double scale, bool invert = false,
                              PushMode mode = PushMode::ratio) {
  return PushPolicy(mode, {Term{input, weight, scale, invert}}, {});
}

// Runs f and returns the ConfigError it throws (fails the test if it throws nothing else).
template <typename F>
ConfigError config_error_of(F&& f) {
  try {
    f();
  } catch (const ConfigError& e) {
    return e;
  }
  return ConfigError("<nothing thrown>", "");
}

}  // namespace throng::params::test
