// throng-link: an internet path between two network namespaces, emulated in user space (this
// kernel has no netem). It makes a TUN device in each namespace, routes the other side through
// it, and forwards every IPv4 packet between them with, in each direction, a one-way delay,
// jitter, random and bursty (Gilbert-Elliott) loss, optional reordering and a bandwidth cap; and,
// unless --no-nat, a home router's NAT (port-restricted cone) in front of the client.
//
//   ip netns add srv; ip netns add cli
//   throng-link --server-ns srv --client-ns cli --rtt-ms 100 --jitter-ms 5 --loss 0.02 --json link.json
//   # server in srv at 10.77.0.1; clients in cli at 10.77.1.2, seen by the server as 10.77.0.100
//
// Prints "throng-link: up ..." on stdout once both devices exist, a progress line every
// --progress seconds on stderr, and what it did at the end (SIGINT/SIGTERM or --duration).
// Exit codes: 0 ok, 1 setup failed (namespace missing, not root), 2 bad usage.
#include <atomic>
#include <csignal>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>

#include <CLI/CLI.hpp>

#include "throng/link/ipv4_packet.h"
#include "throng/link/link.h"
#include "throng/link/link_report.h"
#include "tun_device.h"

namespace {

std::atomic<bool> g_stop{false};
extern "C" void on_signal(int) { g_stop.store(true); }

// One impairment setting: a value for both directions, and optional overrides for each.
template <class T>
struct Both {
  T both{};
  std::optional<T> up, down;
  T get(bool is_up) const { return (is_up ? up : down).value_or(both); }
};

template <class T>
void add_both(CLI::App& app, const std::string& name, Both<T>& v, const std::string& help, CLI::Validator check) {
  app.add_option("--" + name, v.both, help + " (both directions)")->check(check)->capture_default_str();
  app.add_option("--up-" + name, v.up, help + ", client->server only")->check(check);
  app.add_option("--down-" + name, v.down, help + ", server->client only")->check(check);
}

// "P_GB,P_BG[,LOSS_BAD[,LOSS_GOOD]]"
std::optional<throng::link::GilbertElliott> parse_burst(const std::string& text, std::string& error) {
  if (text.empty()) return throng::link::GilbertElliott{};
  std::vector<double> v;
  std::stringstream in(text);
  for (std::string part; std::getline(in, part, ',');) {
    try {
      std::size_t used = 0;
      v.push_back(std::stod(part, &used));
      if (used != part.size()) throw std::invalid_argument(part);
    } catch (const std::exception&) {
      error = "'" + text + "': '" + part + "' is not a number";
      return std::nullopt;
    }
  }
  if (v.size() < 2 || v.size() > 4) {
    error = "'" + text + "' must be P_GB,P_BG[,LOSS_BAD[,LOSS_GOOD]]";
    return std::nullopt;
  }
  throng::link::GilbertElliott g;
  g.p_good_to_bad = v[0];
  g.p_bad_to_good = v[1];
  if (v.size() > 2) g.loss_bad = v[2];
  if (v.size() > 3) g.loss_good = v[3];
  return g;
}

std::optional<std::uint32_t> address_or_fail(const std::string& text, const char* what) {
  const auto a = throng::link::parse_address(text);
  if (!a) std::fprintf(stderr, "throng-link: %s '%s' is not an IPv4 address\n", what, text.c_str());
  return a;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace throng::link;
  CLI::App app{"throng-link: an emulated internet path (delay, jitter, loss, reordering, bandwidth, home NAT) "
               "between two network namespaces"};
  std::string server_ns, client_ns, server_addr = "10.77.0.1", client_addr = "10.77.1.2", nat_addr = "10.77.0.100";
  bool no_nat = false;
  std::optional<double> rtt_ms;
  Both<double> delay_ms, jitter_ms, loss, reorder, reorder_gap_ms, rate_kbps, queue_ms;
  queue_ms.both = 200;
  Both<std::string> burst;
  double nat_udp_timeout_s = 30, duration_s = 0, progress_s = 0;
  std::uint64_t seed = 1;
  std::string json_path;
  int mtu = 1500;

  app.add_option("--server-ns", server_ns, "the server's network namespace (ip netns add NAME)")->required();
  app.add_option("--client-ns", client_ns, "the clients' network namespace (their home network)")->required();
  app.add_option("--server-addr", server_addr, "the server's address, on the TUN device in --server-ns")
      ->capture_default_str();
  app.add_option("--client-addr", client_addr, "the clients' private address, on the TUN device in --client-ns")
      ->capture_default_str();
  app.add_option("--nat-addr", nat_addr, "the home router's public address, in the server's /24")->capture_default_str();
  app.add_flag("--no-nat", no_nat, "route the clients' private address as it is (no NAT)");
  app.add_option("--nat-udp-timeout", nat_udp_timeout_s, "seconds a UDP mapping lives without outbound traffic")
      ->check(CLI::Range(1.0, 3600.0))
      ->capture_default_str();
  auto* rtt = app.add_option("--rtt-ms", rtt_ms, "round trip: sets the one-way delay of both directions to half")
                  ->check(CLI::Range(0.0, 20000.0));
  auto* delay = app.add_option("--delay-ms", delay_ms.both, "one-way delay (both directions)")
                    ->check(CLI::Range(0.0, 10000.0))
                    ->capture_default_str();
  rtt->excludes(delay);
  app.add_option("--up-delay-ms", delay_ms.up, "one-way delay, client->server only")->check(CLI::Range(0.0, 10000.0));
  app.add_option("--down-delay-ms", delay_ms.down, "one-way delay, server->client only")->check(CLI::Range(0.0, 10000.0));
  add_both(app, "jitter-ms", jitter_ms, "jitter: each packet's delay is moved by up to this, uniformly",
           CLI::Range(0.0, 10000.0));
  add_both(app, "loss", loss, "random loss probability per packet", CLI::Range(0.0, 1.0));
  app.add_option("--burst", burst.both,
                 "bursty loss, Gilbert-Elliott: P_GB,P_BG[,LOSS_BAD[,LOSS_GOOD]] per packet (both directions; "
                 "mean burst 1/P_BG packets)");
  app.add_option("--up-burst", burst.up, "bursty loss, client->server only");
  app.add_option("--down-burst", burst.down, "bursty loss, server->client only");
  add_both(app, "reorder", reorder, "probability that a packet is held back and let out of order",
           CLI::Range(0.0, 1.0));
  add_both(app, "reorder-gap-ms", reorder_gap_ms, "how long a reordered packet is held back (0: twice the jitter)",
           CLI::Range(0.0, 10000.0));
  add_both(app, "rate-kbps", rate_kbps, "bandwidth cap in kbit/s (0: none)", CLI::Range(0.0, 10e6));
  add_both(app, "queue-ms", queue_ms, "the capped link's buffer, in sending time; packets beyond it are dropped",
           CLI::Range(0.0, 10000.0));
  app.add_option("--mtu", mtu, "MTU of both TUN devices")->check(CLI::Range(576, 9000))->capture_default_str();
  app.add_option("--seed", seed, "seed of every random choice (loss, jitter, reordering, NAT ports)")
      ->capture_default_str();
  app.add_option("--duration", duration_s, "seconds to run (0: until SIGINT/SIGTERM)")
      ->check(CLI::Range(0.0, 1e6))
      ->capture_default_str();
  app.add_option("--progress", progress_s, "print a progress line every this many seconds (0: never)")
      ->check(CLI::Range(0.0, 3600.0));
  app.add_option("--json", json_path, "write what the link did to this file at the end");
  CLI11_PARSE(app, argc, argv);

  const auto s_addr = address_or_fail(server_addr, "--server-addr");
  const auto c_addr = address_or_fail(client_addr, "--client-addr");
  const auto n_addr = address_or_fail(nat_addr, "--nat-addr");
  if (!s_addr || !c_addr || !n_addr) return 2;
  if ((*s_addr >> 8) == (*c_addr >> 8)) {
    std::fprintf(stderr, "throng-link: --client-addr must be outside the server's /24 (%s/24)\n", server_addr.c_str());
    return 2;
  }
  if (!no_nat && ((*n_addr >> 8) != (*s_addr >> 8) || *n_addr == *s_addr)) {
    std::fprintf(stderr, "throng-link: --nat-addr must be another address in the server's /24 (%s/24)\n",
                 server_addr.c_str());
    return 2;
  }

  LinkConfig config;
  config.seed = seed;
  const auto us = [](double ms) { return Micros(static_cast<std::int64_t>(ms * 1000.0)); };
  for (const bool up : {true, false}) {
    ImpairmentConfig& c = up ? config.up : config.down;
    c.delay = rtt_ms ? us(*rtt_ms / 2) : us(delay_ms.get(up));
    if (const auto& o = up ? delay_ms.up : delay_ms.down; o) c.delay = us(*o);
    c.jitter = us(jitter_ms.get(up));
    c.loss = loss.get(up);
    std::string error;
    const auto b = parse_burst(burst.get(up), error);
    if (!b) {
      std::fprintf(stderr, "throng-link: --%sburst %s\n", up ? "up-" : "down-", error.c_str());
      return 2;
    }
    c.burst = *b;
    c.reorder = reorder.get(up);
    c.reorder_gap = us(reorder_gap_ms.get(up));
    c.rate_bits_per_s = static_cast<std::uint64_t>(rate_kbps.get(up) * 1000.0);
    c.queue = us(queue_ms.get(up));
    if (const std::string why = check(c); !why.empty()) {
      std::fprintf(stderr, "throng-link: %s: %s\n", up ? "client->server" : "server->client", why.c_str());
      return 2;
    }
  }
  if (!no_nat) {
    NatConfig nat;
    nat.public_address = *n_addr;
    nat.udp_timeout = std::chrono::milliseconds(static_cast<std::int64_t>(nat_udp_timeout_s * 1000));
    config.nat = nat;
  }

  const std::string tag = std::to_string(::getpid() % 100000);
  std::optional<TunDevice> server_tun, client_tun;
  try {
    // The server's side routes the clients' private /24 into the link too: a reply sent to a
    // private address a client announced then reaches the emulated internet and is dropped there,
    // as it would be, instead of failing at once on this host.
    server_tun.emplace(TunSpec{server_ns, "thls" + tag, *s_addr, 24, mtu, {Route{*c_addr, 24}}});
    client_tun.emplace(TunSpec{client_ns, "thlc" + tag, *c_addr, 24, mtu, {Route{0, 0}}});
  } catch (const std::exception& e) {
    std::fprintf(stderr, "throng-link: %s\n", e.what());
    return 1;
  }

  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  std::printf("throng-link: up: %s (%s) <-> %s (%s)%s, seed %llu\n", server_ns.c_str(), server_addr.c_str(),
              client_ns.c_str(), client_addr.c_str(),
              no_nat ? "" : (", clients seen as " + nat_addr + " (port-restricted cone NAT)").c_str(),
              static_cast<unsigned long long>(seed));
  std::fflush(stdout);

  Link link(config, client_tun->fd(), server_tun->fd());
  std::optional<std::chrono::steady_clock::time_point> until;
  if (duration_s > 0)
    until = std::chrono::steady_clock::now() + std::chrono::milliseconds(static_cast<std::int64_t>(duration_s * 1000));
  link.run(
      g_stop, until, [&] { std::fprintf(stderr, "%s\n", progress_line(link).c_str()); },
      std::chrono::milliseconds(static_cast<std::int64_t>(progress_s * 1000)));

  std::fputs(report_text(link).c_str(), stdout);
  if (!json_path.empty()) {
    std::ofstream out(json_path);
    out << report_json(link, config).dump(2) << "\n";
    if (!out) {
      std::fprintf(stderr, "throng-link: cannot write %s\n", json_path.c_str());
      return 1;
    }
  }
  return 0;
}
