// WebServer: the page routes (web_routes.h) served by a throng::http listener, and the WebSocket
// sessions (/ws) it hands upgraded connections to. One io_context run by one thread owned by the
// listener: no handler needs a lock; other threads only post().
#include "throng/view/web_server.h"

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cstdio>
#include <deque>
#include <stdexcept>
#include <vector>

#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>

#include "throng/http/listener.h"
#include "web_routes.h"

namespace throng::view {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
using tcp = asio::ip::tcp;

namespace {

using Message = std::shared_ptr<const std::string>;

}  // namespace

class WsSession;

// What the WebSocket sessions share (the pimpl itself is private to WebServer).
struct WebCore {
  WebCore(WebServerOptions o, WebServer::MessageHandler m) : options(std::move(o)), on_message(std::move(m)) {}

  WebServerOptions options;
  WebServer::MessageHandler on_message;
  std::atomic<std::size_t> ws_open{0};
  // --- web thread only ---
  Message greeting;
  std::vector<std::weak_ptr<WsSession>> sessions;

  template <class Fn>
  void each_session(Fn fn);
};

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

// --- server -----------------------------------------------------------------------------------
namespace {

throng::http::ListenerOptions listener_options(const WebServerOptions& o) {
  throng::http::ListenerOptions l;
  l.name = "throng-view";
  l.bind_address = o.bind_address;
  l.port = o.port;
  l.max_connections = o.max_connections;
  l.io_timeout = o.http_timeout;
  l.header_limit = kHttpHeaderLimit;
  l.body_limit = kHttpBodyLimit;
  return l;
}

// The listener's answer to a request it could not parse, in the page server's own style
// ("bad request\n", Server: throng-view).
HttpResponse refusal(http::status status) {
  std::string body(http::obsolete_reason(status));
  for (char& c : body) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return text_response(status, body + "\n", 11, false);
}

}  // namespace

struct WebServer::Impl : WebCore {
  Impl(WebServerOptions opts, MessageHandler handler) : WebCore(std::move(opts), std::move(handler)) {
    throng::http::HttpHandlers h;
    h.route = [this](const HttpRequest& req) { return route_request(req, options.web_root); };
    h.upgrade = [this](tcp::socket socket, HttpRequest req) {
      std::make_shared<WsSession>(std::move(socket), *this)->start(std::move(req));
    };
    h.refuse = refusal;
    // Open pages hold connections too: the cap counts them with the HTTP ones.
    h.other_connections = [this] { return ws_open.load(); };
    listener = std::make_unique<throng::http::HttpListener>(listener_options(options), std::move(h));
  }

  // Stopped (its thread joined, its sessions freed) before the state they use goes away.
  std::unique_ptr<throng::http::HttpListener> listener;
};

template <class Fn>
void WebCore::each_session(Fn fn) {
  std::erase_if(sessions, [](const std::weak_ptr<WsSession>& w) { return w.expired(); });
  for (const auto& w : sessions) {
    if (auto s = w.lock()) fn(*s);
  }
}

WebServer::WebServer(WebServerOptions options, MessageHandler on_message)
    : impl_(std::make_unique<Impl>(std::move(options), std::move(on_message))) {}

WebServer::~WebServer() { stop(); }

std::uint16_t WebServer::port() const noexcept { return impl_->listener->port(); }

std::size_t WebServer::sessions() const noexcept { return impl_->ws_open.load(); }

void WebServer::set_greeting(std::string message) {
  impl_->listener->post([impl = impl_.get(), m = std::make_shared<const std::string>(std::move(message))] {
    impl->greeting = m;
    impl->each_session([&](WsSession& s) { s.send(m, false); });
  });
}

void WebServer::broadcast(std::string message) {
  impl_->listener->post([impl = impl_.get(), m = std::make_shared<const std::string>(std::move(message))] {
    impl->each_session([&](WsSession& s) { s.send(m, true); });
  });
}

void WebServer::stop() { impl_->listener->stop(); }

}  // namespace throng::view
