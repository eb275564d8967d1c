// validate_config: every field's range, checked once before a match is built.
#include <cmath>
#include <stdexcept>
#include <string>

#include <fmt/format.h>

#include "throng/match/match_config.h"

#include "interest_grid.h"

namespace throng::match {
namespace {

void check(double v, double lo, double hi, const char* field, bool lo_open = false) {
  const bool low_bad = lo_open ? !(v > lo) : !(v >= lo);
  if (!std::isfinite(v) || low_bad || v > hi) {
    throw std::invalid_argument(fmt::format("{}: {} is outside {}{}, {}]", field, v, lo_open ? "(" : "[", lo, hi));
  }
}

}  // namespace

void validate_config(const MatchConfig& c) {
  check(c.tick_hz, 1, 1000, "tick_hz");
  check(c.max_clients, 1, 100000, "max_clients");
  check(c.client_timeout_s, 0.0, 86400.0, "client_timeout_s", true);
  if (std::llround(c.client_timeout_s * c.tick_hz) < 1) {
    throw std::invalid_argument(
        fmt::format("client_timeout_s: {} s is shorter than one tick at {} Hz", c.client_timeout_s, c.tick_hz));
  }
  check(c.max_commands_per_tick, 1, 1000, "max_commands_per_tick");
  check(c.worker_threads, 1, 64, "worker_threads");
  check(c.solver_threads, 1, 64, "solver_threads");
  check(c.player_speed_mps, 0.0, 100.0, "player_speed_mps", true);
  check(c.npc_speed_mps, 0.0, 100.0, "npc_speed_mps", true);
  // No further than snapshots serve (interest_grid.h): a camera the match accepted must not make the
  // snapshot phase throw.
  check(c.camera_limit_m, 0.0, detail::kMaxCoordinateM, "camera_limit_m", true);
  check(c.interest.radius_m, 0.0, 1e6, "interest.radius_m");
  check(c.interest.exit_hysteresis, 1.0, 10.0, "interest.exit_hysteresis");
  if (c.interest.budget_bytes != 0)  // 0 = unlimited (measurements, LAN spectators)
    check(c.interest.budget_bytes, 128, 1u << 24, "interest.budget_bytes");
  check(c.interest.keepalive_ticks, 1, 1e6, "interest.keepalive_ticks");
  check(c.interest.removed_repeat, 1, 1000, "interest.removed_repeat");
  check(c.contacts.max_clients, 0, 256, "contacts.max_clients");
  check(c.contacts.max_pairs, 1, 1024, "contacts.max_pairs");
  check(c.contacts.radius_m, 0.0, 1000.0, "contacts.radius_m", true);
}

}  // namespace throng::match
