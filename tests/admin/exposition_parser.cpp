#include "exposition_parser.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <set>

namespace throng::admin::test {
namespace {

bool name_char(char c, bool first) {
  const bool alpha = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_' || c == ':';
  return alpha || (!first && c >= '0' && c <= '9');
}

// Reads [a-zA-Z_:][a-zA-Z0-9_:]* at `at`; empty when there is none.
std::string_view read_name(std::string_view line, std::size_t& at) {
  const std::size_t start = at;
  while (at < line.size() && name_char(line[at], at == start)) ++at;
  return line.substr(start, at - start);
}

bool parse_double(std::string_view token, double& out) {
  if (token.empty()) return false;
  const std::string s(token);
  char* end = nullptr;
  out = std::strtod(s.c_str(), &end);
  return end == s.c_str() + s.size();
}

// The family a sample belongs to: the name itself, or a histogram's name without its suffix.
std::string family_of(const Exposition& e, std::string_view sample) {
  if (e.type.count(std::string(sample))) return std::string(sample);
  for (std::string_view suffix : {"_bucket", "_sum", "_count"}) {
    if (sample.ends_with(suffix)) {
      const std::string base(sample.substr(0, sample.size() - suffix.size()));
      auto it = e.type.find(base);
      if (it != e.type.end() && it->second == "histogram") return base;
    }
  }
  return {};
}

// Parses one sample line into `e`; returns what is wrong with it, or "" when it is fine.
std::string parse_sample(Exposition& e, std::string_view line) {
  std::size_t at = 0;
  const std::string_view name = read_name(line, at);
  if (name.empty()) return "no metric name";
  std::vector<std::pair<std::string, std::string>> labels;  // values kept escaped
  if (at < line.size() && line[at] == '{') {
    ++at;
    while (at < line.size() && line[at] != '}') {
      const std::string_view key = read_name(line, at);
      if (key.empty() || key.find(':') != std::string_view::npos) return "bad label name";
      if (line.substr(at, 2) != "=\"") return "label without =\"";
      at += 2;
      const std::size_t start = at;
      while (at < line.size() && line[at] != '"') {
        if (line[at] == '\\') {
          if (at + 1 >= line.size() || std::string_view("\\\"n").find(line[at + 1]) == std::string_view::npos)
            return "bad escape in label value";
          ++at;
        } else if (line[at] == '\n') {
          return "raw newline in label value";
        }
        ++at;
      }
      if (at >= line.size()) return "unterminated label value";
      labels.emplace_back(std::string(key), std::string(line.substr(start, at - start)));
      ++at;  // closing quote
      if (at < line.size() && line[at] == ',') ++at;
    }
    if (at >= line.size()) return "unterminated label set";
    ++at;  // '}'
  }
  if (at >= line.size() || line[at] != ' ') return "no space before the value";
  ++at;
  const std::size_t space = line.find(' ', at);
  double value = 0;
  if (!parse_double(line.substr(at, space - at), value)) return "bad value";
  if (space != std::string_view::npos) {
    double timestamp = 0;
    if (!parse_double(line.substr(space + 1), timestamp)) return "bad timestamp";
  }

  std::set<std::string> names;
  for (const auto& label : labels) {
    if (!names.insert(label.first).second) return "label given twice";
  }
  const std::string family = family_of(e, name);
  if (family.empty()) return "sample before its family's TYPE";
  if (e.families.back() != family) return "sample away from its family's block";

  std::sort(labels.begin(), labels.end());
  std::string key(name);
  for (std::size_t i = 0; i < labels.size(); ++i) {
    key += (i == 0 ? "{" : ",") + labels[i].first + "=\"" + labels[i].second + "\"";
  }
  if (!labels.empty()) key += "}";
  if (!e.samples.emplace(key, value).second) return "series given twice";
  e.series_order.push_back(key);
  return "";
}

}  // namespace

double Exposition::value(const std::string& key) const {
  auto it = samples.find(key);
  if (it == samples.end()) {
    ADD_FAILURE() << key << " is not in the exposition";
    return std::nan("");
  }
  return it->second;
}

std::string series(std::string_view name, std::vector<std::pair<std::string, std::string>> labels) {
  std::sort(labels.begin(), labels.end());
  std::string key(name);
  for (std::size_t i = 0; i < labels.size(); ++i) {
    key += (i == 0 ? "{" : ",") + labels[i].first + "=\"";
    for (char c : labels[i].second) {
      if (c == '\\') key += "\\\\";
      else if (c == '"') key += "\\\"";
      else if (c == '\n') key += "\\n";
      else key += c;
    }
    key += '"';
  }
  if (!labels.empty()) key += "}";
  return key;
}

Exposition parse_exposition(const std::string& text) {
  Exposition e;
  if (!text.empty() && text.back() != '\n') ADD_FAILURE() << "the exposition does not end with a newline";
  std::size_t start = 0;
  while (start < text.size()) {
    std::size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    const std::string_view line(text.data() + start, end - start);
    start = end + 1;
    std::string why;
    if (line.starts_with("# HELP ") || line.starts_with("# TYPE ")) {
      std::size_t at = 7;
      const std::string name(read_name(line, at));
      const std::string rest(at < line.size() ? line.substr(at + 1) : std::string_view());
      if (name.empty() || at >= line.size() || line[at] != ' ') {
        why = "bad HELP/TYPE line";
      } else if (line[2] == 'H') {
        if (!e.help.emplace(name, rest).second) why = "HELP given twice";
      } else if (rest != "counter" && rest != "gauge" && rest != "histogram" && rest != "summary" && rest != "untyped") {
        why = "unknown TYPE";
      } else if (!e.type.emplace(name, rest).second) {
        why = "TYPE given twice";
      } else {
        e.families.push_back(name);
      }
    } else if (line.starts_with("#")) {
      continue;  // a comment
    } else if (line.empty()) {
      why = "empty line";
    } else {
      why = parse_sample(e, line);
    }
    if (!why.empty()) ADD_FAILURE() << why << ": \"" << line << "\"";
  }
  return e;
}

}  // namespace throng::admin::test
