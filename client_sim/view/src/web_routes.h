#pragma once
// The page server's HTTP routing as a pure function of one parsed request: no sockets, no threads,
// so the session code (throng::http) only moves bytes, and the routing is tested and fuzzed
// (tests/fuzz/view_http.cpp) without a network. Routes: see web_server.h.
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

#include <boost/beast/http.hpp>

namespace throng::view {

namespace http = boost::beast::http;
using HttpRequest = http::request<http::string_body>;
using HttpResponse = http::response<http::string_body>;

// Limits of one request as the HTTP sessions parse it (http::request_parser).
inline constexpr std::size_t kHttpHeaderLimit = 8 * 1024;
inline constexpr std::size_t kHttpBodyLimit = 4 * 1024;

// A plain-text response (Server: throng-view).
HttpResponse text_response(http::status status, std::string body, unsigned version, bool keep_alive);

// The answer to one request, or nullopt for an accepted WebSocket upgrade (GET /ws with Upgrade and
// no foreign Origin): the session then hands its socket to a WebSocket session. web_root empty =
// the embedded assets, else files of that folder (flat names only).
std::optional<HttpResponse> route_request(const HttpRequest& req, const std::string& web_root);

}  // namespace throng::view
