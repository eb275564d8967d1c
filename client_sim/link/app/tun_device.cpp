#include "tun_device.h"

#include <arpa/inet.h>
#include <fcntl.h>
#include <linux/if_tun.h>
#include <net/if.h>
#include <net/route.h>
#include <netinet/in.h>
#include <sched.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

#include "throng/link/ipv4_packet.h"

namespace throng::link {

namespace {

[[noreturn]] void fail(const std::string& what) {
  throw std::runtime_error(what + ": " + std::strerror(errno));
}

// Closes a descriptor when it goes out of scope.
struct Fd {
  int fd = -1;
  ~Fd() {
    if (fd >= 0) ::close(fd);
  }
};

sockaddr_in ipv4(std::uint32_t address) {
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(address);
  return a;
}

std::uint32_t mask(int prefix) { return prefix == 0 ? 0 : ~std::uint32_t{0} << (32 - prefix); }

void set_up(int sock, const std::string& device, const std::string& where) {
  ifreq ifr{};
  std::strncpy(ifr.ifr_name, device.c_str(), IFNAMSIZ - 1);
  if (::ioctl(sock, SIOCGIFFLAGS, &ifr) < 0) fail(where + "cannot read the flags of " + device);
  ifr.ifr_flags = static_cast<short>(ifr.ifr_flags | IFF_UP | IFF_RUNNING);
  if (::ioctl(sock, SIOCSIFFLAGS, &ifr) < 0) fail(where + "cannot bring " + device + " up");
}

// Runs the configuration inside the namespace, then returns to the one this thread came from.
class InNamespace {
 public:
  explicit InNamespace(const std::string& name) {
    home_.fd = ::open("/proc/self/ns/net", O_RDONLY | O_CLOEXEC);
    if (home_.fd < 0) fail("cannot open this process's network namespace");
    Fd target{::open(("/run/netns/" + name).c_str(), O_RDONLY | O_CLOEXEC)};
    if (target.fd < 0) fail("network namespace '" + name + "' (make it with: ip netns add " + name + ")");
    if (::setns(target.fd, CLONE_NEWNET) < 0) fail("cannot enter network namespace '" + name + "' (root is needed)");
  }
  ~InNamespace() { (void)::setns(home_.fd, CLONE_NEWNET); }

 private:
  Fd home_;
};

}  // namespace

TunDevice::TunDevice(const TunSpec& spec) : spec_(spec) {
  if (spec.device.empty() || spec.device.size() >= IFNAMSIZ)
    throw std::runtime_error("device name '" + spec.device + "' must be 1.." + std::to_string(IFNAMSIZ - 1) + " characters");
  const std::string where = "netns " + spec.netns + ", " + spec.device + ": ";
  InNamespace inside(spec.netns);
  fd_ = ::open("/dev/net/tun", O_RDWR | O_NONBLOCK | O_CLOEXEC);
  if (fd_ < 0) fail(where + "cannot open /dev/net/tun");
  try {
    ifreq ifr{};
    ifr.ifr_flags = IFF_TUN | IFF_NO_PI;
    std::strncpy(ifr.ifr_name, spec.device.c_str(), IFNAMSIZ - 1);
    if (::ioctl(fd_, TUNSETIFF, &ifr) < 0) fail(where + "cannot create the TUN device");

    Fd sock{::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0)};
    if (sock.fd < 0) fail(where + "cannot open a configuration socket");
    set_up(sock.fd, "lo", where);
    ifr = {};
    std::strncpy(ifr.ifr_name, spec.device.c_str(), IFNAMSIZ - 1);
    const sockaddr_in address = ipv4(spec.address);
    std::memcpy(&ifr.ifr_addr, &address, sizeof address);
    if (::ioctl(sock.fd, SIOCSIFADDR, &ifr) < 0) fail(where + "cannot set address " + format_address(spec.address));
    const sockaddr_in netmask = ipv4(mask(spec.prefix));
    std::memcpy(&ifr.ifr_netmask, &netmask, sizeof netmask);
    if (::ioctl(sock.fd, SIOCSIFNETMASK, &ifr) < 0) fail(where + "cannot set the netmask");
    ifr.ifr_mtu = spec.mtu;
    if (::ioctl(sock.fd, SIOCSIFMTU, &ifr) < 0) fail(where + "cannot set the MTU");
    set_up(sock.fd, spec.device, where);
    for (const Route& r : spec.routes) {
      rtentry rt{};
      const sockaddr_in dst = ipv4(r.destination & mask(r.prefix));
      const sockaddr_in genmask = ipv4(mask(r.prefix));
      std::memcpy(&rt.rt_dst, &dst, sizeof dst);
      std::memcpy(&rt.rt_genmask, &genmask, sizeof genmask);
      rt.rt_flags = RTF_UP;
      std::string dev = spec.device;
      rt.rt_dev = dev.data();
      if (::ioctl(sock.fd, SIOCADDRT, &rt) < 0 && errno != EEXIST)
        fail(where + "cannot add the route " + format_address(r.destination) + "/" + std::to_string(r.prefix));
    }
  } catch (...) {
    ::close(fd_);
    throw;
  }
}

TunDevice::~TunDevice() {
  if (fd_ >= 0) ::close(fd_);
}

}  // namespace throng::link
