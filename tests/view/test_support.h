#pragma once
// Helpers for the throng-view tests (processes and temp dirs come from tests/support): polling
// with a deadline, throng-view's port, and a small Boost.Beast WebSocket/HTTP client
// whose every operation is bounded by a timeout (used for the gateway's /ws and for Chromium's
// DevTools protocol).
#include <sys/types.h>

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "support/child_process.h"

namespace throng::view::testing {

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

using throng::test::ChildProcess;
using throng::test::read_file;
using throng::test::TempDir;

// The port in throng-view's "view at http://127.0.0.1:PORT/" line on its stdout, once printed.
std::optional<std::uint16_t> view_port(const std::filesystem::path& out);

// Polls pred every 50 ms until it is true or timeout passes; returns its last value.
bool wait_until(const std::function<bool()>& pred, std::chrono::milliseconds timeout);

// A WebSocket client; every call is bounded and throws std::runtime_error on failure or timeout
// (read() returns nullopt on timeout instead).
class WsClient {
 public:
  WsClient(const std::string& host, std::uint16_t port, const std::string& target,
           std::chrono::milliseconds timeout = 10s, const std::string& origin = {});
  ~WsClient();
  WsClient(const WsClient&) = delete;
  WsClient& operator=(const WsClient&) = delete;

  void send(const std::string& message, bool binary = false, std::chrono::milliseconds timeout = 10s);
  std::optional<std::string> read(std::chrono::milliseconds timeout);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

struct HttpResult {
  int status = 0;
  std::string body;
  std::string content_type;
};
// GET (or another method) over one connection; throws std::runtime_error on failure or timeout.
HttpResult http_request(const std::string& host, std::uint16_t port, const std::string& target,
                        const std::string& method = "GET", std::chrono::milliseconds timeout = 10s);

// Chrome DevTools Protocol over a WsClient (one page target).
class Cdp {
 public:
  Cdp(const std::string& host, std::uint16_t port, const std::string& target);
  nlohmann::json call(const std::string& method, const nlohmann::json& params = nlohmann::json::object(),
                      std::chrono::milliseconds timeout = 15s);
  // Runtime.evaluate with returnByValue; throws on a JavaScript exception.
  nlohmann::json evaluate(const std::string& expression, std::chrono::milliseconds timeout = 15s);

 private:
  WsClient ws_;
  int next_id_ = 1;
};

// A key press (keyDown with its text for a printable key, then keyUp), as a person typing it.
inline void press_key(Cdp& cdp, const std::string& key, const std::string& code, int virtual_key) {
  nlohmann::json e = {{"key", key}, {"code", code}, {"windowsVirtualKeyCode", virtual_key}, {"nativeVirtualKeyCode", virtual_key}};
  e["type"] = "keyDown";
  if (key.size() == 1) e["text"] = key;
  cdp.call("Input.dispatchKeyEvent", e);
  e.erase("text");
  e["type"] = "keyUp";
  cdp.call("Input.dispatchKeyEvent", e);
}

std::string base64_decode(const std::string& in);

}  // namespace throng::view::testing
