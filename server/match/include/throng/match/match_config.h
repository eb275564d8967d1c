#pragma once
// Everything a match is configured with besides its scene. Validated by validate_config (throws
// std::invalid_argument naming the field), so a bad command-line value never reaches a tick.
#include <cstdint>

namespace throng::match {

struct InterestConfig {
  double radius_m = 30.0;             // objects within this distance of the camera are sent; 0 = all
  double exit_hysteresis = 1.1;       // an object leaves the view at radius * this
  std::uint32_t budget_bytes = 1066;  // per client per tick (256 kbit/s at 30 Hz), headers included
  std::uint32_t keepalive_ticks = 30; // an unchanged object is still re-sent this often
  std::uint32_t removed_repeat = 3;   // a removal is repeated in this many snapshots (best-effort)
};

// The contact-pairs debug channel (protocol::kActionContacts, the ContactPairs topic; contacts.h
// says which pairs). Bounded so that it costs the server and the other clients little: only
// granted clients get it, a fixed number of pairs each, in a sample of its own (never out of the
// snapshot budget). Not part of the match log's config: it never changes a result.
struct ContactsConfig {
  std::uint32_t max_clients = 4;  // clients served at once, first come; 0 = the channel is off [0, 256]
  std::uint32_t max_pairs = 32;   // pairs per client and tick, nearest the camera first [1, 1024]
  double radius_m = 12.0;         // around the client's camera (and never beyond interest.radius_m) (0, 1000]
};

struct MatchConfig {
  std::uint32_t tick_hz = 30;
  std::uint32_t max_clients = 256;
  double client_timeout_s = 5.0;          // no command for this long: the client is dropped
  std::uint32_t max_commands_per_tick = 4;  // per client; more in one tick are rejected
  double player_speed_mps = 4.0;          // |move| = 1 gives this speed (sprint x1.5)
  double npc_speed_mps = 1.2;             // NPC cruising speed
  double camera_limit_m = 10000.0;        // |camera coordinate| above this is rejected [0, 1e6]
  // Threads building (and, with a sink, publishing) the clients' snapshots, the caller included.
  // Results do not depend on it: each client's snapshot depends only on the world and its own history.
  std::uint32_t worker_threads = 2;
  // Threads that sweep the world's crowd solve (WorldSettings::threads), the tick's thread
  // included. The state is the same bits for any number: a large crowd's tick gets shorter, a
  // small one's (up to about 5,000 bodies, one block of the schedule) does not change.
  std::uint32_t solver_threads = 1;
  // Whether the world records push events as its scene settings say (the contacts overlay, the
  // tick report's count). Results do not depend on it (World::set_push_events_recorded): a
  // re-simulation that reads no events turns it off.
  bool push_events = true;
  std::uint64_t seed = 1;                 // AI tie-breaks (deterministic)
  InterestConfig interest;
  ContactsConfig contacts;
};

void validate_config(const MatchConfig& config);

}  // namespace throng::match
