#pragma once
// throng-server's log lines: plain text for a terminal, or one JSON object per line for log
// collectors (--log-format json); either way every line names the match it belongs to, so the
// lines of many matches on one host or in one fleet can be told apart.
#include <string>

namespace throng::server {

enum class LogFormat { text, json };

// Installs the default logger (stderr: stdout carries only the summary) with the format and
// level ("trace" .. "error"). Lines before set_log_match_id() show the match as "-".
void configure_logging(LogFormat format, const std::string& level);

// The match id every following line carries (thread-safe).
void set_log_match_id(const std::string& match_id);

// The JSON string escape used for the message field (exposed for tests).
std::string json_escape(const std::string& text);

}  // namespace throng::server
