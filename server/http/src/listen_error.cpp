#include "listen_error.h"

#include <boost/asio/error.hpp>

namespace throng::http {

namespace {

// An IPv6 address is bracketed so the port stays readable: [::1]:8080.
std::string endpoint_text(const std::string& address, std::uint16_t port) {
  const bool v6 = address.find(':') != std::string::npos;
  return (v6 ? "[" + address + "]" : address) + ":" + std::to_string(port);
}

std::string reason_text(const boost::system::error_code& ec) {
  namespace error = boost::asio::error;
  if (ec == error::address_in_use) return "address in use";
  if (ec == error::access_denied) return "permission denied";
  if (ec == boost::system::errc::address_not_available) return "address not available on this host";
  return ec.message();
}

}  // namespace

std::string listen_error(const std::string& address, std::uint16_t port, const boost::system::error_code& ec) {
  return "cannot listen on " + endpoint_text(address, port) + ": " + reason_text(ec);
}

}  // namespace throng::http
