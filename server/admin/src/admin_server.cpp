// AdminServer: listener, accept loop and the admin thread. Everything network-side runs on one
// io_context driven by one thread that this class owns, so no handler ever needs a lock and the
// game tick never waits on a socket.
#include "throng/admin/admin_server.h"

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/steady_timer.hpp>
#include <cstdio>
#include <exception>
#include <stdexcept>
#include <thread>

#include "http_session.h"
#include "routes.h"

namespace throng::admin {

namespace asio = boost::asio;
using tcp = asio::ip::tcp;

struct AdminServer::Impl {
  Impl(MetricsRegistry& registry, ReadinessCheck ready_check, AdminServerOptions opts)
      : ready(std::move(ready_check)),
        options(std::move(opts)),
        config{Routes{registry, ready, &options.degraded}, options.io_timeout, options.header_limit, options.body_limit} {}

  void listen();
  void accept();
  void run();
  void stop();

  ReadinessCheck ready;
  AdminServerOptions options;
  SessionConfig config;
  std::uint16_t port = 0;
  // Declared before the io_context: sessions still pending when it is destroyed decrement this.
  std::size_t open_connections = 0;
  // Held by pointer so stop() can destroy them, in this order: I/O objects, then the io_context,
  // whose destruction frees the sessions its pending handlers own (closing their sockets).
  std::unique_ptr<asio::io_context> io;
  std::unique_ptr<tcp::acceptor> acceptor;
  std::unique_ptr<asio::steady_timer> accept_retry;
  std::thread thread;
};

namespace {

std::string endpoint_text(const std::string& address, std::uint16_t port) {
  const bool v6 = address.find(':') != std::string::npos;
  return (v6 ? "[" + address + "]" : address) + ":" + std::to_string(port);
}

std::string reason_text(const boost::system::error_code& ec) {
  if (ec == asio::error::address_in_use) return "address in use";
  if (ec == asio::error::access_denied) return "permission denied";
  if (ec == boost::system::errc::address_not_available) return "address not available on this host";
  return ec.message();
}

}  // namespace

void AdminServer::Impl::listen() {
  boost::system::error_code ec;
  const auto address = asio::ip::make_address(options.bind_address, ec);
  if (ec) throw std::runtime_error("admin: invalid bind address \"" + options.bind_address + "\"");
  const tcp::endpoint endpoint(address, options.port);
  const auto fail = [&](const boost::system::error_code& why) {
    throw std::runtime_error("admin: cannot listen on " + endpoint_text(options.bind_address, options.port) + ": " +
                             reason_text(why));
  };

  io = std::make_unique<asio::io_context>(1);  // concurrency hint: exactly one thread runs it
  acceptor = std::make_unique<tcp::acceptor>(*io);
  accept_retry = std::make_unique<asio::steady_timer>(*io);
  if (acceptor->open(endpoint.protocol(), ec); ec) fail(ec);
  // Lets a restarted server rebind while old connections sit in TIME_WAIT; a live listener on the
  // port still makes bind() fail, which is the "in use" case we must report.
  if (acceptor->set_option(tcp::acceptor::reuse_address(true), ec); ec) fail(ec);
  if (acceptor->bind(endpoint, ec); ec) fail(ec);
  if (acceptor->listen(asio::socket_base::max_listen_connections, ec); ec) fail(ec);
  port = acceptor->local_endpoint().port();
}

void AdminServer::Impl::accept() {
  acceptor->async_accept([this](boost::system::error_code ec, tcp::socket socket) {
    if (ec == asio::error::operation_aborted) return;  // stop()
    if (ec) {
      // Typically out of file descriptors: retry shortly instead of spinning on the error.
      accept_retry->expires_after(std::chrono::milliseconds(100));
      accept_retry->async_wait([this](boost::system::error_code wait_ec) {
        if (!wait_ec) accept();
      });
      return;
    }
    // Over the cap the socket just closes here: a flood of scrapers cannot exhaust the process.
    if (open_connections < options.max_connections) {
      std::make_shared<HttpSession>(std::move(socket), config, open_connections)->start();
    }
    accept();
  });
}

void AdminServer::Impl::run() {
  // Handlers do not throw by design; should one (say bad_alloc while rendering), report it and keep
  // serving rather than take the game server down with an uncaught exception on this thread.
  for (;;) {
    try {
      io->run();
      return;
    } catch (const std::exception& e) {
      std::fprintf(stderr, "admin: handler failed: %s\n", e.what());
    }
  }
}

void AdminServer::Impl::stop() {
  if (!io) return;
  io->stop();
  if (thread.joinable()) thread.join();
  accept_retry.reset();
  acceptor.reset();
  io.reset();
}

AdminServer::AdminServer(MetricsRegistry& registry, ReadinessCheck ready, AdminServerOptions options)
    : impl_(std::make_unique<Impl>(registry, std::move(ready), std::move(options))) {
  impl_->listen();
  impl_->accept();
  impl_->thread = std::thread([impl = impl_.get()] { impl->run(); });
}

AdminServer::~AdminServer() { stop(); }

std::uint16_t AdminServer::port() const noexcept { return impl_->port; }

const std::string& AdminServer::bind_address() const noexcept { return impl_->options.bind_address; }

void AdminServer::stop() { impl_->stop(); }

}  // namespace throng::admin
