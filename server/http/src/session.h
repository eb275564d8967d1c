// One HTTP connection: read a request (bounded size, bounded time), route it, write the response,
// repeat while the client keeps the connection alive; or hand the connection to the upgrade hook.
// Lives on the listener's single thread, owned by its own pending handlers through
// shared_from_this.
#pragma once

#include <array>
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <cstddef>
#include <memory>
#include <optional>

#include "throng/http/handlers.h"
#include "throng/http/listener.h"

namespace throng::http {

class HttpSession : public std::enable_shared_from_this<HttpSession> {
 public:
  // `options`, `handlers` and `open_sessions` belong to the listener and outlive every session; the
  // count is incremented here and decremented when the session dies, so the accept loop can cap
  // connections.
  HttpSession(boost::asio::ip::tcp::socket socket, const ListenerOptions& options, const HttpHandlers& handlers,
              std::size_t& open_sessions);
  ~HttpSession();
  HttpSession(const HttpSession&) = delete;
  HttpSession& operator=(const HttpSession&) = delete;

  void start() { read_request(); }

 private:
  void read_request();
  void on_read(boost::beast::error_code ec);
  void refuse(Status status);
  void write(Response response);
  void on_write(bool keep_alive, boost::beast::error_code ec);
  void finish();  // graceful close after our last response
  void discard_input();

  boost::beast::tcp_stream stream_;
  boost::beast::flat_buffer buffer_;
  // A fresh parser per request, because the size limits and the parse state are per request.
  std::optional<boost::beast::http::request_parser<boost::beast::http::string_body>> parser_;
  Response response_;  // kept alive here until its async write completes
  std::array<char, 1024> discard_{};
  const ListenerOptions& options_;
  const HttpHandlers& handlers_;
  std::size_t& open_sessions_;
};

}  // namespace throng::http
