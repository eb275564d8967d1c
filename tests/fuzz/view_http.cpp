// throng-view's page server: HTTP/1.1 requests parsed as its sessions parse them (Beast, same
// limits), then routed (route_request: assets, 404/405, WebSocket upgrade or refusal). Input: a
// byte choosing the embedded assets or a web root folder (the page's own sources), then the bytes
// a browser sends.
#include <cstdint>
#include <cstdlib>
#include <string>

#include "web_routes.h"

using namespace throng;
namespace http = boost::beast::http;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  static const std::string web_root = THRONG_SOURCE_DIR "/client_sim/view/web";
  const std::string& root = (data[0] & 1) ? web_root : std::string();
  boost::asio::const_buffer rest(data + 1, size - 1);
  for (int i = 0; i < 8 && rest.size() > 0; ++i) {
    http::request_parser<http::string_body> parser;
    parser.header_limit(view::kHttpHeaderLimit);
    parser.body_limit(view::kHttpBodyLimit);
    parser.eager(true);
    boost::beast::error_code ec;
    const std::size_t used = parser.put(rest, ec);
    if (!ec && !parser.is_done()) parser.put_eof(ec);
    if (ec) return 0;  // the session answers 400 (or drops the connection) and closes
    const auto res = view::route_request(parser.get(), root);
    if (res && (res->result_int() < 200 || res->result_int() > 599)) std::abort();
    if (used == 0) return 0;
    rest += used;
  }
  return 0;
}
