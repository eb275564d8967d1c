#include "throng/link/link_report.h"

#include <fmt/format.h>

namespace throng::link {

namespace {

double ms(Micros m) { return static_cast<double>(m.count()) / 1000.0; }

nlohmann::json config_json(const ImpairmentConfig& c) {
  return {{"delay_ms", ms(c.delay)},
          {"jitter_ms", ms(c.jitter)},
          {"loss", c.loss},
          {"burst",
           {{"p_good_to_bad", c.burst.p_good_to_bad},
            {"p_bad_to_good", c.burst.p_bad_to_good},
            {"loss_bad", c.burst.loss_bad},
            {"loss_good", c.burst.loss_good}}},
          {"reorder", c.reorder},
          {"reorder_gap_ms", ms(c.reorder_gap)},
          {"rate_kbit_per_s", static_cast<double>(c.rate_bits_per_s) / 1000.0},
          {"queue_ms", ms(c.queue)}};
}

nlohmann::json direction_json(const Impairment& path) {
  const DirectionCounters& c = path.counters();
  const DelayHistogram& d = path.delays();
  const std::uint64_t lost = c.lost_random + c.lost_burst + c.lost_queue;
  return {{"config", config_json(path.config())},
          {"packets", c.packets},
          {"bytes", c.bytes},
          {"delivered", c.delivered},
          {"lost_random", c.lost_random},
          {"lost_burst", c.lost_burst},
          {"lost_queue", c.lost_queue},
          {"loss_rate", c.packets == 0 ? 0.0 : static_cast<double>(lost) / static_cast<double>(c.packets)},
          {"loss_bursts", c.bursts},
          {"longest_loss_burst", c.longest_burst},
          {"reordered", c.reordered},
          {"delay_ms",
           {{"min", d.min_ms()},
            {"p50", d.quantile_ms(0.5)},
            {"p99", d.quantile_ms(0.99)},
            {"max", d.max_ms()},
            {"mean", d.mean_ms()}}}};
}

std::string direction_text(const char* name, const Impairment& path) {
  const DirectionCounters& c = path.counters();
  const DelayHistogram& d = path.delays();
  const std::uint64_t lost = c.lost_random + c.lost_burst + c.lost_queue;
  return fmt::format(
      "  {}: {} packets ({:.1f} kB), {} delivered, {} lost ({:.2f} %: {} random, {} burst, {} queue; longest run {}), "
      "{} reordered; delay min {:.1f} / p50 {:.1f} / p99 {:.1f} / max {:.1f} ms\n",
      name, c.packets, static_cast<double>(c.bytes) / 1000.0, c.delivered, lost,
      c.packets == 0 ? 0.0 : 100.0 * static_cast<double>(lost) / static_cast<double>(c.packets), c.lost_random,
      c.lost_burst, c.lost_queue, c.longest_burst, c.reordered, d.min_ms(), d.quantile_ms(0.5), d.quantile_ms(0.99),
      d.max_ms());
}

}  // namespace

nlohmann::json report_json(const Link& link, const LinkConfig& config) {
  nlohmann::json j = {{"seed", config.seed},
                      {"seconds", link.seconds()},
                      {"up", direction_json(link.up())},
                      {"down", direction_json(link.down())},
                      {"not_ipv4", link.counters().not_ipv4},
                      {"write_errors", link.counters().write_errors}};
  if (const HomeNat* nat = link.nat()) {
    const NatCounters& n = nat->counters();
    j["nat"] = {{"public_address", format_address(config.nat->public_address)},
                {"udp_timeout_s", static_cast<double>(config.nat->udp_timeout.count()) / 1000.0},
                {"mappings_created", n.mappings_created},
                {"mappings_expired", n.mappings_expired},
                {"mappings_now", nat->mappings()},
                {"outbound", n.outbound},
                {"inbound", n.inbound},
                {"unmapped", n.unmapped},
                {"filtered", n.filtered},
                {"unsupported", n.unsupported}};
  } else {
    j["nat"] = nullptr;
  }
  return j;
}

std::string report_text(const Link& link) {
  std::string s = fmt::format("throng-link: {:.1f} s\n", link.seconds());
  s += direction_text("up (client->server)", link.up());
  s += direction_text("down (server->client)", link.down());
  if (const HomeNat* nat = link.nat()) {
    const NatCounters& n = nat->counters();
    s += fmt::format(
        "  nat: {} mappings made ({} expired, {} now), {} out, {} in; dropped inbound: {} unmapped, {} filtered; "
        "{} unsupported\n",
        n.mappings_created, n.mappings_expired, nat->mappings(), n.outbound, n.inbound, n.unmapped, n.filtered,
        n.unsupported);
  }
  if (link.counters().not_ipv4 > 0) s += fmt::format("  {} packets that were not IPv4 dropped\n", link.counters().not_ipv4);
  return s;
}

std::string progress_line(const Link& link) {
  const auto& u = link.up().counters();
  const auto& d = link.down().counters();
  return fmt::format("throng-link: {:.0f} s: up {} packets ({} lost), down {} packets ({} lost)", link.seconds(),
                     u.packets, u.lost_random + u.lost_burst + u.lost_queue, d.packets,
                     d.lost_random + d.lost_burst + d.lost_queue);
}

}  // namespace throng::link
