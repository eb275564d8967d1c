// What a page sends throng-view over its WebSocket: live-mode input (parse_page_message) and
// log-mode control (parse_log_message). Neither throws: every message is a value or an
// InputError. Input: the message text.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string_view>
#include <variant>

#include "throng/protocol/messages.h"
#include "throng/view/log_control.h"
#include "throng/view/page_input.h"

using namespace throng;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  const auto live = view::parse_page_message(text);
  if (const auto* in = std::get_if<view::PageInput>(&live)) {
    // The documented guarantees of a valid input.
    if (!std::isfinite(in->move_x) || !std::isfinite(in->move_y) || std::hypot(in->move_x, in->move_y) > 1.0f + 2e-3f) std::abort();
    if (!(std::fabs(in->facing_rad) <= 3.1416f)) std::abort();
    if ((in->actions & ~protocol::kKnownActions) != 0) std::abort();
    if (in->camera_x.has_value() != in->camera_y.has_value()) std::abort();
  }
  const auto log = view::parse_log_message(text);
  if (const auto* c = std::get_if<view::LogCommand>(&log)) {
    if (c->kind == view::LogCommand::Kind::speed && !(c->speed >= view::kMinSpeed && c->speed <= view::kMaxSpeed)) std::abort();
    if (c->kind == view::LogCommand::Kind::seek && !std::isfinite(c->tick)) std::abort();
  }
  return 0;
}
