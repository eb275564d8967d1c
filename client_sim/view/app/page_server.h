#pragma once
// The page side both throng-view loops share (live gateway and --log): the WebServer whose
// messages are parsed on the web thread and handed to the loop's sink, and the stderr report of
// rejected page messages. Only the message type and the sink differ between the two modes.
#include <array>
#include <cstdint>
#include <cstdio>
#include <optional>
#include <string>
#include <string_view>
#include <variant>

#include <fmt/format.h>

#include "throng/view/page_input.h"
#include "throng/view/web_server.h"

namespace throng::view {

// Starts the web server on bind:port; page messages are parsed by `parse` (text ->
// variant<Msg, InputError>) and go to sink.accept(Msg), rejections to sink.reject(InputError) and
// back to the page as an error message. Prints why and returns false when it cannot start
// (a port in use): the callers exit 1. (An out parameter: WebServer cannot move.)
template <class Msg, class Parse, class Sink>
bool open_page_server(std::optional<WebServer>& web, const std::string& bind, int port, const std::string& web_root,
                      Parse parse, Sink& sink) {
  try {
    WebServerOptions wo;
    wo.bind_address = bind;
    wo.port = static_cast<std::uint16_t>(port);
    wo.web_root = web_root;
    web.emplace(wo, [parse, &sink](std::string_view text, bool binary) -> std::optional<std::string> {
      auto parsed = binary ? std::variant<Msg, InputError>(InputError::not_text) : parse(text);
      if (auto* m = std::get_if<Msg>(&parsed)) {
        sink.accept(*m);
        return std::nullopt;
      }
      const InputError e = std::get<InputError>(parsed);
      sink.reject(e);
      return fmt::format(R"({{"type":"error","reason":"{}"}})", to_string(e));
    });
  } catch (const std::exception& e) {
    fmt::print(stderr, "throng-view: {}\n", e.what());
    web.reset();
    return false;
  }
  return true;
}

// One stderr line per kind of page message rejected since the last call.
inline void report_rejections(const std::array<std::uint64_t, kInputErrorCount>& errors,
                              std::array<std::uint64_t, kInputErrorCount>& reported) {
  for (std::size_t i = 0; i < kInputErrorCount; ++i) {
    if (errors[i] == reported[i]) continue;
    fmt::print(stderr, "throng-view: rejected {} page message(s): {} (total {})\n", errors[i] - reported[i],
               to_string(static_cast<InputError>(i)), errors[i]);
    reported[i] = errors[i];
  }
}

}  // namespace throng::view
