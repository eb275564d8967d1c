// A small blocking Beast HTTP client for the admin tests. Each call looks synchronous, but runs
// the async operation on a private io_context under a tcp_stream deadline, because Asio's truly
// synchronous reads cannot time out: a server bug must fail a test, never hang it.
#pragma once

#include <boost/asio/connect.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace throng::admin::test {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
using Response = http::response<http::string_body>;

class HttpTestClient {
 public:
  explicit HttpTestClient(std::uint16_t port, std::chrono::milliseconds timeout = std::chrono::seconds(5))
      : stream_(io_), timeout_(timeout) {
    const asio::ip::tcp::endpoint endpoint(asio::ip::make_address("127.0.0.1"), port);
    const auto ec = run([&](auto done) { stream_.async_connect(endpoint, [done](beast::error_code e) { done(e, 0); }); });
    if (ec) throw beast::system_error(ec);
  }

  // Sends one request and reads its response; nullopt if the server closed or timed out instead.
  std::optional<Response> request(http::verb method, std::string_view target, bool keep_alive = true) {
    http::request<http::string_body> req{method, beast::string_view(target.data(), target.size()), 11};
    req.set(http::field::host, "127.0.0.1");
    req.keep_alive(keep_alive);
    req.prepare_payload();
    const auto ec = run([&](auto done) { http::async_write(stream_, req, done); });
    if (ec) return std::nullopt;
    return read_response();
  }
  std::optional<Response> get(std::string_view target) { return request(http::verb::get, target); }

  // Raw bytes, for requests no well-behaved client would produce.
  beast::error_code send_raw(std::string_view bytes) {
    return run([&](auto done) { asio::async_write(stream_, asio::buffer(bytes.data(), bytes.size()), done); });
  }

  std::optional<Response> read_response() {
    Response res;
    const auto ec = run([&](auto done) { http::async_read(stream_, buffer_, res, done); });
    if (ec) return std::nullopt;
    return res;
  }

  // The error that ended a read of further bytes: eof / connection_reset when the server hung up,
  // beast::error::timeout when it kept the connection open past the deadline.
  beast::error_code wait_for_close() {
    char byte = 0;
    for (;;) {
      const auto ec = run([&](auto done) { stream_.async_read_some(asio::buffer(&byte, 1), done); });
      if (ec) return ec;
    }
  }

 private:
  // Starts one async operation via `start(done)` and runs it to completion or the deadline.
  template <class Start>
  beast::error_code run(Start start) {
    std::optional<beast::error_code> result;
    stream_.expires_after(timeout_);
    start([&result](beast::error_code ec, std::size_t) { result = ec; });
    io_.restart();
    io_.run_for(timeout_ + std::chrono::seconds(1));  // the stream deadline fires first; this is a backstop
    if (!result) {  // never leave a handler pending that points at this frame
      stream_.close();
      io_.restart();
      io_.run_for(std::chrono::seconds(1));
    }
    return result.value_or(beast::error::timeout);
  }

  asio::io_context io_;
  beast::tcp_stream stream_;
  beast::flat_buffer buffer_;
  std::chrono::milliseconds timeout_;
};

}  // namespace throng::admin::test
