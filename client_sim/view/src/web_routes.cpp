// The page server's routing (web_routes.h): which asset, which status, whether a WebSocket upgrade
// is accepted. Pure functions of the request; throng::http and web_server.cpp do the I/O.
#include "web_routes.h"

#include <algorithm>
#include <fstream>
#include <sstream>

#include <boost/beast/websocket/rfc6455.hpp>

#include "throng/view/web_server.h"

namespace throng::view {

namespace beast = boost::beast;
namespace websocket = beast::websocket;

const char* content_type_for(std::string_view name) {
  auto ends = [&](std::string_view ext) { return name.size() >= ext.size() && name.substr(name.size() - ext.size()) == ext; };
  if (ends(".html")) return "text/html; charset=utf-8";
  if (ends(".js")) return "text/javascript; charset=utf-8";
  if (ends(".css")) return "text/css; charset=utf-8";
  if (ends(".png")) return "image/png";
  if (ends(".svg")) return "image/svg+xml";
  if (ends(".json")) return "application/json";
  if (ends(".ico")) return "image/x-icon";
  return "application/octet-stream";
}

namespace {

bool flat_name(std::string_view n) {
  if (n.empty() || n.front() == '.') return false;
  return std::all_of(n.begin(), n.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '.' || c == '_' || c == '-';
  });
}

std::string_view path_of(beast::string_view target) {
  std::string_view t(target.data(), target.size());
  return t.substr(0, t.find_first_of("?#"));
}

// Browsers send Origin on every WebSocket handshake; tools (tests, curl) usually do not.
bool same_origin(const HttpRequest& req) {
  const auto origin = req.find(http::field::origin);
  if (origin == req.end()) return true;
  const auto host = req.find(http::field::host);
  if (host == req.end()) return false;
  return std::string_view(origin->value().data(), origin->value().size()) ==
         "http://" + std::string(host->value().data(), host->value().size());
}

}  // namespace

HttpResponse text_response(http::status status, std::string body, unsigned version, bool keep_alive) {
  HttpResponse res{status, version};
  res.set(http::field::server, "throng-view");
  res.set(http::field::content_type, "text/plain; charset=utf-8");
  res.keep_alive(keep_alive);
  res.body() = std::move(body);
  res.prepare_payload();
  return res;
}

namespace {

HttpResponse handle(const HttpRequest& req, const std::string& web_root) {
  const bool head = req.method() == http::verb::head;
  if (req.method() != http::verb::get && !head) {
    HttpResponse r = text_response(http::status::method_not_allowed, "method not allowed\n", req.version(), req.keep_alive());
    r.set(http::field::allow, "GET, HEAD");
    return r;
  }
  std::string_view path = path_of(req.target());
  std::string name;
  std::string body;
  bool found = false;
  if (web_root.empty()) {
    if (const Asset* a = find_embedded_asset(path)) {
      name = a->name;
      body.assign(reinterpret_cast<const char*>(a->data), a->size);
      found = true;
    }
  } else {
    name = path == "/" ? "index.html" : std::string(path.substr(path.empty() ? 0 : 1));
    if (flat_name(name)) {
      std::ifstream in(web_root + "/" + name, std::ios::binary);
      if (in) {
        std::ostringstream ss;
        ss << in.rdbuf();
        body = ss.str();
        found = true;
      }
    }
  }
  if (!found) return text_response(http::status::not_found, "not found\n", req.version(), req.keep_alive());
  HttpResponse res{http::status::ok, req.version()};
  res.set(http::field::server, "throng-view");
  res.set(http::field::content_type, content_type_for(name));
  res.set(http::field::cache_control, "no-cache");
  res.set("X-Content-Type-Options", "nosniff");
  res.set("Content-Security-Policy", "default-src 'self'; connect-src 'self'; img-src 'self' data:");
  res.keep_alive(req.keep_alive());
  res.body() = std::move(body);
  res.prepare_payload();
  if (head) res.body().clear();  // Content-Length stays the GET one
  return res;
}

}  // namespace

std::optional<HttpResponse> route_request(const HttpRequest& req, const std::string& web_root) {
  if (websocket::is_upgrade(req)) {
    if (path_of(req.target()) != "/ws") return text_response(http::status::not_found, "not found\n", req.version(), false);
    if (!same_origin(req)) return text_response(http::status::forbidden, "cross-origin WebSocket refused\n", req.version(), false);
    return std::nullopt;
  }
  return handle(req, web_root);
}

}  // namespace throng::view
