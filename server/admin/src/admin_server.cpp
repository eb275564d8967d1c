// AdminServer: the admin routes (routes.h) served by a throng::http listener, which owns the
// socket side (bind, accept, limits, timeouts) on its own thread, so the game tick never waits on
// a socket.
#include "throng/admin/admin_server.h"

#include <optional>
#include <stdexcept>

#include "routes.h"
#include "throng/http/listener.h"

namespace throng::admin {

namespace {

throng::http::ListenerOptions listener_options(const AdminServerOptions& o) {
  throng::http::ListenerOptions l;
  l.name = "admin";
  l.bind_address = o.bind_address;
  l.port = o.port;
  l.max_connections = o.max_connections;
  l.io_timeout = o.io_timeout;
  l.header_limit = o.header_limit;
  l.body_limit = o.body_limit;
  return l;
}

}  // namespace

struct AdminServer::Impl {
  Impl(MetricsRegistry& registry, ReadinessCheck ready_check, AdminServerOptions opts)
      : ready(std::move(ready_check)),
        options(std::move(opts)),
        routes{registry, ready, &options.degraded},
        listener(start(listener_options(options), routes)) {}

  // The listener's errors name the address; ours also say which endpoint could not start.
  static std::unique_ptr<throng::http::HttpListener> start(throng::http::ListenerOptions o, const Routes& routes) {
    throng::http::HttpHandlers handlers;
    handlers.route = [&routes](const Request& req) -> std::optional<Response> { return routes.handle(req); };
    handlers.refuse = [](http::status status) { return error_response(status, 11); };
    try {
      return std::make_unique<throng::http::HttpListener>(std::move(o), std::move(handlers));
    } catch (const std::runtime_error& e) {
      throw std::runtime_error(std::string("admin: ") + e.what());
    }
  }

  ReadinessCheck ready;
  AdminServerOptions options;
  Routes routes;
  // Last, so it stops (joining its thread) before the state its handlers read goes away.
  std::unique_ptr<throng::http::HttpListener> listener;
};

AdminServer::AdminServer(MetricsRegistry& registry, ReadinessCheck ready, AdminServerOptions options)
    : impl_(std::make_unique<Impl>(registry, std::move(ready), std::move(options))) {}

AdminServer::~AdminServer() { stop(); }

std::uint16_t AdminServer::port() const noexcept { return impl_->listener->port(); }

const std::string& AdminServer::bind_address() const noexcept { return impl_->options.bind_address; }

void AdminServer::stop() { impl_->listener->stop(); }

}  // namespace throng::admin
