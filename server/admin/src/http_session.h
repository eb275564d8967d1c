// One admin connection: read a request (bounded size, bounded time), route it, write the response,
// repeat while the client keeps the connection alive. Lives on the admin io_context's single
// thread, owned by its own pending handlers through shared_from_this.
#pragma once

#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <array>
#include <chrono>
#include <cstddef>
#include <memory>
#include <optional>

#include "routes.h"

namespace throng::admin {

struct SessionConfig {
  Routes routes;
  std::chrono::milliseconds io_timeout;
  std::size_t header_limit;
  std::size_t body_limit;
};

class HttpSession : public std::enable_shared_from_this<HttpSession> {
 public:
  // `config` and `open_connections` belong to the server and outlive every session; the count is
  // incremented here and decremented when the session dies, so the accept loop can cap connections.
  HttpSession(boost::asio::ip::tcp::socket socket, const SessionConfig& config, std::size_t& open_connections);
  ~HttpSession();
  HttpSession(const HttpSession&) = delete;
  HttpSession& operator=(const HttpSession&) = delete;

  void start() { read_request(); }

 private:
  void read_request();
  void on_read(boost::beast::error_code ec);
  void write(Response response);
  void on_write(bool keep_alive, boost::beast::error_code ec);
  void finish();  // graceful close after our last response
  void discard_input();

  boost::beast::tcp_stream stream_;
  boost::beast::flat_buffer buffer_;
  // A fresh parser per request, because the size limits and the parse state are per request.
  std::optional<http::request_parser<http::string_body>> parser_;
  Response response_;  // kept alive here until its async write completes
  std::array<char, 1024> discard_{};
  const SessionConfig& config_;
  std::size_t& open_connections_;
};

}  // namespace throng::admin
