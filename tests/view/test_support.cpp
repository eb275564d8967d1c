#include "test_support.h"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fstream>
#include <sstream>
#include <stdexcept>
#include <thread>

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>

extern char** environ;

namespace throng::view::testing {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
using tcp = asio::ip::tcp;

// --- processes --------------------------------------------------------------------------------
TempDir::TempDir() {
  std::string tmpl = (std::filesystem::temp_directory_path() / "throng-view-test-XXXXXX").string();
  if (!mkdtemp(tmpl.data())) throw std::runtime_error("mkdtemp failed");
  path_ = tmpl;
}

TempDir::~TempDir() {
  std::error_code ec;
  std::filesystem::remove_all(path_, ec);
}

ChildProcess::ChildProcess(const std::string& program, const std::vector<std::string>& args,
                           const std::filesystem::path& out, const std::filesystem::path& err, bool own_group)
    : own_group_(own_group) {
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addopen(&fa, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&fa, STDOUT_FILENO, out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_addopen(&fa, STDERR_FILENO, err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawnattr_t attr;
  posix_spawnattr_init(&attr);
  if (own_group) {
    posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETPGROUP);
    posix_spawnattr_setpgroup(&attr, 0);
  }
  std::vector<std::string> argv_s{program};
  argv_s.insert(argv_s.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& a : argv_s) argv.push_back(a.data());
  argv.push_back(nullptr);
  const int rc = posix_spawn(&pid_, program.c_str(), &fa, &attr, argv.data(), environ);
  posix_spawnattr_destroy(&attr);
  posix_spawn_file_actions_destroy(&fa);
  if (rc != 0) throw std::runtime_error("posix_spawn " + program + " failed: " + std::to_string(rc));
}

ChildProcess::~ChildProcess() { kill_now(); }

void ChildProcess::kill_now() {
  if (pid_ <= 0) return;
  if (own_group_) ::kill(-pid_, SIGKILL);  // the group this child leads: its helpers too
  if (!status_) {
    ::kill(pid_, SIGKILL);
    int st = 0;
    if (::waitpid(pid_, &st, 0) == pid_) status_ = WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
  }
}

bool ChildProcess::running() { return !wait(0ms).has_value(); }

void ChildProcess::signal(int signo) {
  if (pid_ > 0 && !status_) ::kill(pid_, signo);
}

std::optional<int> ChildProcess::wait(std::chrono::milliseconds timeout) {
  const auto until = Clock::now() + timeout;
  while (!status_) {
    int st = 0;
    if (::waitpid(pid_, &st, WNOHANG) == pid_) {
      status_ = WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
      break;
    }
    if (Clock::now() >= until) break;
    std::this_thread::sleep_for(20ms);
  }
  return status_;
}

std::string read_file(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
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
