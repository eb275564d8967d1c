#include "throng/params/pair_rules.h"

#include <cmath>

#include "text_util.h"
#include "throng/params/config_error.h"

namespace throng::params {
namespace {

void check_bound_pair(double lo, double hi, const std::string& lo_path, const std::string& hi_path) {
  if (std::isnan(lo)) throw ConfigError(lo_path, "NaN is not allowed");
  if (std::isnan(hi)) throw ConfigError(hi_path, "NaN is not allowed");
  if (lo > hi) {
    throw ConfigError(hi_path, detail::format_number(hi) + " is below the minimum " + detail::format_number(lo));
  }
}

}  // namespace

bool SidePredicate::matches(const ObjectParams& o, std::uint32_t home_faction) const {
  if ((character_types & category_bit(o.character_type)) == 0u) return false;
  if ((kinds & category_bit(o.kind)) == 0u) return false;
  if ((relations & category_bit(o.relation(home_faction))) == 0u) return false;
  if (o.weight_kg < weight_min_kg || o.weight_kg > weight_max_kg) return false;
  if (fixed.has_value() && *fixed != o.fixed) return false;
  for (const ParamBound& b : ranges) {
    const double v = o.get(b.param);
    if (v < b.min || v > b.max) return false;
  }
  return true;
}

void SidePredicate::validate(const std::string& path) const {
  // An empty set can never match: almost certainly a mistake, so say so instead of a dead rule.
  if (character_types == 0u) throw ConfigError(path + ".character_type", "empty list never matches");
  if (kinds == 0u) throw ConfigError(path + ".kind", "empty list never matches");
  if (relations == 0u) throw ConfigError(path + ".faction", "empty list never matches");
  check_bound_pair(weight_min_kg, weight_max_kg, path + ".weight_at_least", path + ".weight_at_most");
  if (weight_min_kg < 0.0) throw ConfigError(path + ".weight_at_least", "must not be negative");
  for (const ParamBound& b : ranges) {
    const std::string base = path + ".ranges." + std::string(param_name(b.param));
    check_bound_pair(b.min, b.max, base + ".min", base + ".max");
  }
}

void validate_pair_rules(const std::vector<PairRule>& rules) {
  if (rules.size() > kMaxPairRules) {
    throw ConfigError("pair_rules", "at most " + std::to_string(kMaxPairRules) + " rules are supported (got " +
                                        std::to_string(rules.size()) + ")");
  }
  for (std::size_t i = 0; i < rules.size(); ++i) {
    const std::string path = "pair_rules[" + std::to_string(i) + "]";
    const PairRule& r = rules[i];
    if (r.name.empty()) throw ConfigError(path + ".name", "must not be empty");
    for (std::size_t j = 0; j < i; ++j) {
      if (rules[j].name == r.name) throw ConfigError(path + ".name", "duplicate rule name '" + r.name + "'");
    }
    r.a.validate(path + ".a");
    r.b.validate(path + ".b");
    if (std::isnan(r.share_b) || r.share_b < 0.0 || r.share_b > 1.0) {
      throw ConfigError(path + ".share_b", detail::format_number(r.share_b) + " is out of range [0, 1]");
    }
  }
}

void compute_rule_masks(const std::vector<PairRule>& rules, const ObjectParams& o, std::uint32_t home_faction,
                        std::uint32_t& lhs, std::uint32_t& rhs) {
  lhs = 0u;
  rhs = 0u;
  const std::size_t n = rules.size() < kMaxPairRules ? rules.size() : kMaxPairRules;
  for (std::size_t r = 0; r < n; ++r) {
    if (rules[r].a.matches(o, home_faction)) lhs |= 1u << r;
    if (rules[r].b.matches(o, home_faction)) rhs |= 1u << r;
  }
}

std::optional<double> match_pair_rules(const std::vector<PairRule>& rules, const ObjectParams& first,
                                       const ObjectParams& second, std::uint32_t home_faction) {
  for (const PairRule& r : rules) {
    if (r.a.matches(first, home_faction) && r.b.matches(second, home_faction)) return 1.0 - r.share_b;
    if (r.a.matches(second, home_faction) && r.b.matches(first, home_faction)) return r.share_b;
  }
  return std::nullopt;
}

}  // namespace throng::params
