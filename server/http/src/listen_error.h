// The text of a failed bind: "cannot listen on ADDRESS:PORT: REASON", with the reasons an
// operator meets most (a port in use, a privileged port, an address this host does not have) in
// plain words rather than the OS's phrasing.
#pragma once

#include <boost/system/error_code.hpp>
#include <cstdint>
#include <string>

namespace throng::http {

std::string listen_error(const std::string& address, std::uint16_t port, const boost::system::error_code& ec);

}  // namespace throng::http
