#include "test_support.h"

#include <regex>
#include <sstream>
#include <stdexcept>
#include <thread>

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>

namespace throng::view::testing {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
using tcp = asio::ip::tcp;

std::optional<std::uint16_t> view_port(const std::filesystem::path& out) {
  static const std::regex re(R"(view at http://127\.0\.0\.1:(\d+)/)");
  std::smatch m;
  const std::string text = read_file(out);
  if (!std::regex_search(text, m, re)) return std::nullopt;
  return static_cast<std::uint16_t>(std::stoi(m[1]));
}

bool wait_until(const std::function<bool()>& pred, std::chrono::milliseconds timeout) {
  const auto until = Clock::now() + timeout;
  for (;;) {
    if (pred()) return true;
    if (Clock::now() >= until) return false;
    std::this_thread::sleep_for(50ms);
  }
}

// --- bounded asio -----------------------------------------------------------------------------
namespace {

// Runs io until done() or the deadline; false on timeout.
bool run_until(asio::io_context& io, const std::function<bool()>& done, Clock::time_point deadline) {
  while (!done()) {
    if (io.stopped()) io.restart();
    if (io.run_one_until(deadline) == 0) {
      if (done()) return true;
      if (Clock::now() >= deadline || io.stopped()) return done();
    }
  }
  return true;
}

}  // namespace

struct WsClient::Impl {
  asio::io_context io;
  websocket::stream<beast::tcp_stream> ws{io};
  beast::flat_buffer buffer;
  bool reading = false, read_done = false;
  beast::error_code read_ec;
};

WsClient::WsClient(const std::string& host, std::uint16_t port, const std::string& target,
                   std::chrono::milliseconds timeout, const std::string& origin)
    : impl_(std::make_unique<Impl>()) {
  const auto deadline = Clock::now() + timeout;
  auto& m = *impl_;
  bool done = false;
  beast::error_code ec;
  beast::get_lowest_layer(m.ws).expires_after(timeout);
  beast::get_lowest_layer(m.ws).async_connect(tcp::endpoint(asio::ip::make_address(host), port),
                                              [&](beast::error_code e) { ec = e; done = true; });
  if (!run_until(m.io, [&] { return done; }, deadline)) throw std::runtime_error("WebSocket connect timed out");
  if (ec) throw std::runtime_error("WebSocket connect: " + ec.message());
  beast::get_lowest_layer(m.ws).expires_never();
  m.ws.set_option(websocket::stream_base::timeout::suggested(beast::role_type::client));
  m.ws.read_message_max(64 * 1024 * 1024);  // screenshots
  if (!origin.empty()) {
    m.ws.set_option(websocket::stream_base::decorator(
        [origin](websocket::request_type& req) { req.set(http::field::origin, origin); }));
  }
  done = false;
  m.ws.async_handshake(host + ":" + std::to_string(port), target, [&](beast::error_code e) {
    ec = e;
    done = true;
  });
  if (!run_until(m.io, [&] { return done; }, deadline)) throw std::runtime_error("WebSocket handshake timed out");
  if (ec) throw std::runtime_error("WebSocket handshake: " + ec.message());
}

WsClient::~WsClient() = default;

void WsClient::send(const std::string& message, bool binary, std::chrono::milliseconds timeout) {
  auto& m = *impl_;
  bool done = false;
  beast::error_code ec;
  m.ws.binary(binary);
  m.ws.async_write(asio::buffer(message), [&](beast::error_code e, std::size_t) {
    ec = e;
    done = true;
  });
  if (!run_until(m.io, [&] { return done; }, Clock::now() + timeout))
    throw std::runtime_error("WebSocket write timed out");
  if (ec) throw std::runtime_error("WebSocket write: " + ec.message());
}

std::optional<std::string> WsClient::read(std::chrono::milliseconds timeout) {
  auto& m = *impl_;
  if (!m.reading) {
    m.reading = true;
    m.read_done = false;
    m.ws.async_read(m.buffer, [&m](beast::error_code e, std::size_t) {
      m.read_ec = e;
      m.read_done = true;
    });
  }
  if (!run_until(m.io, [&] { return m.read_done; }, Clock::now() + timeout)) return std::nullopt;
  m.reading = false;
  if (m.read_ec) throw std::runtime_error("WebSocket read: " + m.read_ec.message());
  std::string s = beast::buffers_to_string(m.buffer.data());
  m.buffer.consume(m.buffer.size());
  return s;
}

HttpResult http_request(const std::string& host, std::uint16_t port, const std::string& target,
                        const std::string& method, std::chrono::milliseconds timeout) {
  asio::io_context io;
  beast::tcp_stream stream(io);
  const auto deadline = Clock::now() + timeout;
  stream.expires_after(timeout);
  bool done = false;
  beast::error_code ec;
  auto step = [&](const char* what) {
    if (!run_until(io, [&] { return done; }, deadline)) throw std::runtime_error(std::string("HTTP ") + what + " timed out");
    if (ec) throw std::runtime_error(std::string("HTTP ") + what + ": " + ec.message());
    done = false;
  };
  stream.async_connect(tcp::endpoint(asio::ip::make_address(host), port), [&](beast::error_code e) {
    ec = e;
    done = true;
  });
  step("connect");
  http::request<http::empty_body> req{http::string_to_verb(method), target, 11};
  req.set(http::field::host, host + ":" + std::to_string(port));
  req.keep_alive(false);
  http::async_write(stream, req, [&](beast::error_code e, std::size_t) {
    ec = e;
    done = true;
  });
  step("write");
  beast::flat_buffer buffer;
  http::response_parser<http::string_body> parser;
  parser.body_limit(64 * 1024 * 1024);
  if (method == "HEAD") parser.skip(true);
  http::async_read(stream, buffer, parser, [&](beast::error_code e, std::size_t) {
    ec = e;
    done = true;
  });
  step("read");
  const auto& res = parser.get();
  HttpResult r;
  r.status = static_cast<int>(res.result_int());
  r.body = res.body();
  if (auto it = res.find(http::field::content_type); it != res.end()) r.content_type = std::string(it->value());
  return r;
}

// --- DevTools ---------------------------------------------------------------------------------
Cdp::Cdp(const std::string& host, std::uint16_t port, const std::string& target) : ws_(host, port, target) {}

nlohmann::json Cdp::call(const std::string& method, const nlohmann::json& params, std::chrono::milliseconds timeout) {
  const int id = next_id_++;
  ws_.send(nlohmann::json{{"id", id}, {"method", method}, {"params", params}}.dump());
  const auto deadline = Clock::now() + timeout;
  for (;;) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now());
    if (left <= 0ms) throw std::runtime_error("DevTools " + method + " timed out");
    const auto text = ws_.read(left);
    if (!text) throw std::runtime_error("DevTools " + method + " timed out");
    const auto j = nlohmann::json::parse(*text, nullptr, false);
    if (j.is_discarded() || !j.contains("id") || j["id"] != id) continue;  // events, other replies
    if (j.contains("error")) throw std::runtime_error("DevTools " + method + ": " + j["error"].dump());
    return j.value("result", nlohmann::json::object());
  }
}

nlohmann::json Cdp::evaluate(const std::string& expression, std::chrono::milliseconds timeout) {
  const auto r = call("Runtime.evaluate", {{"expression", expression}, {"returnByValue", true}, {"awaitPromise", true}},
                      timeout);
  if (r.contains("exceptionDetails")) throw std::runtime_error("JavaScript: " + r["exceptionDetails"].dump());
  return r["result"].value("value", nlohmann::json());
}

std::string base64_decode(const std::string& in) {
  auto value = [](char c) -> int {
    if (c >= 'A' && c <= 'Z') return c - 'A';
    if (c >= 'a' && c <= 'z') return c - 'a' + 26;
    if (c >= '0' && c <= '9') return c - '0' + 52;
    if (c == '+') return 62;
    if (c == '/') return 63;
    return -1;
  };
  std::string out;
  out.reserve(in.size() * 3 / 4);
  unsigned acc = 0;
  int bits = 0;
  for (char c : in) {
    const int v = value(c);
    if (v < 0) continue;  // padding, whitespace
    acc = (acc << 6) | static_cast<unsigned>(v);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out.push_back(static_cast<char>((acc >> bits) & 0xFFu));
    }
  }
  return out;
}

}  // namespace throng::view::testing
