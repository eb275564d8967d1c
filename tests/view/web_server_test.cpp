// WebServer: static page and assets, errors, the WebSocket greeting/broadcast/reply path, the
// cross-origin refusal and a port in use.
#include <gtest/gtest.h>

#include <boost/asio/connect.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/write.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <cctype>
#include <fstream>
#include <stdexcept>

#include "test_support.h"
#include "throng/view/web_server.h"

namespace throng::view {
namespace {

using namespace testing;

WebServerOptions any_port() {
  WebServerOptions o;
  o.port = 0;
  return o;
}

std::optional<std::string> echo_upper(std::string_view text, bool binary) {
  if (binary) return std::string("binary");
  std::string s(text);
  for (char& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return s;
}

// Reads messages until one contains `needle` (bounded).
std::optional<std::string> read_until(WsClient& ws, const std::string& needle, std::chrono::milliseconds timeout = 5s) {
  const auto until = Clock::now() + timeout;
  while (Clock::now() < until) {
    const auto m = ws.read(std::chrono::duration_cast<std::chrono::milliseconds>(until - Clock::now()));
    if (m && m->find(needle) != std::string::npos) return m;
  }
  return std::nullopt;
}

// Sends raw bytes (requests no browser would produce) and reads one response; nullopt if the
// server closed or the deadline passed instead.
std::optional<boost::beast::http::response<boost::beast::http::string_body>> raw_exchange(std::uint16_t port,
                                                                                          const std::string& bytes) {
  namespace beast = boost::beast;
  boost::asio::io_context io;
  beast::tcp_stream stream(io);
  beast::flat_buffer buffer;
  beast::http::response<beast::http::string_body> res;
  bool done = false;
  stream.expires_after(5s);
  stream.async_connect({boost::asio::ip::make_address("127.0.0.1"), port}, [&](beast::error_code ec) {
    if (ec) return;
    boost::asio::async_write(stream, boost::asio::buffer(bytes), [&](beast::error_code wec, std::size_t) {
      if (wec) return;
      beast::http::async_read(stream, buffer, res, [&](beast::error_code rec, std::size_t) { done = !rec; });
    });
  });
  io.run_for(6s);
  if (!done) return std::nullopt;
  return res;
}

TEST(WebServer, ServesTheEmbeddedPage) {
  WebServer web(any_port(), echo_upper);
  ASSERT_NE(web.port(), 0);
  auto r = http_request("127.0.0.1", web.port(), "/");
  EXPECT_EQ(r.status, 200);
  EXPECT_EQ(r.content_type, "text/html; charset=utf-8");
  EXPECT_NE(r.body.find("<canvas"), std::string::npos);
  EXPECT_NE(r.body.find("app.js"), std::string::npos);
  r = http_request("127.0.0.1", web.port(), "/app.js?v=1");
  EXPECT_EQ(r.status, 200);
  EXPECT_EQ(r.content_type, "text/javascript; charset=utf-8");
  EXPECT_NE(r.body.find("throngView"), std::string::npos);
  EXPECT_EQ(http_request("127.0.0.1", web.port(), "/style.css").status, 200);
  EXPECT_EQ(http_request("127.0.0.1", web.port(), "/nope.js").status, 404);
  EXPECT_EQ(http_request("127.0.0.1", web.port(), "/../CMakeLists.txt").status, 404);
  EXPECT_EQ(http_request("127.0.0.1", web.port(), "/", "POST").status, 405);
  EXPECT_EQ(http_request("127.0.0.1", web.port(), "/", "HEAD").status, 200);
}

TEST(WebServer, RefusesWhatItCannotParseInItsOwnStyle) {
  WebServer web(any_port(), echo_upper);
  namespace http = boost::beast::http;
  const auto bad = raw_exchange(web.port(), "\x01\x02 nonsense\r\n\r\n");
  ASSERT_TRUE(bad);
  EXPECT_EQ(bad->result(), http::status::bad_request);
  EXPECT_EQ(bad->body(), "bad request\n");
  EXPECT_EQ(bad->at(http::field::server), "throng-view");
  EXPECT_FALSE(bad->keep_alive());
  const std::string pad(16 * 1024, 'a');
  const auto header = raw_exchange(web.port(), "GET / HTTP/1.1\r\nHost: x\r\nX-Pad: " + pad + "\r\n\r\n");
  ASSERT_TRUE(header);
  EXPECT_EQ(header->result(), http::status::request_header_fields_too_large);
  EXPECT_EQ(header->at(http::field::server), "throng-view");
  const std::string big(8192, 'b');  // over the view's body limit (kHttpBodyLimit)
  const auto body = raw_exchange(web.port(), "POST / HTTP/1.1\r\nHost: x\r\nContent-Length: 8192\r\n\r\n" + big);
  ASSERT_TRUE(body);
  EXPECT_EQ(body->result(), http::status::payload_too_large);
  EXPECT_EQ(body->body(), "payload too large\n");
}

TEST(WebServer, ServesAWebRootWithoutLeavingIt) {
  TempDir dir;
  std::filesystem::create_directories(dir / "web");
  { std::ofstream(dir / "web" / "index.html") << "hello"; }
  { std::ofstream(dir / "secret.txt") << "secret"; }
  auto o = any_port();
  o.web_root = (dir / "web").string();
  WebServer web(o, echo_upper);
  EXPECT_EQ(http_request("127.0.0.1", web.port(), "/").body, "hello");
  EXPECT_EQ(http_request("127.0.0.1", web.port(), "/../secret.txt").status, 404);
  EXPECT_EQ(http_request("127.0.0.1", web.port(), "/%2e%2e/secret.txt").status, 404);
}

TEST(WebServer, WebSocketGreetingBroadcastAndReply) {
  WebServer web(any_port(), echo_upper);
  web.set_greeting(R"({"type":"match","n":1})");
  WsClient ws("127.0.0.1", web.port(), "/ws");
  const auto hello = ws.read(5s);
  ASSERT_TRUE(hello);
  EXPECT_EQ(*hello, R"({"type":"match","n":1})");
  ASSERT_TRUE(wait_until([&] { return web.sessions() == 1; }, 5s));
  web.broadcast("frame-1");
  EXPECT_TRUE(read_until(ws, "frame-1"));
  ws.send("abc");
  EXPECT_TRUE(read_until(ws, "ABC"));
  ws.send("x", /*binary=*/true);
  EXPECT_TRUE(read_until(ws, "binary"));
  web.set_greeting("match-2");  // a new match reaches open pages too
  EXPECT_TRUE(read_until(ws, "match-2"));
}

TEST(WebServer, RefusesCrossOriginWebSockets) {
  WebServer web(any_port(), echo_upper);
  const std::string self = "http://127.0.0.1:" + std::to_string(web.port());
  EXPECT_THROW(WsClient("127.0.0.1", web.port(), "/ws", 5s, "http://evil.example"), std::runtime_error);
  EXPECT_NO_THROW(WsClient("127.0.0.1", web.port(), "/ws", 5s, self));
  EXPECT_THROW(WsClient("127.0.0.1", web.port(), "/elsewhere", 5s), std::runtime_error);
}

TEST(WebServer, PortInUseIsAClearError) {
  WebServer first(any_port(), echo_upper);
  auto o = any_port();
  o.port = first.port();
  try {
    WebServer second(o, echo_upper);
    FAIL() << "bound a port in use";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("cannot listen on 127.0.0.1:" + std::to_string(first.port()) + ": address in use"),
              std::string::npos)
        << e.what();
  }
}

TEST(WebServer, StopsWithPagesConnected) {
  auto web = std::make_unique<WebServer>(any_port(), echo_upper);
  WsClient ws("127.0.0.1", web->port(), "/ws");
  ASSERT_TRUE(wait_until([&] { return web->sessions() == 1; }, 5s));
  const auto t0 = Clock::now();
  web.reset();
  EXPECT_LT(Clock::now() - t0, 2s);
}

}  // namespace
}  // namespace throng::view
