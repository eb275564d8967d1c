// HttpListener on its own, over loopback: what its users (admin, throng-view) rely on beyond
// their routes, which their own suites cover: the upgrade hand-over, connections held outside the
// listener counted against the cap, the default refusal, and the bind error text.
#include <gtest/gtest.h>

#include <atomic>
#include <boost/asio/write.hpp>
#include <chrono>
#include <future>
#include <stdexcept>
#include <string>

#include "http_test_client.h"  // tests/admin: a blocking Beast client with deadlines
#include "throng/http/listener.h"

namespace throng::http {
namespace {

using namespace std::chrono_literals;
using admin::test::HttpTestClient;
namespace bhttp = boost::beast::http;

Response ok(const Request& req) {
  Response res{bhttp::status::ok, req.version()};
  res.keep_alive(req.keep_alive());
  res.body() = "ok\n";
  res.prepare_payload();
  return res;
}

ListenerOptions any_port() {
  ListenerOptions o;
  o.name = "test";
  return o;
}

TEST(HttpListener, UnansweredRequestsGoToTheUpgradeHookWithTheirSocket) {
  std::promise<std::string> target;
  HttpHandlers h;
  h.route = [](const Request& req) -> std::optional<Response> {
    if (req.target() == "/up") return std::nullopt;
    return ok(req);
  };
  h.upgrade = [&target](boost::asio::ip::tcp::socket socket, Request req) {
    // The hook owns the connection now: answer on the raw socket to prove it is live.
    boost::asio::write(socket, boost::asio::buffer(std::string("HTTP/1.1 200 OK\r\nContent-Length: 3\r\n\r\nup\n")));
    target.set_value(std::string(req.target()));
  };
  HttpListener listener(any_port(), std::move(h));
  HttpTestClient client(listener.port());
  auto res = client.get("/plain");
  ASSERT_TRUE(res);
  EXPECT_EQ(res->body(), "ok\n");
  res = client.get("/up");
  ASSERT_TRUE(res);
  EXPECT_EQ(res->body(), "up\n");
  auto got = target.get_future();
  ASSERT_EQ(got.wait_for(5s), std::future_status::ready);
  EXPECT_EQ(got.get(), "/up");
}

TEST(HttpListener, WithoutAnUpgradeHookAnUnansweredRequestCloses) {
  HttpHandlers h;
  h.route = [](const Request&) -> std::optional<Response> { return std::nullopt; };
  HttpListener listener(any_port(), std::move(h));
  HttpTestClient client(listener.port());
  EXPECT_FALSE(client.get("/"));
}

TEST(HttpListener, OtherConnectionsCountAgainstTheCap) {
  std::atomic<std::size_t> others{0};
  HttpHandlers h;
  h.route = [](const Request& req) -> std::optional<Response> { return ok(req); };
  h.other_connections = [&others] { return others.load(); };
  ListenerOptions o = any_port();
  o.max_connections = 2;
  HttpListener listener(o, std::move(h));
  {
    HttpTestClient client(listener.port());
    EXPECT_TRUE(client.get("/"));
  }
  others = 2;
  HttpTestClient refused(listener.port());
  EXPECT_FALSE(refused.get("/"));
}

TEST(HttpListener, RefusalWithoutAHandlerIsThePlainReasonAndCloses) {
  HttpHandlers h;
  h.route = [](const Request& req) -> std::optional<Response> { return ok(req); };
  HttpListener listener(any_port(), std::move(h));
  HttpTestClient client(listener.port());
  ASSERT_FALSE(client.send_raw("\x01\x02 nonsense\r\n\r\n"));
  const auto res = client.read_response();
  ASSERT_TRUE(res);
  EXPECT_EQ(res->result(), bhttp::status::bad_request);
  EXPECT_EQ(res->body(), "Bad Request\n");
  EXPECT_FALSE(res->keep_alive());
}

TEST(HttpListener, RefusalHandlerCannotKeepTheConnection) {
  HttpHandlers h;
  h.route = [](const Request& req) -> std::optional<Response> { return ok(req); };
  h.refuse = [](Status status) {
    Response res{status, 11};
    res.set(bhttp::field::server, "mine");
    res.keep_alive(true);  // the listener overrides this: the stream cannot be trusted any more
    res.prepare_payload();
    return res;
  };
  ListenerOptions o = any_port();
  o.body_limit = 16;
  HttpListener listener(o, std::move(h));
  HttpTestClient client(listener.port());
  ASSERT_FALSE(client.send_raw("POST / HTTP/1.1\r\nHost: x\r\nContent-Length: 100\r\n\r\n" + std::string(100, 'b')));
  const auto res = client.read_response();
  ASSERT_TRUE(res);
  EXPECT_EQ(res->result(), bhttp::status::payload_too_large);
  EXPECT_EQ(res->at(bhttp::field::server), "mine");
  EXPECT_FALSE(res->keep_alive());
  EXPECT_NE(client.wait_for_close(), admin::test::beast::error::timeout);
}

TEST(HttpListener, BindErrorsNameTheAddressAndTheReason) {
  HttpHandlers h;
  h.route = [](const Request& req) -> std::optional<Response> { return ok(req); };
  HttpListener first(any_port(), h);
  ListenerOptions o = any_port();
  o.port = first.port();
  try {
    HttpListener second(o, h);
    FAIL() << "bound a port in use";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), "cannot listen on 127.0.0.1:" + std::to_string(first.port()) + ": address in use");
  }
  o.bind_address = "localhost";  // names are not resolved: the operator gives an address
  try {
    HttpListener third(o, h);
    FAIL() << "bound a host name";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), "invalid bind address \"localhost\"");
  }
}

TEST(HttpListener, PostRunsOnTheListenerThreadAndIsDroppedAfterStop) {
  HttpHandlers h;
  h.route = [](const Request& req) -> std::optional<Response> { return ok(req); };
  HttpListener listener(any_port(), std::move(h));
  std::promise<std::thread::id> ran;
  listener.post([&ran] { ran.set_value(std::this_thread::get_id()); });
  auto id = ran.get_future();
  ASSERT_EQ(id.wait_for(5s), std::future_status::ready);
  EXPECT_NE(id.get(), std::this_thread::get_id());
  listener.stop();
  // After stop() there is no thread to run it and no io_context to queue it on: post() must drop
  // it without touching freed state (the sanitizer build would see that) and never run it.
  bool late = false;
  listener.post([&late] { late = true; });
  listener.stop();  // idempotent
  EXPECT_FALSE(late);
  EXPECT_NE(listener.port(), 0);
}

}  // namespace
}  // namespace throng::http
