// A strict reader of text exposition format 0.0.4 for the tests: it checks every line's syntax
// and gives the samples by series, so a test asserts what a scraper would read, independent of
// line order and float spelling.
#pragma once

#include <map>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace throng::admin::test {

struct Exposition {
  std::map<std::string, std::string> help;  // family → HELP text, as written (escaped)
  std::map<std::string, std::string> type;  // family → TYPE
  std::vector<std::string> families;        // in the order their TYPE lines come
  std::map<std::string, double> samples;    // series() key → value
  std::vector<std::string> series_order;    // series() keys in the order they come

  bool has(const std::string& key) const { return samples.count(key) != 0; }
  // The sample's value; fails the test (and returns NaN) when the series is missing.
  double value(const std::string& key) const;
};

// The key of a series: name{a="x",b="y"} with the labels sorted by name and their values escaped as
// the format escapes them (backslash, double quote, newline); just the name without labels.
std::string series(std::string_view name, std::vector<std::pair<std::string, std::string>> labels = {});

// Fails the test (ADD_FAILURE naming the line) for every line that is not valid 0.0.4: a sample
// before its family's TYPE, a family typed twice, a series given twice, bad labels or numbers.
Exposition parse_exposition(const std::string& text);

}  // namespace throng::admin::test
