// The JSON log format escapes what a message may hold (a client's name, a file path, an error text).
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "throng/server/log_setup.h"

namespace throng::server {
namespace {

TEST(LogSetup, MessagesAreEscapedIntoValidJsonStrings) {
  const std::string nasty = "name \"x\"\\path\nline2\ttab\r\x01\x1f end";
  const std::string escaped = json_escape(nasty);
  EXPECT_EQ(escaped, "name \\\"x\\\"\\\\path\\nline2\\ttab\\r\\u0001\\u001f end");
  EXPECT_EQ(nlohmann::json::parse("\"" + escaped + "\"").get<std::string>(), nasty);
  EXPECT_EQ(json_escape("plain ütf-8"), "plain ütf-8");
}

}  // namespace
}  // namespace throng::server
