#include "throng/link/link.h"

#include <poll.h>
#include <unistd.h>

#include <cerrno>

namespace throng::link {

namespace {
// Distinct streams per direction and for the NAT: each direction's fates depend only on its own
// packets, not on how they interleave with the other direction's.
constexpr std::uint64_t kUpStream = 0x9e3779b97f4a7c15ull, kDownStream = 0xc2b2ae3d27d4eb4full,
                        kNatStream = 0x165667b19e3779f9ull;
}  // namespace

Link::Link(LinkConfig config, int client_fd, int server_fd)
    : config_(config),
      client_fd_(client_fd),
      server_fd_(server_fd),
      up_(config.up, config.seed ^ kUpStream),
      down_(config.down, config.seed ^ kDownStream),
      start_(std::chrono::steady_clock::now()) {
  if (config.nat) nat_.emplace(*config.nat, config.seed ^ kNatStream);
}

Micros Link::now() const {
  return std::chrono::duration_cast<Micros>(std::chrono::steady_clock::now() - start_);
}

double Link::seconds() const { return static_cast<double>(now().count()) / 1e6; }

void Link::read_all(int fd, bool from_client) {
  for (;;) {
    const ssize_t n = ::read(fd, buffer_.data(), buffer_.size());
    if (n <= 0) return;  // EAGAIN: drained (errors end the burst too; the next poll retries)
    std::vector<std::uint8_t> packet(buffer_.begin(), buffer_.begin() + n);
    const auto header = parse_ipv4(packet);
    if (!header) {
      ++counters_.not_ipv4;
      continue;
    }
    const Micros t = now();
    if (from_client && nat_ && nat_->outbound(packet, *header, std::chrono::steady_clock::now()) != NatVerdict::pass) {
      ++counters_.nat_dropped_up;
      continue;
    }
    Impairment& path = from_client ? up_ : down_;
    const Decision d = path.decide(t, packet.size());
    if (d.fate != Fate::deliver) continue;
    (from_client ? to_server_ : to_client_).push(Pending{d.release, order_++, std::move(packet)});
  }
}

void Link::release_due(Micros t) {
  for (Queue* q : {&to_server_, &to_client_}) {
    const bool to_client = q == &to_client_;
    while (!q->empty() && q->top().release <= t) {
      // priority_queue's top is const: the packet is copied out once, on its way out.
      std::vector<std::uint8_t> packet = q->top().bytes;
      q->pop();
      if (to_client && nat_) {
        const auto header = parse_ipv4(packet);
        if (!header || nat_->inbound(packet, *header, std::chrono::steady_clock::now()) != NatVerdict::pass) {
          ++counters_.nat_dropped_down;
          continue;
        }
      }
      if (::write(to_client ? client_fd_ : server_fd_, packet.data(), packet.size()) < 0) ++counters_.write_errors;
    }
  }
}

void Link::run(const std::atomic<bool>& stop, std::optional<std::chrono::steady_clock::time_point> until,
               const std::function<void()>& progress, std::chrono::milliseconds progress_every) {
  auto next_progress = std::chrono::steady_clock::now() + progress_every;
  while (!stop.load()) {
    const auto wall = std::chrono::steady_clock::now();
    if (until && wall >= *until) break;
    if (progress && progress_every.count() > 0 && wall >= next_progress) {
      progress();
      next_progress = wall + progress_every;
    }
    // Wake for the next release, and at least every 50 ms to look at stop and the deadline.
    Micros wait{50'000};
    const Micros t = now();
    for (const Queue* q : {&to_server_, &to_client_})
      if (!q->empty()) wait = std::min(wait, std::max(Micros(0), q->top().release - t));
    pollfd fds[2] = {{client_fd_, POLLIN, 0}, {server_fd_, POLLIN, 0}};
    const timespec ts{static_cast<time_t>(wait.count() / 1'000'000), static_cast<long>(wait.count() % 1'000'000) * 1000};
    const int r = ::ppoll(fds, 2, &ts, nullptr);
    if (r < 0 && errno != EINTR) break;
    if (r > 0) {
      if (fds[0].revents & POLLIN) read_all(client_fd_, true);
      if (fds[1].revents & POLLIN) read_all(server_fd_, false);
    }
    release_due(now());
  }
}

}  // namespace throng::link
