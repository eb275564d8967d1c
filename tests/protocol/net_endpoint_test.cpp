// "tcp://HOST:PORT" and "udp://HOST:PORT" as --listen and --server take it: accepted forms, and a reason for the rest.
#include <gtest/gtest.h>

#include "throng/protocol/dds_transport.h"

namespace throng::protocol {
namespace {

TEST(NetEndpoint, HostAndPortAreParsed) {
  const NetEndpoint a = parse_endpoint("tcp://10.0.0.7:7400");
  EXPECT_EQ(a.host, "10.0.0.7");
  EXPECT_EQ(a.port, 7400);
  const NetEndpoint b = parse_endpoint("tcp://match-3.example.org:65535");
  EXPECT_EQ(b.host, "match-3.example.org");
  EXPECT_EQ(b.port, 65535);
  EXPECT_EQ(check_endpoint("tcp://0.0.0.0:1"), "");
  EXPECT_EQ(a.scheme, NetEndpoint::Scheme::tcp);
  const NetEndpoint u = parse_endpoint("udp://203.0.113.7:7400");
  EXPECT_EQ(u.scheme, NetEndpoint::Scheme::udp);
  EXPECT_EQ(u.host, "203.0.113.7");
  EXPECT_EQ(u.port, 7400);
  EXPECT_EQ(u.text(), "udp://203.0.113.7:7400");
}

TEST(NetEndpoint, BadFormsSayWhatIsWrong) {
  const struct {
    const char* text;
    const char* reason;
  } cases[] = {
      {"http://1.2.3.4:5", "must start with tcp:// or udp://"},
      {"udp://1.2.3.4", "host and port are both needed"},
      {"udp://1.2.3.4:0", "1-65535"},
      {"1.2.3.4:5", "must start with tcp://"},
      {"tcp://1.2.3.4", "host and port are both needed"},
      {"tcp://:7400", "host and port are both needed"},
      {"tcp://1.2.3.4:", "1-65535"},
      {"tcp://1.2.3.4:0", "1-65535"},
      {"tcp://1.2.3.4:65536", "1-65535"},
      {"tcp://1.2.3.4:74a0", "1-65535"},
      {"tcp://1.2.3.4:-1", "1-65535"},
      {"tcp://1.2.3.4:99999999999999999999", "1-65535"},
  };
  for (const auto& c : cases) {
    EXPECT_THROW((void)parse_endpoint(c.text), TransportError) << c.text;
    const std::string why = check_endpoint(c.text);
    EXPECT_NE(why.find(c.reason), std::string::npos) << c.text << ": " << why;
    EXPECT_NE(why.find(c.text), std::string::npos) << "the message names the value: " << why;
  }
}

}  // namespace
}  // namespace throng::protocol
