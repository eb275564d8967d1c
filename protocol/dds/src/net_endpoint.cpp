// "tcp://HOST:PORT" and "udp://HOST:PORT" as the server's --listen and the clients' --server take them.
#include <string>

#include "throng/protocol/dds_transport.h"

namespace throng::protocol {

NetEndpoint parse_endpoint(const std::string& text) {
  const std::string usage = "'" + text + "' is not tcp://HOST:PORT or udp://HOST:PORT";
  NetEndpoint e;
  std::string rest;
  if (text.rfind("tcp://", 0) == 0) {
    e.scheme = NetEndpoint::Scheme::tcp;
  } else if (text.rfind("udp://", 0) == 0) {
    e.scheme = NetEndpoint::Scheme::udp;
  } else {
    throw TransportError(usage + " (it must start with tcp:// or udp://)");
  }
  rest = text.substr(6);
  const auto colon = rest.rfind(':');
  if (colon == std::string::npos || colon == 0) throw TransportError(usage + " (host and port are both needed)");
  e.host = rest.substr(0, colon);
  const std::string port = rest.substr(colon + 1);
  if (port.empty() || port.size() > 5 || port.find_first_not_of("0123456789") != std::string::npos)
    throw TransportError(usage + " (the port must be a number 1-65535)");
  const unsigned long p = std::stoul(port);
  if (p < 1 || p > 65535) throw TransportError(usage + " (the port must be a number 1-65535)");
  e.port = static_cast<std::uint16_t>(p);
  return e;
}

std::string check_endpoint(const std::string& text) {
  try {
    (void)parse_endpoint(text);
    return {};
  } catch (const TransportError& e) {
    return e.what();
  }
}

}  // namespace throng::protocol
