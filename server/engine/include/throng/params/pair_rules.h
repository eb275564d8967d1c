#pragma once
// Pair rules: the patent's "combination of parameters" example — a player character pushes an NPC
// out 100%, but an NPC that is heavy (or more) only 80% — expressed as data.
//
// A rule has a predicate for side a and one for side b, and the share of the penetration depth
// that side b is pushed out (side a takes 1 - share_b). Rules match in either orientation and the
// first matching rule in list order wins.
//
// Why predicates are per side and only read the object's own parameters: then "does this object
// satisfy rule r's side a / side b" is a per-object bit that can be cached with the object's push
// coefficients, and the per-pair test is two ANDs (see PushPolicy::share_a). Dynamic parameters
// used in predicates (speed, height, camera distance) are as fresh as the cached coefficients.
#include <bit>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "throng/params/categories.h"
#include "throng/params/object_params.h"

namespace throng::params {

// Rule masks are 32-bit, one bit per rule.
inline constexpr std::size_t kMaxPairRules = 32;

struct ParamBound {
  Param param;
  double min = -std::numeric_limits<double>::infinity();  // inclusive
  double max = std::numeric_limits<double>::infinity();   // inclusive
};

struct SidePredicate {
  static constexpr std::uint32_t kAny = 0xFFFFFFFFu;
  // Bit sets over the enum ordinals (bit 1 << value); kAny = no constraint.
  std::uint32_t character_types = kAny;
  std::uint32_t kinds = kAny;
  std::uint32_t relations = kAny;  // FactionRelation, relative to the policy's home faction
  double weight_min_kg = 0.0;                                       // "weight_at_least", inclusive
  double weight_max_kg = std::numeric_limits<double>::infinity();   // "weight_at_most", inclusive
  // Fixed bodies never reach the rules (a fixed body always takes 0%), so only `fixed: false` is
  // a useful constraint; true is accepted for symmetry and simply never matches a pair.
  std::optional<bool> fixed;
  std::vector<ParamBound> ranges;  // any numeric parameter, all must hold

  bool matches(const ObjectParams& o, std::uint32_t home_faction) const;
  // Throws ConfigError naming "<path>.<field>".
  void validate(const std::string& path) const;
};

template <typename Enum>
constexpr std::uint32_t category_bit(Enum e) {
  return 1u << static_cast<std::uint32_t>(e);
}

struct PairRule {
  std::string name;
  SidePredicate a;
  SidePredicate b;
  double share_b = 1.0;  // [0, 1]: share of the penetration depth side b is pushed out
};

// Throws ConfigError naming "pair_rules[i]..." (also for more than kMaxPairRules rules).
void validate_pair_rules(const std::vector<PairRule>& rules);

// Bit r of lhs: object satisfies rules[r].a; bit r of rhs: it satisfies rules[r].b.
void compute_rule_masks(const std::vector<PairRule>& rules, const ObjectParams& o, std::uint32_t home_faction,
                        std::uint32_t& lhs, std::uint32_t& rhs);

// The pair-rule outcome from cached masks: first rule r (lowest bit) matching either orientation.
// Returns the share of `first`, or nullopt when no rule matches. If rule r matches both ways,
// `first` is taken as side a.
inline std::optional<double> resolve_rule_masks(const std::vector<PairRule>& rules, std::uint32_t first_lhs,
                                                std::uint32_t first_rhs, std::uint32_t second_lhs,
                                                std::uint32_t second_rhs) {
  const std::uint32_t first_as_a = first_lhs & second_rhs;
  const std::uint32_t first_as_b = second_lhs & first_rhs;
  const std::uint32_t any = first_as_a | first_as_b;
  if (any == 0u) return std::nullopt;
  const int r = std::countr_zero(any);  // lowest set bit = first rule in list order
  // Masks from another policy (e.g. cached across a policy reload) must not index past the list.
  if (static_cast<std::size_t>(r) >= rules.size()) return std::nullopt;
  const std::uint32_t lowest = 1u << r;
  const double share_b = rules[static_cast<std::size_t>(r)].share_b;
  return (first_as_a & lowest) != 0u ? 1.0 - share_b : share_b;
}

// Reference implementation straight from the predicates (no masks), for tests and tools.
std::optional<double> match_pair_rules(const std::vector<PairRule>& rules, const ObjectParams& first,
                                       const ObjectParams& second, std::uint32_t home_faction);

}  // namespace throng::params
