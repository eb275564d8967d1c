#pragma once
// The gateway's web side: HTTP/1.1 for the page and its assets, a WebSocket at /ws for the live
// stream (Boost.Beast), all on one thread and one io_context owned by this class, so a slow or
// stuck browser never delays the gateway loop and the loop never blocks on a socket.
//
//   GET|HEAD /            index.html
//   GET|HEAD /<name>      an asset (embedded at build time, or read from web_root when set;
//                         only flat names of [A-Za-z0-9._-], so no path can leave the folder)
//   GET /ws + Upgrade     WebSocket: the greeting (latest match message) first, then broadcasts;
//                         page text messages go to on_message, whose answer (if any) is sent back
//   other path 404, other method 405, bad request 400, oversized header 431 or body 413. A
//   WebSocket upgrade whose Origin header (browsers always send one) is not this server
//   (http://<Host>) gets 403, so another web site open in the same browser cannot drive the
//   character.
//
// Backpressure: a session keeps at most max_queued_frames droppable messages (frames) waiting;
// older waiting frames are dropped for newer ones. Greetings and replies are never dropped.
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

namespace throng::view {

struct WebServerOptions {
  std::string bind_address = "127.0.0.1";
  std::uint16_t port = 8088;  // 0 = any free port (port() tells which)
  std::string web_root;       // empty = the embedded assets
  std::size_t max_connections = 64;
  std::size_t max_message_bytes = 64 * 1024;  // larger page messages close the WebSocket
  std::size_t max_queued_frames = 4;
  std::chrono::milliseconds http_timeout{std::chrono::seconds(10)};
};

class WebServer {
 public:
  // Called on the web thread for every page message; binary = a binary WebSocket message. The
  // returned text (if any) is sent back to that page only.
  using MessageHandler = std::function<std::optional<std::string>(std::string_view text, bool binary)>;

  // Binds and starts serving. Throws std::runtime_error
  // "cannot listen on ADDRESS:PORT: REASON" (e.g. "address in use").
  WebServer(WebServerOptions options, MessageHandler on_message);
  ~WebServer();  // stop()
  WebServer(const WebServer&) = delete;
  WebServer& operator=(const WebServer&) = delete;

  std::uint16_t port() const noexcept;
  // WebSocket sessions open now (thread-safe).
  std::size_t sessions() const noexcept;
  // Thread-safe. The greeting is sent to every page that connects from now on, and to the open
  // ones now; broadcast() sends a droppable message to every open page.
  void set_greeting(std::string message);
  void broadcast(std::string message);
  // Closes everything and joins the thread. Idempotent.
  void stop();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// The files of client_sim/view/web, embedded at build time (cmake/embed_web.cmake), so the
// binary serves the page from anywhere. find_embedded_asset("/") is index.html.
struct Asset {
  const char* name;  // "index.html"
  const unsigned char* data;
  std::size_t size;
};
const Asset* find_embedded_asset(std::string_view path);
const char* content_type_for(std::string_view name);  // by extension

}  // namespace throng::view
