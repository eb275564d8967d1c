#pragma once
// What the page sends, and how the gateway checks it before anything reaches the server.
//
// The page is a client like any other and is never trusted: every message is parsed and range
// checked here, on the web thread, and only a fully valid `input` becomes a PageInput. Anything
// else is an InputError, counted by reason and answered with an `error` message; it never turns
// into a Command.
//
// Accepted message (JSON text, at most kMaxPageMessageBytes):
//   {"type":"input", "move_x":mx, "move_y":my, "facing":f, "actions":a, "camera_x":cx, "camera_y":cy}
//  - move_x, move_y: finite numbers, each in [-1, 1], |(mx, my)| <= 1 (+1e-3 slack); fraction of
//    the entity's max speed. Missing = 0.
//  - facing: finite radians with |f| <= 4 pi, wrapped to [-pi, pi]. Missing = 0.
//  - actions: a non-negative integer made only of protocol::kKnownActions bits. Missing = 0.
//  - camera_x, camera_y: both or neither; finite, |v| <= kMaxCameraM (the server's own limit).
//    Neither = the camera follows the controlled entity.
//  Unknown extra keys are ignored (forward compatible); a known key of the wrong type is bad_type.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string_view>
#include <variant>

namespace throng::view {

inline constexpr std::size_t kMaxPageMessageBytes = 4096;
inline constexpr double kMaxCameraM = 10000.0;

struct PageInput {
  float move_x = 0, move_y = 0;
  float facing_rad = 0;  // in [-pi, pi]
  std::uint32_t actions = 0;
  std::optional<float> camera_x, camera_y;  // both set or both empty
  bool panned() const { return camera_x.has_value(); }
};

enum class InputError : std::uint8_t {
  too_large,      // over kMaxPageMessageBytes
  not_text,       // a binary WebSocket message
  not_json,       // does not parse
  not_object,     // parses but is not a JSON object
  unknown_type,   // "type" missing or not "input"
  bad_type,       // a known field of the wrong JSON type (string, null, array ...)
  non_finite,     // a number that overflowed to +-inf (JSON has no NaN)
  out_of_range,   // move, facing or camera beyond the limits above, or only one camera coordinate
  bad_actions,    // negative, fractional or unknown action bits
  count_
};
inline constexpr std::size_t kInputErrorCount = static_cast<std::size_t>(InputError::count_);
const char* to_string(InputError e);

// Parses and validates one page message.
std::variant<PageInput, InputError> parse_page_message(std::string_view text);

}  // namespace throng::view
