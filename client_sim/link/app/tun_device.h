#pragma once
// A TUN device made inside a named network namespace (`ip netns add NAME`): the kernel of that
// namespace hands the device's outgoing IP packets to this process and takes the ones written
// back as arriving on it. The device lives as long as the descriptor (closing it removes it).
#include <cstdint>
#include <string>
#include <vector>

namespace throng::link {

struct Route {
  std::uint32_t destination = 0;  // host order; 0 with prefix 0 is the default route
  int prefix = 0;
};

struct TunSpec {
  std::string netns;   // the namespace's name under /run/netns
  std::string device;  // at most 15 characters
  std::uint32_t address = 0;
  int prefix = 24;
  int mtu = 1500;
  std::vector<Route> routes;  // through the device, besides its own subnet
};

class TunDevice {
 public:
  // Enters the namespace on this thread, creates and configures the device (address, MTU, up,
  // routes, and the namespace's loopback up), and returns to the namespace it came from. Throws
  // std::runtime_error naming the step that failed.
  explicit TunDevice(const TunSpec& spec);
  ~TunDevice();
  TunDevice(const TunDevice&) = delete;
  TunDevice& operator=(const TunDevice&) = delete;

  int fd() const { return fd_; }
  const TunSpec& spec() const { return spec_; }

 private:
  TunSpec spec_;
  int fd_ = -1;
};

}  // namespace throng::link
