#include "throng/view/page_input.h"

#include <cmath>
#include <numbers>

#include <nlohmann/json.hpp>

#include "throng/protocol/messages.h"

namespace throng::view {

const char* to_string(InputError e) {
  switch (e) {
    case InputError::too_large: return "too_large";
    case InputError::not_text: return "not_text";
    case InputError::not_json: return "not_json";
    case InputError::not_object: return "not_object";
    case InputError::unknown_type: return "unknown_type";
    case InputError::bad_type: return "bad_type";
    case InputError::non_finite: return "non_finite";
    case InputError::out_of_range: return "out_of_range";
    case InputError::bad_actions: return "bad_actions";
    case InputError::count_: break;
  }
  return "unknown";
}

namespace {

constexpr double kMoveSlack = 1e-3;  // the server allows the same
constexpr double kMaxFacing = 4.0 * std::numbers::pi;

// A number field: nullopt result = absent; error when present but not a finite number.
std::variant<std::optional<double>, InputError> number(const nlohmann::json& j, const char* key) {
  const auto it = j.find(key);
  if (it == j.end()) return std::optional<double>{};
  if (!it->is_number()) return InputError::bad_type;
  const double v = it->get<double>();
  if (!std::isfinite(v)) return InputError::non_finite;
  return std::optional<double>{v};
}

}  // namespace

std::variant<PageInput, InputError> parse_page_message(std::string_view text) {
  if (text.size() > kMaxPageMessageBytes) return InputError::too_large;
  const nlohmann::json j = nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (j.is_discarded()) return InputError::not_json;  // also numbers that overflow a double
  if (!j.is_object()) return InputError::not_object;
  const auto type = j.find("type");
  if (type == j.end() || !type->is_string() || type->get_ref<const std::string&>() != "input")
    return InputError::unknown_type;

  double v[5] = {0, 0, 0, 0, 0};
  bool present[5] = {false, false, false, false, false};
  const char* keys[5] = {"move_x", "move_y", "facing", "camera_x", "camera_y"};
  for (int i = 0; i < 5; ++i) {
    auto r = number(j, keys[i]);
    if (auto* e = std::get_if<InputError>(&r)) return *e;
    const auto& value = std::get<std::optional<double>>(r);
    present[i] = value.has_value();
    v[i] = value.value_or(0.0);
  }
  PageInput in;
  const double mx = v[0], my = v[1], facing = v[2];
  if (std::abs(mx) > 1.0 || std::abs(my) > 1.0 || std::hypot(mx, my) > 1.0 + kMoveSlack) return InputError::out_of_range;
  if (std::abs(facing) > kMaxFacing) return InputError::out_of_range;
  if (present[3] != present[4]) return InputError::out_of_range;
  if (present[3] && (std::abs(v[3]) > kMaxCameraM || std::abs(v[4]) > kMaxCameraM)) return InputError::out_of_range;

  if (const auto a = j.find("actions"); a != j.end()) {
    if (!a->is_number()) return InputError::bad_type;
    if (!a->is_number_integer()) return InputError::bad_actions;  // fractional
    if (a->is_number_unsigned()) {
      const std::uint64_t bits = a->get<std::uint64_t>();
      if ((bits & ~static_cast<std::uint64_t>(protocol::kKnownActions)) != 0) return InputError::bad_actions;
      in.actions = static_cast<std::uint32_t>(bits);
    } else if (a->get<std::int64_t>() != 0) {
      return InputError::bad_actions;  // negative
    }
  }

  in.move_x = static_cast<float>(mx);
  in.move_y = static_cast<float>(my);
  // Wrap to [-pi, pi]; the float rounding of pi itself stays inside the server's slack.
  double f = std::remainder(facing, 2.0 * std::numbers::pi);
  in.facing_rad = static_cast<float>(f);
  if (present[3]) {
    in.camera_x = static_cast<float>(v[3]);
    in.camera_y = static_cast<float>(v[4]);
  }
  return in;
}

}  // namespace throng::view
