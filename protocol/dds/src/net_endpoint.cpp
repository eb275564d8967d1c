// "tcp://HOST:PORT" as the server's --listen and the clients' --server take it.
#include <string>

#include "throng/protocol/dds_transport.h"

namespace throng::protocol {

TcpEndpoint parse_tcp_endpoint(const std::string& text) {
  const std::string prefix = "tcp://";
  const std::string usage = "'" + text + "' is not tcp://HOST:PORT";
  if (text.rfind(prefix, 0) != 0) throw TransportError(usage + " (it must start with tcp://)");
  const std::string rest = text.substr(prefix.size());
  const auto colon = rest.rfind(':');
  if (colon == std::string::npos || colon == 0) throw TransportError(usage + " (host and port are both needed)");
  TcpEndpoint e;
  e.host = rest.substr(0, colon);
  const std::string port = rest.substr(colon + 1);
  if (port.empty() || port.size() > 5 || port.find_first_not_of("0123456789") != std::string::npos)
    throw TransportError(usage + " (the port must be a number 1-65535)");
  const unsigned long p = std::stoul(port);
  if (p < 1 || p > 65535) throw TransportError(usage + " (the port must be a number 1-65535)");
  e.port = static_cast<std::uint16_t>(p);
  return e;
}

std::string check_tcp_endpoint(const std::string& text) {
  try {
    (void)parse_tcp_endpoint(text);
    return {};
  } catch (const TransportError& e) {
    return e.what();
  }
}

}  // namespace throng::protocol
