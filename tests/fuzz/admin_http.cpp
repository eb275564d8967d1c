// The admin endpoint (/healthz, /readyz, /metrics): HTTP/1.1 requests parsed as its sessions parse
// them (Beast, same header/body limits), then routed (Routes::handle). Several requests may be
// pipelined in one input. Input: the bytes a client sends.
#include <cstdint>
#include <cstdlib>
#include <optional>

#include <boost/beast/core/flat_buffer.hpp>

#include "routes.h"
#include "throng/admin/admin_server.h"
#include "throng/admin/metrics.h"

using namespace throng;
namespace http = boost::beast::http;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static admin::MetricsRegistry registry;
  static const admin::AdminServer::ReadinessCheck ready = [] { return true; };
  static const admin::AdminServerOptions limits;
  const admin::Routes routes{registry, ready};
  boost::asio::const_buffer rest(data, size);
  for (int i = 0; i < 8 && rest.size() > 0; ++i) {
    http::request_parser<http::string_body> parser;
    parser.header_limit(static_cast<std::uint32_t>(limits.header_limit));
    parser.body_limit(limits.body_limit);
    parser.eager(true);
    boost::beast::error_code ec;
    const std::size_t used = parser.put(rest, ec);
    if (!ec && !parser.is_done()) parser.put_eof(ec);
    if (ec) {
      (void)admin::error_response(http::status::bad_request, 11);
      return 0;  // the session answers and closes
    }
    const admin::Response res = routes.handle(parser.get());
    if (res.result_int() < 200 || res.result_int() > 599) std::abort();
    if (used == 0) return 0;
    rest += used;
  }
  return 0;
}
