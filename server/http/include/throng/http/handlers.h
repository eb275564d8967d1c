// What an HttpListener serves: its users' side of the contract. The listener moves bytes and
// enforces limits; every decision about what to answer is made by these callbacks, which run on
// the listener's thread (one thread, so they need no lock among themselves).
#pragma once

#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/http.hpp>
#include <cstddef>
#include <functional>
#include <optional>

namespace throng::http {

using Request = boost::beast::http::request<boost::beast::http::string_body>;
using Response = boost::beast::http::response<boost::beast::http::string_body>;
using Status = boost::beast::http::status;

struct HttpHandlers {
  // The answer to one parsed request. nullopt hands the connection over: the socket and the
  // request go to `upgrade` (a WebSocket handshake), or the connection closes when there is none.
  std::function<std::optional<Response>(const Request&)> route;
  // Takes over a connection `route` did not answer; the socket runs on the listener's io_context,
  // so whatever owns it must not outlive HttpListener::stop() (which destroys that context).
  std::function<void(boost::asio::ip::tcp::socket, Request)> upgrade;
  // The answer to a request the parser refused: 400 (not HTTP), 413 (body), 431 (header). The
  // listener closes the connection after it, whatever keep-alive it asks for. Each user builds it
  // so it carries that user's Server header and body style.
  std::function<Response(Status)> refuse;
  // Connections held outside the listener's HTTP sessions (upgraded ones) that count against
  // max_connections too. Empty: none.
  std::function<std::size_t()> other_connections;
};

}  // namespace throng::http
