#pragma once
// PushPolicy: how the penetration depth of two overlapping bodies is split between them
// (the patent's push-out ratio, FIG. 7 and FIG. 9 step S9).
//
// Modes:
//   ratio    — the patent: each body gets a share strictly inside (0, 1), computed from weighted
//              parameters. Score s_i = sum_k weight_k * sign_k * value_k / scale_k (sign = -1 when
//              the term is inverted), clamped to [-20, 20]; resistance m_i = exp(s_i);
//              share_a = m_b / (m_a + m_b). Higher score = harder to push.
//   priority — conventional baseline 1: the body with the lower score (same terms) moves 100%;
//              ties: the lower caller-supplied id moves.
//   half     — conventional baseline 2: 50/50.
// In every mode the order is: fixed bodies, then pair rules, then the mode.
//
// Why exp of a weighted sum: only the score difference matters (share_a = 1 / (1 + e^(s_a - s_b))),
// so adding a term shifts shares smoothly and never flips a pair abruptly, and a ratio of
// resistances is what the patent draws (FIG. 7: 4:1). The clamp keeps exp finite; a final clamp of
// the share to [kMinShare, 1 - kMinShare] keeps both shares strictly inside (0, 1) in double
// precision (1 - 4e-18 would otherwise round to exactly 1).
//
// Hot path: the engine calls coefficients() once per object when its parameters change and
// share_a() once per contact pair per tick. Everything per-object (static terms, rule predicates,
// fixed) is folded into PushCoefficients; share_a() touches ObjectParams only when the policy has
// pair-dependent terms.
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "throng/params/group_table.h"
#include "throng/params/object_params.h"
#include "throng/params/pair_rules.h"

namespace throng::params {

enum class PushMode : std::uint8_t { ratio = 0, priority = 1, half = 2 };
std::string_view push_mode_name(PushMode m);
std::optional<PushMode> parse_push_mode(std::string_view name);

// What a term reads. Most are the object's own parameters; a few are derived:
//   faction            — relation to the home faction: ally +1, neutral 0, enemy -1. Per object
//                        (only the difference of two bodies matters, and ally-vs-ally cancels
//                        anyway), so it is folded into the cached resistance: no per-pair cost.
//   group_*            — attributes of the object's group (0 without a group). Cached with the
//                        object: recompute coefficients of the members when these change.
//   facing  (pair)     — dot(facing, unit direction toward the other body), in [-1, 1]:
//                        +1 = facing the other (braced), -1 = showing it its back.
//   morale  (pair)     — the group's current morale (base + level offset), read live from the
//                        GroupTable at pair time so a morale change needs no recomputation.
enum class TermInput : std::uint8_t {
  kind,
  importance,
  size_m,
  weight_kg,
  equipment_level,
  speed_mps,
  height_above_ground_m,
  camera_distance_m,
  hp,
  level,
  faction,
  group_member_count,
  group_strength,
  group_importance,
  facing,
  morale,
};
inline constexpr std::size_t kTermInputCount = 16;

std::string_view term_input_name(TermInput t);
// Accepts the canonical names plus "weight" for weight_kg.
std::optional<TermInput> parse_term_input(std::string_view name);
std::string term_input_names_list();
constexpr bool is_pair_dependent(TermInput t) { return t == TermInput::facing || t == TermInput::morale; }

struct Term {
  TermInput input = TermInput::weight_kg;
  double weight = 1.0;  // [0, 1000]
  double scale = 1.0;   // (0, 1e9]: the parameter's "unit" — value / scale is what gets weighted
  bool invert = false;  // the patent's "opposite result": a larger value makes the body easier to push
};

// Belongs to the policy that computed it: recompute every object's coefficients after swapping the
// policy (rule bits index that policy's rule list).
struct PushCoefficients {
  double resistance;            // exp(clamped static score); +infinity for a fixed body
  std::uint32_t rule_mask_lhs;  // bit r: satisfies pair_rules[r].a
  std::uint32_t rule_mask_rhs;  // bit r: satisfies pair_rules[r].b
};

// One side of a contact pair as the engine sees it.
struct PairView {
  PushCoefficients coefficients;
  const ObjectParams* params;  // read only if has_pair_dependent_terms(); may be null otherwise
  std::uint32_t id;            // the engine's object id value; breaks priority-mode ties
  // Unit direction from THIS body toward the other one (so b's is the negation of a's).
  double to_other_x;
  double to_other_y;
  double to_other_z;
};

inline constexpr double kScoreClamp = 20.0;
inline constexpr double kMinShare = 1e-9;
inline constexpr double kMaxShare = 1.0 - kMinShare;
inline constexpr double kFixedResistance = std::numeric_limits<double>::infinity();
inline constexpr std::uint32_t kDefaultHomeFaction = 1;

// Share of the penetration depth by which body a is pushed out, for two movable bodies with
// finite positive resistances (no rules, no pair terms). share_b = 1 - share_a.
inline double share_a_fast(double resistance_a, double resistance_b) {
  const double s = resistance_b / (resistance_a + resistance_b);
  return s < kMinShare ? kMinShare : (s > kMaxShare ? kMaxShare : s);
}

class PushPolicy {
 public:
  // Ratio mode, no terms, no rules: every movable pair splits 50/50.
  PushPolicy();
  // Validates everything; throws ConfigError whose path matches the JSON layout
  // ("terms[2].scale", "pair_rules[0].share_b", "home_faction").
  PushPolicy(PushMode mode, std::vector<Term> terms, std::vector<PairRule> rules,
             std::uint32_t home_faction = kDefaultHomeFaction);
  // Reading one from its JSON file format: throng/params/params_json.h (target throng::scene).

  PushMode mode() const { return mode_; }
  const std::vector<Term>& terms() const { return terms_; }
  const std::vector<PairRule>& rules() const { return rules_; }
  std::uint32_t home_faction() const { return home_faction_; }
  bool has_pair_dependent_terms() const { return facing_coef_ != 0.0 || morale_coef_ != 0.0; }
  bool uses_morale() const { return morale_coef_ != 0.0; }

  // The clamped static score (the per-object part of s_i). Throws std::invalid_argument if the
  // parameters produce NaN (only possible if fields were written around the validated setters).
  double static_score(const ObjectParams& o, const GroupTable& groups) const;
  PushCoefficients coefficients(const ObjectParams& o, const GroupTable& groups) const;

  // Share of the penetration depth that a is pushed out; b gets 1 - share. Movable vs fixed
  // returns 1 for a rigid fixed body — if the fixed body is soft (softness > 0), the engine
  // multiplies by soft_push_share() (soft_push.h), which needs the depth. Fixed vs fixed throws
  // std::logic_error: such pairs must be filtered out before.
  // The two-argument form is for policies without a morale term (it throws std::logic_error
  // otherwise, since morale lives in the GroupTable).
  double share_a(const PairView& a, const PairView& b) const { return share_impl(a, b, nullptr); }
  double share_a(const PairView& a, const PairView& b, const GroupTable& groups) const {
    return share_impl(a, b, &groups);
  }
  static double share_a_fast(double resistance_a, double resistance_b) {
    return params::share_a_fast(resistance_a, resistance_b);
  }

 private:
  struct CompiledTerm {
    TermInput input;
    double signed_weight;
    double scale;
  };

  double share_impl(const PairView& a, const PairView& b, const GroupTable* groups) const;
  static double fixed_share(double resistance_a, double resistance_b);  // throws for fixed-fixed
  double pair_score_delta(const PairView& a, const PairView& b, const GroupTable* groups) const;
  double priority_share(double ma, double mb, std::uint32_t id_a, std::uint32_t id_b) const;

  PushMode mode_ = PushMode::ratio;
  std::vector<Term> terms_;
  std::vector<PairRule> rules_;
  std::uint32_t home_faction_ = kDefaultHomeFaction;
  std::vector<CompiledTerm> static_terms_;
  // Pair terms compiled to one coefficient each (weight * sign / scale); 0 = absent.
  double facing_coef_ = 0.0;
  double morale_coef_ = 0.0;
};

inline double PushPolicy::share_impl(const PairView& a, const PairView& b, const GroupTable* groups) const {
  const double ra = a.coefficients.resistance;
  const double rb = b.coefficients.resistance;
  if (ra == kFixedResistance || rb == kFixedResistance) return fixed_share(ra, rb);
  // Rule masks are zero when there are no rules, so this costs two ANDs on the common path.
  if (auto ruled = resolve_rule_masks(rules_, a.coefficients.rule_mask_lhs, a.coefficients.rule_mask_rhs,
                                      b.coefficients.rule_mask_lhs, b.coefficients.rule_mask_rhs)) {
    return *ruled;
  }
  if (mode_ == PushMode::half) return 0.5;
  double ma = ra;
  if (has_pair_dependent_terms()) ma = ra * std::exp(pair_score_delta(a, b, groups));
  if (mode_ == PushMode::priority) return priority_share(ma, rb, a.id, b.id);
  return params::share_a_fast(ma, rb);
}

}  // namespace throng::params
