// AdminServer over real loopback sockets: endpoints, status codes, limits, and clean shutdown.
// Every server binds 127.0.0.1 port 0, so tests can run in parallel; every wait is bounded.
#include <gtest/gtest.h>

#include <atomic>
#include <boost/asio/ip/tcp.hpp>
#include <chrono>
#include <stdexcept>
#include <string>

#include "http_test_client.h"
#include "throng/admin/admin_server.h"
#include "throng/admin/metrics.h"

namespace throng::admin {
namespace {

using namespace std::chrono_literals;
using test::HttpTestClient;
namespace http = test::http;

class AdminServerTest : public ::testing::Test {
 protected:
  AdminServerTest() { reg.counter("throng_ticks_total", "Ticks.").inc(42); }

  MetricsRegistry reg;
  std::atomic<bool> ready{false};
  AdminServer::ReadinessCheck check = [this] { return ready.load(); };
};

TEST_F(AdminServerTest, BindsAnEphemeralLoopbackPort) {
  AdminServer server(reg, check);
  EXPECT_NE(server.port(), 0);
  EXPECT_EQ(server.bind_address(), "127.0.0.1");
}

TEST_F(AdminServerTest, HealthzIsOk) {
  AdminServer server(reg, check);
  HttpTestClient client(server.port());
  const auto res = client.get("/healthz");
  ASSERT_TRUE(res);
  EXPECT_EQ(res->result(), http::status::ok);
  EXPECT_EQ(res->body(), "ok\n");
}

TEST_F(AdminServerTest, ReadyzFollowsTheCallback) {
  AdminServer server(reg, check);
  HttpTestClient client(server.port());
  auto res = client.get("/readyz");
  ASSERT_TRUE(res);
  EXPECT_EQ(res->result(), http::status::service_unavailable);
  EXPECT_EQ(res->body(), "not ready\n");

  ready = true;
  res = client.get("/readyz");
  ASSERT_TRUE(res);
  EXPECT_EQ(res->result(), http::status::ok);
  EXPECT_EQ(res->body(), "ready\n");
}

// A ready server that lost something (its match log) says so and stays ready (200): an
// orchestrator must not pull a match its players are in; not ready wins over degraded.
TEST_F(AdminServerTest, ReadyzSaysDegradedWithTheReasonWhileReady) {
  std::atomic<bool> lost{false};
  AdminServerOptions o;
  o.degraded = [&] { return lost.load() ? std::string("match log stopped: No space left on device") : std::string(); };
  AdminServer server(reg, check, o);
  HttpTestClient client(server.port());
  ready = true;
  auto res = client.get("/readyz");
  ASSERT_TRUE(res);
  EXPECT_EQ(res->body(), "ready\n");
  lost = true;
  res = client.get("/readyz");
  ASSERT_TRUE(res);
  EXPECT_EQ(res->result(), http::status::ok);
  EXPECT_EQ(res->body(), "degraded: match log stopped: No space left on device\n");
  ready = false;
  res = client.get("/readyz");
  ASSERT_TRUE(res);
  EXPECT_EQ(res->result(), http::status::service_unavailable);
  EXPECT_EQ(res->body(), "not ready\n");
}

TEST_F(AdminServerTest, EmptyCallbackMeansReadyAndThrowingMeansNotReady) {
  {
    AdminServer server(reg, nullptr);
    HttpTestClient client(server.port());
    const auto res = client.get("/readyz");
    ASSERT_TRUE(res);
    EXPECT_EQ(res->result(), http::status::ok);
  }
  AdminServer server(reg, []() -> bool { throw std::runtime_error("no answer"); });
  HttpTestClient client(server.port());
  const auto res = client.get("/readyz");
  ASSERT_TRUE(res);
  EXPECT_EQ(res->result(), http::status::service_unavailable);
}

TEST_F(AdminServerTest, MetricsServesRenderWithPrometheusContentType) {
  AdminServer server(reg, check);
  HttpTestClient client(server.port());
  const auto res = client.get("/metrics");
  ASSERT_TRUE(res);
  EXPECT_EQ(res->result(), http::status::ok);
  EXPECT_EQ((*res)[http::field::content_type], "text/plain; version=0.0.4; charset=utf-8");
  EXPECT_EQ(res->body(), reg.render());
  EXPECT_NE(res->body().find("throng_ticks_total 42\n"), std::string::npos);
}

TEST_F(AdminServerTest, MetricsIgnoresQueryString) {
  AdminServer server(reg, check);
  HttpTestClient client(server.port());
  const auto res = client.get("/metrics?name[]=throng_ticks_total");
  ASSERT_TRUE(res);
  EXPECT_EQ(res->result(), http::status::ok);
  EXPECT_EQ(res->body(), reg.render());
}

TEST_F(AdminServerTest, UnknownPathIs404) {
  AdminServer server(reg, check);
  HttpTestClient client(server.port());
  for (const char* path : {"/", "/nope", "/metrics/extra", "/healthz/"}) {
    const auto res = client.get(path);
    ASSERT_TRUE(res) << path;
    EXPECT_EQ(res->result(), http::status::not_found) << path;
  }
}

TEST_F(AdminServerTest, NonGetIs405WithAllowHeader) {
  AdminServer server(reg, check);
  HttpTestClient client(server.port());
  for (const auto method : {http::verb::post, http::verb::put, http::verb::delete_, http::verb::head}) {
    const auto res = client.request(method, "/metrics");
    ASSERT_TRUE(res) << http::to_string(method);
    EXPECT_EQ(res->result(), http::status::method_not_allowed) << http::to_string(method);
    EXPECT_EQ((*res)[http::field::allow], "GET");
  }
}

TEST_F(AdminServerTest, MalformedRequestIs400AndCloses) {
  AdminServer server(reg, check);
  for (const char* garbage : {"\x01\x02\x03 nonsense\r\n\r\n", "GET /metrics HTTP/9.Z\r\n\r\n",
                              "GET /metrics HTTP/1.1\r\nno colon here\r\n\r\n"}) {
    HttpTestClient client(server.port());
    ASSERT_FALSE(client.send_raw(garbage));
    const auto res = client.read_response();
    ASSERT_TRUE(res) << garbage;
    EXPECT_EQ(res->result(), http::status::bad_request) << garbage;
    EXPECT_FALSE(res->keep_alive());
    EXPECT_NE(client.wait_for_close(), test::beast::error::timeout);
  }
}

TEST_F(AdminServerTest, OversizedHeaderIs431) {
  AdminServer server(reg, check);
  HttpTestClient client(server.port());
  const std::string request = "GET /metrics HTTP/1.1\r\nHost: x\r\nX-Padding: " + std::string(16 * 1024, 'a') + "\r\n\r\n";
  ASSERT_FALSE(client.send_raw(request));
  const auto res = client.read_response();
  ASSERT_TRUE(res);
  EXPECT_EQ(res->result(), http::status::request_header_fields_too_large);
}

TEST_F(AdminServerTest, OversizedBodyIs413) {
  AdminServer server(reg, check);
  HttpTestClient client(server.port());
  const std::string body(16 * 1024, 'b');
  const std::string request =
      "POST /metrics HTTP/1.1\r\nHost: x\r\nContent-Length: " + std::to_string(body.size()) + "\r\n\r\n" + body;
  ASSERT_FALSE(client.send_raw(request));
  const auto res = client.read_response();
  ASSERT_TRUE(res);
  EXPECT_EQ(res->result(), http::status::payload_too_large);
}

TEST_F(AdminServerTest, KeepAliveServesSeveralRequestsOnOneConnection) {
  AdminServer server(reg, check);
  HttpTestClient client(server.port());
  for (int i = 0; i < 5; ++i) {
    const auto res = client.get(i % 2 ? "/healthz" : "/metrics");
    ASSERT_TRUE(res) << i;
    EXPECT_EQ(res->result(), http::status::ok);
    EXPECT_TRUE(res->keep_alive());
  }
}

TEST_F(AdminServerTest, ConnectionCloseIsHonoured) {
  AdminServer server(reg, check);
  HttpTestClient client(server.port());
  const auto res = client.request(http::verb::get, "/healthz", /*keep_alive=*/false);
  ASSERT_TRUE(res);
  EXPECT_FALSE(res->keep_alive());
  EXPECT_EQ(client.wait_for_close(), test::asio::error::eof);
}

TEST_F(AdminServerTest, StuckClientIsDisconnectedAfterTheTimeout) {
  AdminServerOptions options;
  options.io_timeout = 200ms;
  AdminServer server(reg, check, options);
  HttpTestClient client(server.port());
  ASSERT_FALSE(client.send_raw("GET /metr"));  // half a request, then nothing
  const auto start = std::chrono::steady_clock::now();
  EXPECT_NE(client.wait_for_close(), test::beast::error::timeout);
  EXPECT_LT(std::chrono::steady_clock::now() - start, 4s);
}

TEST_F(AdminServerTest, PortInUseThrowsNamingThePort) {
  AdminServer first(reg, check);
  AdminServerOptions options;
  options.port = first.port();
  try {
    AdminServer second(reg, check, options);
    FAIL() << "second server bound a port already in use";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()),
              "admin: cannot listen on 127.0.0.1:" + std::to_string(first.port()) + ": address in use");
  }
}

TEST_F(AdminServerTest, InvalidBindAddressThrows) {
  AdminServerOptions options;
  options.bind_address = "not-an-address";
  EXPECT_THROW(AdminServer(reg, check, options), std::runtime_error);
}

TEST_F(AdminServerTest, StopReturnsPromptlyWithAClientConnected) {
  AdminServer server(reg, check);
  HttpTestClient idle(server.port());
  HttpTestClient active(server.port());
  ASSERT_TRUE(active.get("/healthz"));  // a live keep-alive connection, and an idle one
  const auto start = std::chrono::steady_clock::now();
  server.stop();
  EXPECT_LT(std::chrono::steady_clock::now() - start, 1s);
  EXPECT_NE(idle.wait_for_close(), test::beast::error::timeout);
  EXPECT_NE(active.wait_for_close(), test::beast::error::timeout);
  server.stop();  // idempotent
  EXPECT_NE(server.port(), 0);
}

TEST_F(AdminServerTest, ConnectionsOverTheCapAreClosed) {
  AdminServerOptions options;
  options.max_connections = 1;
  AdminServer server(reg, check, options);
  HttpTestClient first(server.port());
  ASSERT_TRUE(first.get("/healthz"));  // the server has certainly accepted this one
  HttpTestClient second(server.port());
  EXPECT_FALSE(second.get("/healthz"));
  ASSERT_TRUE(first.get("/healthz"));  // the admitted client is unaffected
}

}  // namespace
}  // namespace throng::admin
