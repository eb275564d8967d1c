#include "throng/server/agones_sdk.h"

#include <sys/socket.h>
#include <sys/time.h>

#include <condition_variable>
#include <cstdlib>
#include <mutex>
#include <stdexcept>
#include <thread>

#include <boost/asio/connect.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

namespace throng::server {

namespace {

namespace asio = boost::asio;
namespace http = boost::beast::http;
using Clock = std::chrono::steady_clock;

void set_socket_timeout(asio::ip::tcp::socket& s, std::chrono::milliseconds t) {
  timeval tv{};
  tv.tv_sec = static_cast<time_t>(t.count() / 1000);
  tv.tv_usec = static_cast<suseconds_t>((t.count() % 1000) * 1000);
  ::setsockopt(s.native_handle(), SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
  ::setsockopt(s.native_handle(), SOL_SOCKET, SO_SNDTIMEO, &tv, sizeof tv);
}

// One request on a fresh connection (the sidecar is local; nothing to gain from keep-alive).
// Returns the response body; throws on a connection error or a non-2xx status.
std::string http_call(std::uint16_t port, http::verb verb, const std::string& target, const std::string& body,
                      std::chrono::milliseconds timeout) {
  asio::io_context io;
  asio::ip::tcp::socket socket(io);
  socket.connect({asio::ip::make_address("127.0.0.1"), port});
  set_socket_timeout(socket, timeout);
  http::request<http::string_body> req{verb, target, 11};
  req.set(http::field::host, "127.0.0.1");
  req.set(http::field::content_type, "application/json");
  req.set(http::field::connection, "close");
  req.body() = body;
  req.prepare_payload();
  http::write(socket, req);
  boost::beast::flat_buffer buffer;
  http::response<http::string_body> res;
  http::read(socket, buffer, res);
  boost::system::error_code ignored;
  socket.shutdown(asio::ip::tcp::socket::shutdown_both, ignored);
  if (res.result_int() / 100 != 2) throw std::runtime_error("HTTP " + std::to_string(res.result_int()) + " " + res.body());
  return res.body();
}

}  // namespace

AgonesEndpoint agones_endpoint(std::uint16_t sdk_port, const std::string& port_name, std::chrono::milliseconds timeout) {
  const auto deadline = Clock::now() + timeout;
  std::string last_problem;
  while (true) {
    try {
      const auto j = nlohmann::json::parse(http_call(sdk_port, http::verb::get, "/gameserver", "", std::chrono::seconds(2)));
      const auto& status = j.at("status");
      AgonesEndpoint e;
      e.address = status.value("address", std::string());
      for (const auto& p : status.value("ports", nlohmann::json::array()))
        if (p.value("name", std::string()) == port_name) e.port = static_cast<std::uint16_t>(p.value("port", 0));
      if (!e.address.empty() && e.port != 0) return e;
      last_problem = "the GameServer has no address or no port named '" + port_name + "' yet";
    } catch (const std::exception& e) {
      last_problem = e.what();
    }
    if (Clock::now() > deadline)
      throw std::runtime_error("Agones SDK on 127.0.0.1:" + std::to_string(sdk_port) + ": GET /gameserver gave no endpoint within " +
                               std::to_string(timeout.count() / 1000) + " s (" + last_problem + ")");
    std::this_thread::sleep_for(std::chrono::milliseconds(250));
  }
}

std::uint16_t agones_port_from_environment() {
  const char* v = std::getenv("AGONES_SDK_HTTP_PORT");
  if (v == nullptr || *v == '\0') return 0;
  char* end = nullptr;
  const long p = std::strtol(v, &end, 10);
  if (*end != '\0' || p < 1 || p > 65535)
    throw std::invalid_argument(std::string("AGONES_SDK_HTTP_PORT must be a port number (1-65535), got '") + v + "'");
  return static_cast<std::uint16_t>(p);
}

struct AgonesSdk::Impl {
  AgonesOptions options;
  const AgonesProbe& probe;
  std::mutex mutex;
  std::condition_variable wake;
  bool stopping = false;
  bool shutdown_sent = false;
  std::atomic<std::uint64_t> pings{0}, withheld{0};
  std::atomic<bool> ready{false};
  bool failing = false;  // the last call failed (log the first failure and the recovery only)
  std::thread thread;

  Impl(const AgonesOptions& o, const AgonesProbe& p) : options(o), probe(p) { thread = std::thread([this] { run(); }); }

  bool call(http::verb verb, const std::string& target, const std::string& body) {
    try {
      (void)http_call(options.port, verb, target, body, options.request_timeout);
      if (failing) spdlog::info("Agones SDK on port {} answers again", options.port);
      failing = false;
      return true;
    } catch (const std::exception& e) {
      if (!failing)
        spdlog::warn("Agones SDK on 127.0.0.1:{}: {} {} failed ({}); retrying every {} ms", options.port,
                     std::string(http::to_string(verb)), target, e.what(), options.retry_interval.count());
      failing = true;
      return false;
    }
  }

  // Sleeps until `until` or stop; returns false when stopping.
  bool sleep_until(Clock::time_point until) {
    std::unique_lock<std::mutex> lock(mutex);
    return !wake.wait_until(lock, until, [this] { return stopping; });
  }

  void run() {
    // Ready: once the first tick ran.
    while (probe.ticks.load() == 0 && !probe.ended.load())
      if (!sleep_until(Clock::now() + std::chrono::milliseconds(20))) return;
    while (!probe.ended.load() && !call(http::verb::post, "/ready", "{}"))
      if (!sleep_until(Clock::now() + options.retry_interval)) return;
    if (!probe.ended.load()) {
      ready = true;
      spdlog::info("Agones: ready (health every {} ms while the tick loop runs)", options.health_interval.count());
    }
    std::uint64_t ticks_at_ping = probe.ticks.load();
    std::uint32_t players_labelled = UINT32_MAX;
    auto next_health = Clock::now();
    bool stalled = false;
    while (!probe.ended.load()) {
      const std::uint32_t players = probe.players.load();
      if (players != players_labelled &&
          call(http::verb::put, "/metadata/label",
               "{\"key\":\"" + options.player_label + "\",\"value\":\"" + std::to_string(players) + "\"}"))
        players_labelled = players;
      if (Clock::now() >= next_health) {
        const std::uint64_t ticks = probe.ticks.load();
        if (ticks != ticks_at_ping || pings.load() == 0) {
          if (call(http::verb::post, "/health", "{}")) {
            ++pings;
            ticks_at_ping = ticks;
            if (stalled) spdlog::info("tick loop running again: Agones health pings resumed");
            stalled = false;
          }
        } else {
          ++withheld;
          if (!stalled) spdlog::error("no tick completed for {} ms: Agones health pings withheld", options.health_interval.count());
          stalled = true;
        }
        next_health += options.health_interval;
        if (next_health < Clock::now()) next_health = Clock::now() + options.health_interval;
      }
      if (!sleep_until(std::min(next_health, Clock::now() + std::chrono::milliseconds(100)))) return;
    }
    // The match ended: the log is flushed and "ended" published by now.
    for (int attempt = 0; attempt < 20; ++attempt) {
      if (call(http::verb::post, "/shutdown", "{}")) {
        spdlog::info("Agones: shutdown requested");
        std::lock_guard<std::mutex> lock(mutex);
        shutdown_sent = true;
        wake.notify_all();
        return;
      }
      if (!sleep_until(Clock::now() + options.retry_interval)) return;
    }
    spdlog::error("Agones: the sidecar did not acknowledge /shutdown; Agones will find the process gone");
  }
};

AgonesSdk::AgonesSdk(const AgonesOptions& options, const AgonesProbe& probe)
    : impl_(std::make_unique<Impl>(options, probe)) {}

AgonesSdk::~AgonesSdk() {
  {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    impl_->stopping = true;
  }
  impl_->wake.notify_all();
  if (impl_->thread.joinable()) impl_->thread.join();
}

bool AgonesSdk::wait_shutdown_sent(std::chrono::milliseconds timeout) {
  std::unique_lock<std::mutex> lock(impl_->mutex);
  return impl_->wake.wait_for(lock, timeout, [this] { return impl_->shutdown_sent; });
}

std::uint64_t AgonesSdk::health_pings() const { return impl_->pings.load(); }
std::uint64_t AgonesSdk::health_withheld() const { return impl_->withheld.load(); }
bool AgonesSdk::ready_sent() const { return impl_->ready.load(); }

}  // namespace throng::server
