// "tcp://HOST:PORT" as --listen and --server take it: accepted forms, and a reason for the rest.
#include <gtest/gtest.h>

#include "throng/protocol/dds_transport.h"

namespace throng::protocol {
namespace {

TEST(TcpEndpoint, HostAndPortAreParsed) {
  const TcpEndpoint a = parse_tcp_endpoint("tcp://10.0.0.7:7400");
  EXPECT_EQ(a.host, "10.0.0.7");
  EXPECT_EQ(a.port, 7400);
  const TcpEndpoint b = parse_tcp_endpoint("tcp://match-3.example.org:65535");
  EXPECT_EQ(b.host, "match-3.example.org");
  EXPECT_EQ(b.port, 65535);
  EXPECT_EQ(check_tcp_endpoint("tcp://0.0.0.0:1"), "");
}

TEST(TcpEndpoint, BadFormsSayWhatIsWrong) {
  const struct {
    const char* text;
    const char* reason;
  } cases[] = {
      {"udp://1.2.3.4:5", "must start with tcp://"},
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
    EXPECT_THROW((void)parse_tcp_endpoint(c.text), TransportError) << c.text;
    const std::string why = check_tcp_endpoint(c.text);
    EXPECT_NE(why.find(c.reason), std::string::npos) << c.text << ": " << why;
    EXPECT_NE(why.find(c.text), std::string::npos) << "the message names the value: " << why;
  }
}

}  // namespace
}  // namespace throng::protocol
