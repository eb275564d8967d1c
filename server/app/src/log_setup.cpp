#include "throng/server/log_setup.h"

#include <memory>
#include <mutex>

#include <fmt/format.h>
#include <spdlog/pattern_formatter.h>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

namespace throng::server {

namespace {

std::mutex g_match_mutex;
std::string g_match_id = "-";

std::string current_match_id() {
  std::lock_guard<std::mutex> lock(g_match_mutex);
  return g_match_id;
}

void append(spdlog::memory_buf_t& dest, const std::string& s) { dest.append(s.data(), s.data() + s.size()); }

// %* : the match id.
class MatchIdFlag final : public spdlog::custom_flag_formatter {
 public:
  void format(const spdlog::details::log_msg&, const std::tm&, spdlog::memory_buf_t& dest) override {
    append(dest, current_match_id());
  }
  std::unique_ptr<custom_flag_formatter> clone() const override { return std::make_unique<MatchIdFlag>(); }
};

// %& : the message, escaped for a JSON string.
class JsonMessageFlag final : public spdlog::custom_flag_formatter {
 public:
  void format(const spdlog::details::log_msg& msg, const std::tm&, spdlog::memory_buf_t& dest) override {
    append(dest, json_escape(std::string(msg.payload.data(), msg.payload.size())));
  }
  std::unique_ptr<custom_flag_formatter> clone() const override { return std::make_unique<JsonMessageFlag>(); }
};

}  // namespace

std::string json_escape(const std::string& text) {
  std::string out;
  out.reserve(text.size() + 8);
  for (const char ch : text) {
    const auto c = static_cast<unsigned char>(ch);
    switch (ch) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\n': out += "\\n"; break;
      case '\r': out += "\\r"; break;
      case '\t': out += "\\t"; break;
      default:
        if (c < 0x20) out += fmt::format("\\u{:04x}", c);
        else out += ch;
    }
  }
  return out;
}

void configure_logging(LogFormat format, const std::string& level) {
  auto logger = spdlog::stderr_color_mt("throng-server");
  auto formatter = std::make_unique<spdlog::pattern_formatter>(
      format == LogFormat::json ? spdlog::pattern_time_type::utc : spdlog::pattern_time_type::local);
  formatter->add_flag<MatchIdFlag>('*').add_flag<JsonMessageFlag>('&');
  if (format == LogFormat::json)
    formatter->set_pattern(R"({"time":"%Y-%m-%dT%H:%M:%S.%eZ","level":"%l","match":"%*","msg":"%&"})");
  else
    formatter->set_pattern("[%Y-%m-%d %H:%M:%S.%e] [%^%l%$] [%*] %v");
  logger->set_formatter(std::move(formatter));
  logger->set_level(spdlog::level::from_str(level));
  spdlog::set_default_logger(logger);
}

void set_log_match_id(const std::string& match_id) {
  std::lock_guard<std::mutex> lock(g_match_mutex);
  g_match_id = match_id;
}

}  // namespace throng::server
