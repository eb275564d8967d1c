// Parameter metadata (names, ranges) and the validated setters of ObjectParams.
#include "throng/params/object_params.h"

#include <array>
#include <charconv>
#include <cmath>
#include <stdexcept>

#include "text_util.h"

namespace throng::params {
namespace {

struct ParamInfo {
  Param param;
  std::string_view name;
  ParamRange range;
};

constexpr double kTwoPi = 6.283185307179586;
constexpr double kMaxU32 = 4294967295.0;

// One row per Param, in enum order (checked below). Ranges are generous on purpose: they exist to
// catch typos and unit mistakes (a weight of 8e4 "because it was grams"), not to design the game.
constexpr std::array<ParamInfo, kParamCount> kInfo = {{
    {Param::kind, "kind", {0.0, kKindCount - 1.0, true}},
    {Param::importance, "importance", {0.0, 10.0, false}},
    {Param::size_m, "size_m", {0.001, 1000.0, false}},
    {Param::weight_kg, "weight_kg", {0.001, 1.0e6, false}},
    {Param::equipment_level, "equipment_level", {0.0, 10.0, false}},
    {Param::softness, "softness", {0.0, 1.0, false}},
    {Param::speed_mps, "speed_mps", {0.0, 1000.0, false}},
    {Param::facing_yaw_rad, "facing_yaw_rad", {-kTwoPi, kTwoPi, false}},
    {Param::fixed, "fixed", {0.0, 1.0, true}},
    {Param::faction, "faction", {0.0, double(kMaxFaction), true}},
    {Param::character_type, "character_type", {0.0, kCharacterTypeCount - 1.0, true}},
    {Param::height_above_ground_m, "height_above_ground_m", {-1000.0, 10000.0, false}},
    {Param::group_id, "group_id", {0.0, double(kMaxGroupId), true}},
    {Param::camera_distance_m, "camera_distance_m", {0.0, kCameraDistanceCap_m, false}},
    {Param::hp, "hp", {0.0, 1.0e9, false}},
    {Param::level, "level", {0.0, 1.0e6, false}},
    {Param::collision_group, "collision_group", {0.0, kMaxU32, true}},
    {Param::collision_mask, "collision_mask", {0.0, kMaxU32, true}},
}};

constexpr bool info_in_enum_order() {
  for (std::size_t i = 0; i < kInfo.size(); ++i) {
    if (static_cast<std::size_t>(kInfo[i].param) != i) return false;
  }
  return true;
}
static_assert(info_in_enum_order(), "kInfo rows must follow the Param enum order");
static_assert(static_cast<std::size_t>(Param::collision_mask) + 1 == kParamCount, "kParamCount is stale");

const ParamInfo& info(Param p) { return kInfo[static_cast<std::size_t>(p)]; }

[[noreturn]] void throw_field(Param p, const std::string& why) {
  throw std::invalid_argument(std::string(param_name(p)) + ": " + why);
}

[[noreturn]] void fail_text(Param p, std::string_view text, std::string_view expected) {
  throw_field(p, "cannot read '" + std::string(text) + "' (expected " + std::string(expected) + ")");
}

}  // namespace

std::string_view param_name(Param p) {
  const auto i = static_cast<std::size_t>(p);
  return i < kInfo.size() ? kInfo[i].name : std::string_view("?");
}

ParamRange param_range(Param p) { return info(p).range; }

std::optional<Param> try_parse_param(std::string_view name) {
  for (const ParamInfo& row : kInfo) {
    if (row.name == name) return row.param;
  }
  // "weight" is what designers write (and what the patent calls it); the unit lives in the field name.
  if (name == "weight") return Param::weight_kg;
  return std::nullopt;
}

std::string param_names_list() {
  std::string out;
  for (const ParamInfo& row : kInfo) {
    if (!out.empty()) out += ", ";
    out += row.name;
  }
  return out;
}

Param parse_param(std::string_view name) {
  if (auto p = try_parse_param(name)) return *p;
  throw std::invalid_argument("unknown parameter '" + std::string(name) + "' (known: " + param_names_list() + ")");
}

std::optional<std::string> check_param_value(Param p, double value) {
  if (std::isnan(value)) return std::string("NaN is not allowed");
  if (std::isinf(value)) return std::string("infinite value is not allowed");
  const ParamRange r = info(p).range;
  if (value < r.min || value > r.max) {
    return detail::format_number(value) + " is out of range [" + detail::format_number(r.min) + ", " +
           detail::format_number(r.max) + "]";
  }
  if (r.integral && std::floor(value) != value) {
    return detail::format_number(value) + " is not a whole number";
  }
  return std::nullopt;
}

void ObjectParams::set(Param p, double value) {
  if (auto why = check_param_value(p, value)) throw_field(p, *why);
  switch (p) {
    case Param::kind: kind = static_cast<Kind>(value); break;
    case Param::importance: importance = value; break;
    case Param::size_m: size_m = value; break;
    case Param::weight_kg: weight_kg = value; break;
    case Param::equipment_level: equipment_level = value; break;
    case Param::softness: softness = value; break;
    case Param::speed_mps: speed_mps = value; break;
    case Param::facing_yaw_rad:
      facing_x = std::cos(value);
      facing_y = std::sin(value);
      break;
    case Param::fixed: fixed = value != 0.0; break;
    case Param::faction: faction = static_cast<std::uint8_t>(value); break;
    case Param::character_type: character_type = static_cast<CharacterType>(value); break;
    case Param::height_above_ground_m: height_above_ground_m = value; break;
    case Param::group_id: group_id = static_cast<std::uint32_t>(value); break;
    case Param::camera_distance_m: camera_distance_m = value; break;
    case Param::hp: hp = value; break;
    case Param::level: level = value; break;
    case Param::collision_group: collision_group = static_cast<std::uint32_t>(value); break;
    case Param::collision_mask: collision_mask = static_cast<std::uint32_t>(value); break;
  }
}

void ObjectParams::set(std::string_view field, double value) { set(parse_param(field), value); }

void ObjectParams::set(std::string_view field, std::string_view text) {
  const Param p = parse_param(field);
  switch (p) {
    case Param::kind:
      if (auto k = parse_kind(text)) return set(p, static_cast<double>(*k));
      fail_text(p, text, kind_names_list());
    case Param::character_type:
      if (auto t = parse_character_type(text)) return set(p, static_cast<double>(*t));
      fail_text(p, text, character_type_names_list());
    case Param::fixed:
      if (text == "true") return set(p, 1.0);
      if (text == "false") return set(p, 0.0);
      fail_text(p, text, "true or false");
    case Param::weight_kg:
      if (auto c = parse_weight_class(text)) return set(p, weight_class_kg(*c));
      break;  // else a number of kilograms
    default: break;
  }
  double value = 0.0;
  const char* first = text.data();
  const char* last = text.data() + text.size();
  const auto res = std::from_chars(first, last, value);
  if (res.ec != std::errc() || res.ptr != last) {
    fail_text(p, text,
              p == Param::weight_kg ? "a number of kg or one of " + std::string(weight_class_names_list()) : "a number");
  }
  set(p, value);
}

void ObjectParams::set_facing(double x, double y) {
  if (!std::isfinite(x) || !std::isfinite(y)) throw_field(Param::facing_yaw_rad, "facing vector is not finite");
  const double len = std::sqrt(x * x + y * y);
  // A zero vector has no direction; callers keep the previous facing instead (dynamic_params.h).
  if (!(len > 1e-9)) throw_field(Param::facing_yaw_rad, "facing vector has zero length");
  facing_x = x / len;
  facing_y = y / len;
}

double ObjectParams::get(Param p) const {
  switch (p) {
    case Param::kind: return static_cast<double>(kind);
    case Param::importance: return importance;
    case Param::size_m: return size_m;
    case Param::weight_kg: return weight_kg;
    case Param::equipment_level: return equipment_level;
    case Param::softness: return softness;
    case Param::speed_mps: return speed_mps;
    case Param::facing_yaw_rad: return std::atan2(facing_y, facing_x);
    case Param::fixed: return fixed ? 1.0 : 0.0;
    case Param::faction: return static_cast<double>(faction);
    case Param::character_type: return static_cast<double>(character_type);
    case Param::height_above_ground_m: return height_above_ground_m;
    case Param::group_id: return static_cast<double>(group_id);
    case Param::camera_distance_m: return camera_distance_m;
    case Param::hp: return hp;
    case Param::level: return level;
    case Param::collision_group: return static_cast<double>(collision_group);
    case Param::collision_mask: return static_cast<double>(collision_mask);
  }
  return 0.0;
}

void ObjectParams::validate() const {
  for (const ParamInfo& row : kInfo) {
    if (auto why = check_param_value(row.param, get(row.param))) throw_field(row.param, *why);
  }
  // Facing must stay a unit vector: the pair-time facing term relies on it being a cosine.
  const double len2 = facing_x * facing_x + facing_y * facing_y;
  if (!std::isfinite(len2) || std::fabs(len2 - 1.0) > 1e-6) {
    throw_field(Param::facing_yaw_rad, "facing vector (facing_x, facing_y) is not a unit vector");
  }
}

}  // namespace throng::params
