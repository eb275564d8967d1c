// WebServer: listener, HTTP sessions (page + assets), WebSocket sessions (/ws). One io_context
// run by one thread owned by the server: no handler needs a lock; other threads only post().
#include "throng/view/web_server.h"

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <deque>
#include <stdexcept>
#include <thread>
#include <vector>

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/post.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>

#include "web_routes.h"

namespace throng::view {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
using tcp = asio::ip::tcp;

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

using Message = std::shared_ptr<const std::string>;

}  // namespace

class WsSession;

// Everything the sessions share (the pimpl itself is private to WebServer).
struct WebCore {
  WebServerOptions options;
  WebServer::MessageHandler on_message;
  std::uint16_t port = 0;
  std::atomic<std::size_t> ws_open{0};
  // --- web thread only ---
  std::size_t open_connections = 0;
  Message greeting;
  std::vector<std::weak_ptr<WsSession>> sessions;
  // Destroyed in stop(): I/O objects first, then the io_context (which frees pending sessions).
  std::unique_ptr<asio::io_context> io;
  std::unique_ptr<tcp::acceptor> acceptor;
  std::unique_ptr<asio::steady_timer> accept_retry;
  std::thread thread;

  void listen();
  void accept();
  void run();
  void stop();
  template <class Fn>
  void each_session(Fn fn);
};

struct WebServer::Impl : WebCore {};

// --- WebSocket session ------------------------------------------------------------------------
class WsSession : public std::enable_shared_from_this<WsSession> {
 public:
  WsSession(tcp::socket socket, WebCore& server) : ws_(std::move(socket)), server_(server) {}
  ~WsSession() {
    if (registered_) --server_.ws_open;
  }

  void start(http::request<http::string_body> req) {
    ws_.set_option(websocket::stream_base::timeout::suggested(beast::role_type::server));
    ws_.set_option(websocket::stream_base::decorator(
        [](websocket::response_type& res) { res.set(http::field::server, "throng-view"); }));
    ws_.read_message_max(server_.options.max_message_bytes);
    ws_.async_accept(req, [self = shared_from_this()](beast::error_code ec) { self->on_accept(ec); });
  }

  void send(Message m, bool droppable) {
    if (closed_) return;
    if (droppable) {
      // The front is being written when writing_: never drop that one.
      const std::size_t first = writing_ ? 1 : 0;
      std::size_t queued = 0;
      for (std::size_t i = first; i < queue_.size(); ++i) queued += queue_[i].droppable;
      for (std::size_t i = first; i < queue_.size() && queued >= server_.options.max_queued_frames;) {
        if (queue_[i].droppable) {
          queue_.erase(queue_.begin() + static_cast<std::ptrdiff_t>(i));
          --queued;
        } else {
          ++i;
        }
      }
    }
    queue_.push_back(Out{std::move(m), droppable});
    if (!writing_) write_next();
  }

 private:
  struct Out {
    Message msg;
    bool droppable;
  };

  void on_accept(beast::error_code ec) {
    if (ec) return;
    registered_ = true;
    ++server_.ws_open;
    server_.sessions.push_back(weak_from_this());
    if (server_.greeting) send(server_.greeting, false);
    read();
  }

  void read() {
    ws_.async_read(buffer_, [self = shared_from_this()](beast::error_code ec, std::size_t) { self->on_read(ec); });
  }

  void on_read(beast::error_code ec) {
    if (ec) {  // closed, timed out, too big, or the server stops
      closed_ = true;
      return;
    }
    const std::string text = beast::buffers_to_string(buffer_.data());
    buffer_.consume(buffer_.size());
    std::optional<std::string> reply;
    try {
      reply = server_.on_message(text, !ws_.got_text());
    } catch (const std::exception& e) {
      std::fprintf(stderr, "throng-view: page message handler failed: %s\n", e.what());
    }
    if (reply) send(std::make_shared<const std::string>(std::move(*reply)), false);
    read();
  }

  void write_next() {
    writing_ = true;
    ws_.text(true);
    ws_.async_write(asio::buffer(*queue_.front().msg),
                    [self = shared_from_this()](beast::error_code ec, std::size_t) { self->on_write(ec); });
  }

  void on_write(beast::error_code ec) {
    writing_ = false;
    if (ec) {
      closed_ = true;
      queue_.clear();
      return;
    }
    queue_.pop_front();
    if (!queue_.empty()) write_next();
  }

  websocket::stream<beast::tcp_stream> ws_;
  WebCore& server_;
  beast::flat_buffer buffer_;
  std::deque<Out> queue_;
  bool writing_ = false;
  bool closed_ = false;
  bool registered_ = false;
};

// --- HTTP session -----------------------------------------------------------------------------
class HttpSession : public std::enable_shared_from_this<HttpSession> {
 public:
  HttpSession(tcp::socket socket, WebCore& server) : stream_(std::move(socket)), server_(server) {
    ++server_.open_connections;
  }
  ~HttpSession() { --server_.open_connections; }

  void read() {
    parser_.emplace();
    parser_->header_limit(kHttpHeaderLimit);
    parser_->body_limit(kHttpBodyLimit);
    stream_.expires_after(server_.options.http_timeout);
    http::async_read(stream_, buffer_, *parser_,
                     [self = shared_from_this()](beast::error_code ec, std::size_t) { self->on_read(ec); });
  }

 private:
  void on_read(beast::error_code ec) {
    if (ec == http::error::end_of_stream) return close();
    if (ec) {
      if (ec.category() == http::make_error_code(http::error::bad_method).category())
        return write(text_response(http::status::bad_request, "bad request\n", 11, false));
      return;  // timeout, reset, stop()
    }
    auto req = parser_->release();
    if (auto res = route_request(req, server_.options.web_root)) return write(std::move(*res));
    stream_.expires_never();  // an accepted WebSocket upgrade
    std::make_shared<WsSession>(stream_.release_socket(), server_)->start(std::move(req));
  }

  void write(HttpResponse res) {
    response_ = std::move(res);
    const bool keep_alive = response_.keep_alive();
    stream_.expires_after(server_.options.http_timeout);
    http::async_write(stream_, response_, [self = shared_from_this(), keep_alive](beast::error_code ec, std::size_t) {
      if (ec) return;
      if (keep_alive) return self->read();
      self->close();
    });
  }

  void close() {
    beast::error_code ignored;
    stream_.socket().shutdown(tcp::socket::shutdown_send, ignored);
  }

  beast::tcp_stream stream_;
  WebCore& server_;
  beast::flat_buffer buffer_;
  std::optional<http::request_parser<http::string_body>> parser_;
  HttpResponse response_;
};

// --- server -----------------------------------------------------------------------------------
void WebCore::listen() {
  boost::system::error_code ec;
  const auto address = asio::ip::make_address(options.bind_address, ec);
  if (ec) throw std::runtime_error("invalid bind address \"" + options.bind_address + "\"");
  const tcp::endpoint endpoint(address, options.port);
  const auto fail = [&](const boost::system::error_code& why) {
    throw std::runtime_error("cannot listen on " + endpoint_text(options.bind_address, options.port) + ": " +
                             reason_text(why));
  };
  io = std::make_unique<asio::io_context>(1);
  acceptor = std::make_unique<tcp::acceptor>(*io);
  accept_retry = std::make_unique<asio::steady_timer>(*io);
  if (acceptor->open(endpoint.protocol(), ec); ec) fail(ec);
  if (acceptor->set_option(tcp::acceptor::reuse_address(true), ec); ec) fail(ec);
  if (acceptor->bind(endpoint, ec); ec) fail(ec);
  if (acceptor->listen(asio::socket_base::max_listen_connections, ec); ec) fail(ec);
  port = acceptor->local_endpoint().port();
}

void WebCore::accept() {
  acceptor->async_accept([this](boost::system::error_code ec, tcp::socket socket) {
    if (ec == asio::error::operation_aborted) return;
    if (ec) {  // e.g. out of file descriptors: retry shortly instead of spinning
      accept_retry->expires_after(std::chrono::milliseconds(100));
      accept_retry->async_wait([this](boost::system::error_code wait_ec) {
        if (!wait_ec) accept();
      });
      return;
    }
    if (open_connections + ws_open.load() < options.max_connections)
      std::make_shared<HttpSession>(std::move(socket), *this)->read();
    accept();
  });
}

template <class Fn>
void WebCore::each_session(Fn fn) {
  std::erase_if(sessions, [](const std::weak_ptr<WsSession>& w) { return w.expired(); });
  for (const auto& w : sessions) {
    if (auto s = w.lock()) fn(*s);
  }
}

void WebCore::run() {
  for (;;) {
    try {
      io->run();
      return;
    } catch (const std::exception& e) {
      std::fprintf(stderr, "throng-view: web handler failed: %s\n", e.what());
    }
  }
}

void WebCore::stop() {
  if (!io) return;
  io->stop();
  if (thread.joinable()) thread.join();
  accept_retry.reset();
  acceptor.reset();
  sessions.clear();
  io.reset();
}

WebServer::WebServer(WebServerOptions options, MessageHandler on_message) : impl_(std::make_unique<Impl>()) {
  impl_->options = std::move(options);
  impl_->on_message = std::move(on_message);
  impl_->listen();
  impl_->accept();
  impl_->thread = std::thread([impl = impl_.get()] { impl->run(); });
}

WebServer::~WebServer() { stop(); }

std::uint16_t WebServer::port() const noexcept { return impl_->port; }

std::size_t WebServer::sessions() const noexcept { return impl_->ws_open.load(); }

void WebServer::set_greeting(std::string message) {
  if (!impl_->io) return;
  asio::post(*impl_->io, [impl = impl_.get(), m = std::make_shared<const std::string>(std::move(message))] {
    impl->greeting = m;
    impl->each_session([&](WsSession& s) { s.send(m, false); });
  });
}

void WebServer::broadcast(std::string message) {
  if (!impl_->io) return;
  asio::post(*impl_->io, [impl = impl_.get(), m = std::make_shared<const std::string>(std::move(message))] {
    impl->each_session([&](WsSession& s) { s.send(m, true); });
  });
}

void WebServer::stop() { impl_->stop(); }

}  // namespace throng::view
