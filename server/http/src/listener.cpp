// HttpListener: bind, accept loop and the listener's thread. Everything network-side runs on one
// io_context driven by one thread that this class owns, so no handler ever needs a lock and the
// owner's loop never waits on a socket.
#include "throng/http/listener.h"

#include <boost/asio/post.hpp>
#include <cstdio>
#include <exception>
#include <stdexcept>
#include <string>
#include <utility>

#include "listen_error.h"
#include "session.h"

namespace throng::http {

namespace asio = boost::asio;
using tcp = asio::ip::tcp;

namespace {

// For users that do not shape their own: a plain-text reason phrase, no Server header.
Response plain_refusal(Status status) {
  Response res{status, 11};  // the request line may not have parsed, so its version is unknown
  res.set(boost::beast::http::field::content_type, "text/plain; charset=utf-8");
  res.body() = std::string(boost::beast::http::obsolete_reason(status)) + "\n";
  res.prepare_payload();
  return res;
}

}  // namespace

HttpListener::HttpListener(ListenerOptions options, HttpHandlers handlers)
    : options_(std::move(options)), handlers_(std::move(handlers)) {
  if (!handlers_.refuse) handlers_.refuse = plain_refusal;
  listen();
  accept();
  thread_ = std::thread([this] { run(); });
}

HttpListener::~HttpListener() { stop(); }

void HttpListener::listen() {
  boost::system::error_code ec;
  const auto address = asio::ip::make_address(options_.bind_address, ec);
  if (ec) throw std::runtime_error("invalid bind address \"" + options_.bind_address + "\"");
  const tcp::endpoint endpoint(address, options_.port);
  const auto fail = [&](const boost::system::error_code& why) {
    throw std::runtime_error(listen_error(options_.bind_address, options_.port, why));
  };

  io_ = std::make_unique<asio::io_context>(1);  // concurrency hint: exactly one thread runs it
  acceptor_ = std::make_unique<tcp::acceptor>(*io_);
  accept_retry_ = std::make_unique<asio::steady_timer>(*io_);
  if (acceptor_->open(endpoint.protocol(), ec); ec) fail(ec);
  // Lets a restarted server rebind while old connections sit in TIME_WAIT; a live listener on the
  // port still makes bind() fail, which is the "in use" case we must report.
  if (acceptor_->set_option(tcp::acceptor::reuse_address(true), ec); ec) fail(ec);
  if (acceptor_->bind(endpoint, ec); ec) fail(ec);
  if (acceptor_->listen(asio::socket_base::max_listen_connections, ec); ec) fail(ec);
  port_ = acceptor_->local_endpoint().port();
}

void HttpListener::accept() {
  acceptor_->async_accept([this](boost::system::error_code ec, tcp::socket socket) {
    if (ec == asio::error::operation_aborted) return;  // stop()
    if (ec) {
      // Typically out of file descriptors: retry shortly instead of spinning on the error.
      accept_retry_->expires_after(std::chrono::milliseconds(100));
      accept_retry_->async_wait([this](boost::system::error_code wait_ec) {
        if (!wait_ec) accept();
      });
      return;
    }
    // Over the cap the socket just closes here: a flood of clients cannot exhaust the process.
    const std::size_t open = open_sessions_ + (handlers_.other_connections ? handlers_.other_connections() : 0);
    if (open < options_.max_connections) {
      std::make_shared<HttpSession>(std::move(socket), options_, handlers_, open_sessions_)->start();
    }
    accept();
  });
}

void HttpListener::run() {
  // Handlers do not throw by design; should one (say bad_alloc while rendering), report it and keep
  // serving rather than take the whole process down with an uncaught exception on this thread.
  for (;;) {
    try {
      io_->run();
      return;
    } catch (const std::exception& e) {
      std::fprintf(stderr, "%s: handler failed: %s\n", options_.name.c_str(), e.what());
    }
  }
}

void HttpListener::post(std::function<void()> fn) {
  if (io_) asio::post(*io_, std::move(fn));
}

void HttpListener::stop() {
  if (!io_) return;
  io_->stop();
  if (thread_.joinable()) thread_.join();
  accept_retry_.reset();
  acceptor_.reset();
  io_.reset();
}

}  // namespace throng::http
