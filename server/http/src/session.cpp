#include "session.h"

#include <algorithm>
#include <chrono>
#include <utility>

namespace throng::http {

namespace beast = boost::beast;
namespace bhttp = boost::beast::http;
namespace asio = boost::asio;

namespace {

bool is_http_parse_error(const beast::error_code& ec) {
  return ec.category() == bhttp::make_error_code(bhttp::error::bad_method).category();
}

}  // namespace

HttpSession::HttpSession(asio::ip::tcp::socket socket, const ListenerOptions& options, const HttpHandlers& handlers,
                         std::size_t& open_sessions)
    : stream_(std::move(socket)), options_(options), handlers_(handlers), open_sessions_(open_sessions) {
  ++open_sessions_;
}

HttpSession::~HttpSession() { --open_sessions_; }

void HttpSession::read_request() {
  parser_.emplace();
  parser_->header_limit(static_cast<std::uint32_t>(options_.header_limit));
  parser_->body_limit(options_.body_limit);
  // The timer covers the whole request, not each read, so a client dripping one byte at a time
  // (or idling on keep-alive) is cut off after io_timeout.
  stream_.expires_after(options_.io_timeout);
  bhttp::async_read(stream_, buffer_, *parser_,
                    [self = shared_from_this()](beast::error_code ec, std::size_t) { self->on_read(ec); });
}

void HttpSession::on_read(beast::error_code ec) {
  if (ec == bhttp::error::end_of_stream) return finish();  // client finished with the connection
  if (ec == bhttp::error::header_limit) return refuse(Status::request_header_fields_too_large);
  if (ec == bhttp::error::body_limit) return refuse(Status::payload_too_large);
  // A parse error means the client spoke something other than HTTP/1.x; tell it so and hang up.
  if (ec && is_http_parse_error(ec)) return refuse(Status::bad_request);
  // Timeouts, resets and aborts (stop()) end the session: dropping the last reference closes it.
  if (ec) return;
  Request req = parser_->release();
  if (auto res = handlers_.route(req)) return write(std::move(*res));
  if (!handlers_.upgrade) return;  // nothing takes the connection over: it closes with us
  // The upgraded connection keeps its own timeouts; ours would cut it off mid-stream.
  stream_.expires_never();
  handlers_.upgrade(stream_.release_socket(), std::move(req));
}

void HttpSession::refuse(Status status) {
  Response res = handlers_.refuse(status);
  // The stream position after a refused request cannot be trusted, so this is the last response.
  res.keep_alive(false);
  write(std::move(res));
}

void HttpSession::write(Response response) {
  response_ = std::move(response);
  const bool keep_alive = response_.keep_alive();
  stream_.expires_after(options_.io_timeout);  // a client that never reads cannot hold us either
  bhttp::async_write(stream_, response_, [self = shared_from_this(), keep_alive](beast::error_code ec, std::size_t) {
    self->on_write(keep_alive, ec);
  });
}

void HttpSession::on_write(bool keep_alive, beast::error_code ec) {
  if (ec) return;
  if (!keep_alive) return finish();
  read_request();
}

void HttpSession::finish() {
  // Half-close so the client sees EOF after the whole response, then discard whatever it still
  // sends (say the rest of an oversized header) until it closes too: closing a socket with unread
  // input makes the kernel send RST, which can destroy the response before the client reads it.
  beast::error_code ignored;
  stream_.socket().shutdown(asio::ip::tcp::socket::shutdown_send, ignored);
  stream_.expires_after(std::min<std::chrono::milliseconds>(options_.io_timeout, std::chrono::seconds(2)));
  discard_input();
}

void HttpSession::discard_input() {
  stream_.async_read_some(asio::buffer(discard_), [self = shared_from_this()](beast::error_code ec, std::size_t) {
    if (!ec) self->discard_input();  // EOF, timeout or abort: done, the socket closes with us
  });
}

}  // namespace throng::http
