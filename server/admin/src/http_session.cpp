#include "http_session.h"

#include <algorithm>
#include <utility>

namespace throng::admin {

namespace beast = boost::beast;
namespace asio = boost::asio;

namespace {

// Version for error responses: the request line may not have parsed, so we cannot echo it.
constexpr unsigned http_1_1 = 11;

bool is_http_parse_error(const beast::error_code& ec) {
  return ec.category() == beast::http::make_error_code(http::error::bad_method).category();
}

}  // namespace

HttpSession::HttpSession(asio::ip::tcp::socket socket, const SessionConfig& config, std::size_t& open_connections)
    : stream_(std::move(socket)), config_(config), open_connections_(open_connections) {
  ++open_connections_;
}

HttpSession::~HttpSession() { --open_connections_; }

void HttpSession::read_request() {
  parser_.emplace();
  parser_->header_limit(static_cast<std::uint32_t>(config_.header_limit));
  parser_->body_limit(config_.body_limit);
  // The timer covers the whole request, not each read, so a client dripping one byte at a time
  // (or idling on keep-alive) is cut off after io_timeout.
  stream_.expires_after(config_.io_timeout);
  http::async_read(stream_, buffer_, *parser_,
                   [self = shared_from_this()](beast::error_code ec, std::size_t) { self->on_read(ec); });
}

void HttpSession::on_read(beast::error_code ec) {
  if (ec == http::error::end_of_stream) return finish();  // client finished with the connection
  if (ec == http::error::header_limit) return write(error_response(http::status::request_header_fields_too_large, http_1_1));
  if (ec == http::error::body_limit) return write(error_response(http::status::payload_too_large, http_1_1));
  // A parse error means the client spoke something other than HTTP/1.x; tell it so and hang up.
  if (ec && is_http_parse_error(ec)) return write(error_response(http::status::bad_request, http_1_1));
  // Timeouts, resets and aborts (stop()) end the session: dropping the last reference closes it.
  if (ec) return;
  write(config_.routes.handle(parser_->get()));
}

void HttpSession::write(Response response) {
  response_ = std::move(response);
  const bool keep_alive = response_.keep_alive();
  stream_.expires_after(config_.io_timeout);  // a client that never reads cannot hold us either
  http::async_write(stream_, response_, [self = shared_from_this(), keep_alive](beast::error_code ec, std::size_t) {
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
  stream_.expires_after(std::min<std::chrono::milliseconds>(config_.io_timeout, std::chrono::seconds(2)));
  discard_input();
}

void HttpSession::discard_input() {
  stream_.async_read_some(asio::buffer(discard_), [self = shared_from_this()](beast::error_code ec, std::size_t) {
    if (!ec) self->discard_input();  // EOF, timeout or abort: done, the socket closes with us
  });
}

}  // namespace throng::admin
