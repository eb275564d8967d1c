// PushPolicy: validation, per-object coefficients, and the rare branches of share_a (fixed bodies,
// pair-dependent terms, priority mode). The common branch is inline in push_policy.h.
#include "throng/params/push_policy.h"

#include <algorithm>
#include <array>
#include <stdexcept>

#include "text_util.h"
#include "throng/params/config_error.h"

namespace throng::params {
namespace {

constexpr std::array<std::string_view, 3> kModeNames = {"ratio", "priority", "half"};

constexpr std::array<std::string_view, kTermInputCount> kTermNames = {
    "kind",     "importance",         "size_m",         "weight_kg",        "equipment_level", "speed_mps",
    "height_above_ground_m", "camera_distance_m", "hp", "level",            "faction",         "group_member_count",
    "group_strength", "group_importance", "facing",     "morale",
};
static_assert(static_cast<std::size_t>(TermInput::morale) + 1 == kTermInputCount, "kTermInputCount is stale");

constexpr double kMaxTermWeight = 1000.0;
constexpr double kMaxTermScale = 1.0e9;

std::string term_path(std::size_t i, const char* field) {
  return "terms[" + std::to_string(i) + "]." + field;
}

void validate_term(const Term& t, std::size_t i) {
  if (static_cast<std::size_t>(t.input) >= kTermInputCount) throw ConfigError(term_path(i, "param"), "unknown term");
  if (std::isnan(t.weight) || t.weight < 0.0 || t.weight > kMaxTermWeight) {
    throw ConfigError(term_path(i, "weight"), detail::format_number(t.weight) + " is out of range [0, " +
                                                  detail::format_number(kMaxTermWeight) + "]");
  }
  if (std::isnan(t.scale) || !(t.scale > 0.0) || t.scale > kMaxTermScale) {
    throw ConfigError(term_path(i, "scale"), detail::format_number(t.scale) + " is out of range (0, " +
                                                 detail::format_number(kMaxTermScale) + "]");
  }
}

// The per-object value a static term reads.
double static_term_value(TermInput t, const ObjectParams& o, const Group* g, std::uint32_t home_faction) {
  switch (t) {
    case TermInput::kind: return static_cast<double>(o.kind);
    case TermInput::importance: return o.importance;
    case TermInput::size_m: return o.size_m;
    case TermInput::weight_kg: return o.weight_kg;
    case TermInput::equipment_level: return o.equipment_level;
    case TermInput::speed_mps: return o.speed_mps;
    case TermInput::height_above_ground_m: return o.height_above_ground_m;
    case TermInput::camera_distance_m: return o.camera_distance_m;
    case TermInput::hp: return o.hp;
    case TermInput::level: return o.level;
    case TermInput::faction: return faction_relation_value(o.relation(home_faction));
    case TermInput::group_member_count: return g != nullptr ? static_cast<double>(g->member_count) : 0.0;
    case TermInput::group_strength: return g != nullptr ? g->strength : 0.0;
    case TermInput::group_importance: return g != nullptr ? g->importance : 0.0;
    case TermInput::facing:
    case TermInput::morale: break;  // pair-dependent, never compiled into static terms
  }
  return 0.0;
}

}  // namespace

std::string_view push_mode_name(PushMode m) {
  const auto i = static_cast<std::size_t>(m);
  return i < kModeNames.size() ? kModeNames[i] : std::string_view("?");
}

std::optional<PushMode> parse_push_mode(std::string_view name) {
  for (std::size_t i = 0; i < kModeNames.size(); ++i) {
    if (kModeNames[i] == name) return static_cast<PushMode>(i);
  }
  return std::nullopt;
}

std::string_view term_input_name(TermInput t) {
  const auto i = static_cast<std::size_t>(t);
  return i < kTermNames.size() ? kTermNames[i] : std::string_view("?");
}

std::optional<TermInput> parse_term_input(std::string_view name) {
  for (std::size_t i = 0; i < kTermNames.size(); ++i) {
    if (kTermNames[i] == name) return static_cast<TermInput>(i);
  }
  if (name == "weight") return TermInput::weight_kg;
  return std::nullopt;
}

std::string term_input_names_list() {
  std::string out;
  for (std::string_view n : kTermNames) out += (out.empty() ? "" : ", ") + std::string(n);
  return out;
}

PushPolicy::PushPolicy() = default;

PushPolicy::PushPolicy(PushMode mode, std::vector<Term> terms, std::vector<PairRule> rules, std::uint32_t home_faction)
    : mode_(mode), terms_(std::move(terms)), rules_(std::move(rules)), home_faction_(home_faction) {
  if (static_cast<std::size_t>(mode_) >= kModeNames.size()) throw ConfigError("mode", "unknown mode");
  // Faction 0 is neutral by definition, so it cannot be the side the players are on.
  if (home_faction_ < 1 || home_faction_ > kMaxFaction) {
    throw ConfigError("home_faction", std::to_string(home_faction_) + " is out of range [1, " +
                                          std::to_string(kMaxFaction) + "]");
  }
  for (std::size_t i = 0; i < terms_.size(); ++i) {
    const Term& t = terms_[i];
    validate_term(t, i);
    // A repeated term is a copy-paste slip more often than an intent; one weight per input.
    for (std::size_t j = 0; j < i; ++j) {
      if (terms_[j].input == t.input) {
        throw ConfigError(term_path(i, "param"), "duplicate term '" + std::string(term_input_name(t.input)) + "'");
      }
    }
    const double sign = t.invert ? -1.0 : 1.0;
    if (t.input == TermInput::facing) {
      facing_coef_ = t.weight * sign / t.scale;
    } else if (t.input == TermInput::morale) {
      morale_coef_ = t.weight * sign / t.scale;
    } else {
      static_terms_.push_back({t.input, t.weight * sign, t.scale});
    }
  }
  validate_pair_rules(rules_);
}

namespace {
constexpr double kTermValueLimit = 1e100;
}  // namespace

double PushPolicy::static_score(const ObjectParams& o, const GroupTable& groups) const {
  const Group* g = groups.find(o.group_id);
  double s = 0.0;
  for (const CompiledTerm& t : static_terms_) {
    // Each input over its scale is bounded far beyond any real value (kTermValueLimit), so that
    // two unbounded inputs (a height or camera distance of 1e300 m) sum to a finite score instead
    // of inf - inf = NaN; real inputs never come near the bound, so their bits are unchanged.
    const double v =
        std::clamp(static_term_value(t.input, o, g, home_faction_) / t.scale, -kTermValueLimit, kTermValueLimit);
    s += t.signed_weight * v;
  }
  if (std::isnan(s)) {
    throw std::invalid_argument("object " + std::to_string(o.object_id) + "/" + std::to_string(o.collision_id) +
                                ": parameters give a NaN push score (call ObjectParams::validate)");
  }
  return std::clamp(s, -kScoreClamp, kScoreClamp);
}

PushCoefficients PushPolicy::coefficients(const ObjectParams& o, const GroupTable& groups) const {
  // A fixed body never moves and never reaches the rules: +inf resistance is the marker share_a
  // tests first (and it makes share_a_fast give the fixed side 0 if ever called by mistake).
  if (o.fixed) return {kFixedResistance, 0u, 0u};
  PushCoefficients c{std::exp(static_score(o, groups)), 0u, 0u};
  compute_rule_masks(rules_, o, home_faction_, c.rule_mask_lhs, c.rule_mask_rhs);
  return c;
}

double PushPolicy::fixed_share(double resistance_a, double resistance_b) {
  if (resistance_a == kFixedResistance && resistance_b == kFixedResistance) {
    throw std::logic_error("PushPolicy::share_a: both bodies are fixed; fixed-fixed pairs are never resolved");
  }
  return resistance_a == kFixedResistance ? 0.0 : 1.0;
}

// Score difference s_a - s_b contributed by the pair-dependent terms. Clamped to twice the score
// clamp so exp() stays finite; the static part is already within [-20, 20] per body.
double PushPolicy::pair_score_delta(const PairView& a, const PairView& b, const GroupTable* groups) const {
  if (a.params == nullptr || b.params == nullptr) {
    throw std::logic_error("PushPolicy::share_a: this policy has pair-dependent terms; PairView::params is required");
  }
  double delta = 0.0;
  if (facing_coef_ != 0.0) {
    // Facing is planar (xy), so only the horizontal part of the contact direction counts.
    const double fa = a.params->facing_x * a.to_other_x + a.params->facing_y * a.to_other_y;
    const double fb = b.params->facing_x * b.to_other_x + b.params->facing_y * b.to_other_y;
    delta += facing_coef_ * (fa - fb);
  }
  if (morale_coef_ != 0.0) {
    if (groups == nullptr) {
      throw std::logic_error("PushPolicy::share_a: this policy has a morale term; pass the GroupTable");
    }
    delta += morale_coef_ * (groups->morale(a.params->group_id) - groups->morale(b.params->group_id));
  }
  return std::clamp(delta, -2.0 * kScoreClamp, 2.0 * kScoreClamp);
}

double PushPolicy::priority_share(double ma, double mb, std::uint32_t id_a, std::uint32_t id_b) const {
  if (ma < mb) return 1.0;  // a has the lower priority: it moves the whole depth
  if (ma > mb) return 0.0;
  // Deterministic tie-break on the caller's ids: the lower id moves. Equal ids (a caller bug)
  // split evenly rather than favouring an argument order.
  if (id_a < id_b) return 1.0;
  if (id_a > id_b) return 0.0;
  return 0.5;
}

}  // namespace throng::params
