#include "routes.h"

#include <exception>
#include <string_view>

namespace throng::admin {
namespace {

constexpr const char* text_content_type = "text/plain; charset=utf-8";

Response text(http::status status, const Request& req, std::string body, const char* content_type = text_content_type) {
  Response res{status, req.version()};
  res.set(http::field::server, "throng-admin");
  res.set(http::field::content_type, content_type);
  // Health and metrics must reflect "now"; a caching proxy in between would hide an outage.
  res.set(http::field::cache_control, "no-store");
  res.keep_alive(req.keep_alive());
  res.body() = std::move(body);
  res.prepare_payload();
  return res;
}

std::string degraded_reason(const std::function<std::string()>* degraded) {
  if (degraded == nullptr || !*degraded) return {};
  try {
    return (*degraded)();
  } catch (...) {
    return {};
  }
}

bool is_ready(const AdminServer::ReadinessCheck& ready) {
  if (!ready) return true;
  try {
    return ready();
  } catch (const std::exception&) {
    return false;  // a check that cannot answer is not a "yes"
  }
}

}  // namespace

Response Routes::handle(const Request& req) const {
  // Query strings are ignored: a scraper may add them, none of our endpoints reads them.
  std::string_view path(req.target().data(), req.target().size());
  path = path.substr(0, path.find('?'));

  const bool known = path == "/healthz" || path == "/readyz" || path == "/metrics";
  if (!known) return text(http::status::not_found, req, "not found\n");
  if (req.method() != http::verb::get) {
    // A HEAD response must not carry a body, or the next response on the connection is garbled.
    Response res = text(http::status::method_not_allowed, req, req.method() == http::verb::head ? "" : "method not allowed\n");
    res.set(http::field::allow, "GET");
    return res;
  }
  if (path == "/healthz") return text(http::status::ok, req, "ok\n");
  if (path == "/readyz") {
    if (!is_ready(ready)) return text(http::status::service_unavailable, req, "not ready\n");
    const std::string why = degraded_reason(degraded);
    return text(http::status::ok, req, why.empty() ? "ready\n" : "degraded: " + why + "\n");
  }
  return text(http::status::ok, req, registry.render(), metrics_content_type);
}

Response error_response(http::status status, unsigned version) {
  Response res{status, version};
  res.set(http::field::server, "throng-admin");
  res.set(http::field::content_type, text_content_type);
  res.keep_alive(false);
  res.body() = std::string(http::obsolete_reason(status)) + "\n";
  res.prepare_payload();
  return res;
}

}  // namespace throng::admin
