// HttpListener: an HTTP/1.1 server on its own thread and its own io_context, so a slow or stuck
// client can never delay the caller's loop. It binds in the constructor (throwing a message that
// names the address and the reason), accepts up to max_connections, and serves each connection
// with a fresh size-limited parser per request, a whole-request timeout and keep-alive.
#pragma once

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/steady_timer.hpp>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <thread>

#include "throng/http/handlers.h"

namespace throng::http {

struct ListenerOptions {
  std::string name = "http";  // prefixes the listener's log lines, e.g. "admin", "throng-view"
  std::string bind_address = "127.0.0.1";
  std::uint16_t port = 0;  // 0 = ephemeral; HttpListener::port() tells which
  std::size_t max_connections = 64;  // further connections are closed at accept
  // A connection must deliver a whole request (and take a whole response) within this, and an idle
  // keep-alive connection is closed after it: a stuck client cannot pin a socket.
  std::chrono::milliseconds io_timeout{std::chrono::seconds(10)};
  std::size_t header_limit = 8 * 1024;  // bytes; larger request headers are refused with 431
  std::size_t body_limit = 8 * 1024;    // bytes; larger bodies are refused with 413
};

class HttpListener {
 public:
  // Binds and starts serving. Throws std::runtime_error "invalid bind address \"ADDRESS\"" or
  // "cannot listen on ADDRESS:PORT: REASON" (e.g. "address in use"); callers may prefix it.
  HttpListener(ListenerOptions options, HttpHandlers handlers);
  ~HttpListener();  // stop()
  HttpListener(const HttpListener&) = delete;
  HttpListener& operator=(const HttpListener&) = delete;

  // The bound port (the ephemeral one when options.port was 0). Still valid after stop().
  std::uint16_t port() const noexcept { return port_; }

  // Runs fn on the listener's thread; dropped once stop() has begun. Like stop(), call it from
  // the owner's side, not concurrently with stop().
  void post(std::function<void()> fn);

  // Closes the listener and every connection, joins the thread. Idempotent; returns promptly even
  // with clients connected (in-flight responses are dropped). Never call it from a handler (the
  // listener's thread cannot join itself).
  void stop();

 private:
  void listen();
  void accept();
  void run();

  ListenerOptions options_;
  HttpHandlers handlers_;
  std::uint16_t port_ = 0;
  // Declared before the io_context: sessions still pending when it is destroyed decrement this.
  std::size_t open_sessions_ = 0;
  // Held by pointer so stop() can destroy them, in this order: I/O objects, then the io_context,
  // whose destruction frees the sessions its pending handlers own (closing their sockets).
  std::unique_ptr<boost::asio::io_context> io_;
  std::unique_ptr<boost::asio::ip::tcp::acceptor> acceptor_;
  std::unique_ptr<boost::asio::steady_timer> accept_retry_;
  std::thread thread_;
};

}  // namespace throng::http
