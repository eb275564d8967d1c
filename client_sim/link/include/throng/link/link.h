#pragma once
// The emulated path between a client's home network and the server's: packets read from one
// descriptor (a TUN device, or in tests a datagram socket) go through the home NAT and the
// direction's impairment, wait in a queue until their release time, and are written to the other.
//  up   = client -> server: the NAT rewrites the source as the packet leaves home, then the path;
//  down = server -> client: the path, then the NAT as the packet reaches the home router.
#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <optional>
#include <queue>
#include <vector>

#include "throng/link/home_nat.h"
#include "throng/link/impairment.h"

namespace throng::link {

struct LinkConfig {
  ImpairmentConfig up;
  ImpairmentConfig down;
  std::optional<NatConfig> nat;  // nullopt: the client's address is routed as it is
  std::uint64_t seed = 1;
};

struct LinkCounters {
  std::uint64_t not_ipv4 = 0;      // IPv6 and malformed packets: dropped
  std::uint64_t nat_dropped_up = 0;  // outbound protocols the NAT does not carry
  std::uint64_t nat_dropped_down = 0;
  std::uint64_t write_errors = 0;
};

class Link {
 public:
  // client_fd / server_fd: non-blocking descriptors, one packet per read and write.
  Link(LinkConfig config, int client_fd, int server_fd);

  // Forwards until `stop` is set or `until` passes; `progress` (if set) is called about every
  // `progress_every` from the loop.
  void run(const std::atomic<bool>& stop, std::optional<std::chrono::steady_clock::time_point> until = std::nullopt,
           const std::function<void()>& progress = {},
           std::chrono::milliseconds progress_every = std::chrono::milliseconds(0));

  const Impairment& up() const { return up_; }
  const Impairment& down() const { return down_; }
  const HomeNat* nat() const { return nat_ ? &*nat_ : nullptr; }
  const LinkCounters& counters() const { return counters_; }
  double seconds() const;

 private:
  struct Pending {
    Micros release;
    std::uint64_t order;  // arrival order breaks ties: equal release times keep their order
    std::vector<std::uint8_t> bytes;
    bool operator>(const Pending& o) const { return release != o.release ? release > o.release : order > o.order; }
  };
  using Queue = std::priority_queue<Pending, std::vector<Pending>, std::greater<>>;

  Micros now() const;
  void read_all(int fd, bool from_client);
  void release_due(Micros t);

  LinkConfig config_;
  int client_fd_, server_fd_;
  Impairment up_, down_;
  std::optional<HomeNat> nat_;
  Queue to_server_, to_client_;
  std::uint64_t order_ = 0;
  std::vector<std::uint8_t> buffer_ = std::vector<std::uint8_t>(65536);
  std::chrono::steady_clock::time_point start_;
  LinkCounters counters_;
};

}  // namespace throng::link
