// AdminServer: the operator-facing HTTP/1.1 endpoint (Boost.Beast) on its own thread and its own
// io_context, so a slow scraper or a stuck client can never delay the game tick.
//
//   GET /healthz  200 "ok\n"                while the process runs (liveness)
//   GET /readyz   200 "ready\n" / 503 "not ready\n" from the readiness callback, or 200
//                 "degraded: REASON\n" while ready but options.degraded names a reason
//   GET /metrics  200 registry.render(), Content-Type text/plain; version=0.0.4; charset=utf-8
//   other path 404, other method 405, unparsable request 400, oversized header 431
//
// The constructor binds and starts serving; stop() or the destructor closes every connection and
// joins the thread. Boost stays out of this header (pimpl) so including it is cheap.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "throng/admin/metrics.h"

namespace throng::admin {

struct AdminServerOptions {
  std::string bind_address = "127.0.0.1";  // loopback by default: metrics are not for the internet
  std::uint16_t port = 0;                  // 0 = ephemeral; AdminServer::port() tells which
  // A connection must deliver a whole request (and take a whole response) within this, and an idle
  // keep-alive connection is closed after it: a stuck client cannot pin a socket.
  std::chrono::milliseconds io_timeout{std::chrono::seconds(10)};
  std::size_t header_limit = 8 * 1024;  // bytes; larger request headers get 431
  std::size_t body_limit = 8 * 1024;    // bytes; GETs carry none, so anything big is abuse
  std::size_t max_connections = 64;     // further connections are closed at accept
  // Called like the readiness check (admin thread, thread-safe, quick). A non-empty reason makes a
  // ready server answer /readyz with 200 "degraded: REASON": it still serves its players (an
  // orchestrator must not pull it) but has lost something an operator must see, such as its match
  // log. Empty function or empty reason: not degraded; a throwing one counts as not degraded.
  std::function<std::string()> degraded;
};

class AdminServer {
 public:
  // Called on the admin thread for every /readyz, so it must be thread-safe and quick (typically
  // an atomic load). An empty function means "always ready"; a throwing one means "not ready".
  using ReadinessCheck = std::function<bool()>;

  // Binds and starts serving. Throws std::runtime_error
  // "admin: cannot listen on ADDRESS:PORT: REASON" (e.g. "address in use") when it cannot listen.
  // The registry must outlive the server.
  AdminServer(MetricsRegistry& registry, ReadinessCheck ready, AdminServerOptions options = {});
  ~AdminServer();  // stop()
  AdminServer(const AdminServer&) = delete;
  AdminServer& operator=(const AdminServer&) = delete;

  // The bound port (the ephemeral one when options.port was 0). Still valid after stop().
  std::uint16_t port() const noexcept;
  const std::string& bind_address() const noexcept;

  // Closes the listener and every connection, joins the thread. Idempotent; returns promptly even
  // with clients connected (in-flight responses are dropped). Call it from the owner's thread,
  // never from the readiness callback (the admin thread cannot join itself).
  void stop();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace throng::admin
