// The admin endpoint's routing as a pure function of one parsed request: no sockets, no threads,
// so the connection code only moves bytes and every status decision lives here.
#pragma once

#include <boost/beast/http.hpp>

#include "throng/admin/admin_server.h"
#include "throng/admin/metrics.h"

namespace throng::admin {

namespace http = boost::beast::http;

using Request = http::request<http::string_body>;
using Response = http::response<http::string_body>;

inline constexpr const char* metrics_content_type = "text/plain; version=0.0.4; charset=utf-8";

struct Routes {
  MetricsRegistry& registry;
  const AdminServer::ReadinessCheck& ready;
  const std::function<std::string()>* degraded = nullptr;  // AdminServerOptions::degraded

  Response handle(const Request& req) const;
};

// For requests the parser rejected (no Request to route): a plain-text error that closes the
// connection, since the stream position after a parse error cannot be trusted.
Response error_response(http::status status, unsigned version);

}  // namespace throng::admin
