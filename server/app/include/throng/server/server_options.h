#pragma once
// throng-server's configuration: every command-line option as a field with its default, and the
// parser that turns argv into it with clear errors (tested in tests/server/server_cli_test.cpp).
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "throng/match/match_config.h"

namespace throng::server {

// --listen agones: the port Agones allocated to the GameServer's port named "dds".
inline constexpr const char* kListenAgones = "agones";

struct ServerOptions {
  std::string scene = "battle";    // built-in scene name or scene JSON file
  std::uint64_t npcs = 6000;       // scale the scene to this many bodies; 0 = the scene's own count
  int domain = 0;                  // DDS domain id, 0..231
  bool loopback_only = true;       // DDS on 127.0.0.1 only (false: Fast DDS default transports)
  std::string listen;              // --listen udp://ADDR:PORT, tcp://ADDR:PORT or "agones": DDS on that port only (clients --server)
  std::string public_address;      // --public-address IP: the address clients are told (NAT, LB)
  double duration_s = 0.0;         // 0 = until SIGINT/SIGTERM
  int admin_port = 9470;           // -1 = no admin HTTP, 0 = any free port
  std::string admin_bind = "127.0.0.1";
  std::string summary_json;        // written at exit when set
  std::string log_file = "auto";   // match log: "auto" = logs/<match id>.tlog, "" = none (--no-log)
  std::string log_level = "info";  // trace, debug, info, warn, error
  std::string log_format = "text"; // text or json (one object per line, for log collectors)
  std::string log_dir = "logs";    // where --log auto puts <match id>.tlog
  // Keyframes in the match log keep the snapshot baselines: `throng-replay play` then publishes,
  // from any seek on, byte for byte what the server sent. Off: keyframes are about a third the
  // size with 50 clients; play after a seek starts every client's snapshots afresh.
  bool log_baselines = false;
  // A world keyframe every this many ticks (rounded up to the log's 15-tick blocks; 0 = none):
  // a seek re-simulates up to this many ticks; keyframes are most of a log's size.
  std::uint32_t log_keyframe_ticks = 60;
  std::uint32_t max_catchup_ticks = 3;
  // Every this many seconds a thread of its own hands the memory malloc holds freed back to the
  // system (memory_trimmer.h); 0 = never.
  double trim_memory_s = 10.0;
  // Parameter changes (ParamUpdate) are accepted only from operators. With --security, DDS access
  // control lets only identities with the operator permission write them; without it, nobody can
  // be told apart, so they are refused unless this is set (development, tests, local tools).
  bool allow_anonymous_operator = false;
  // End of match besides --duration: every player has left and none came back for this many
  // seconds (counted once a first player joined). 0 = off.
  double end_when_empty_s = 0.0;
  // ... or one side has been routed (every AI group of a faction retreating) for this many
  // seconds. 0 = off.
  double end_when_routed_s = 0.0;
  // Agones REST SDK sidecar port (agones_sdk.h): from AGONES_SDK_HTTP_PORT; 0 = not under Agones.
  std::uint16_t agones_port = 0;
  std::uint32_t agones_health_interval_ms = 2000;  // tests shorten it
  // Tests only: called on the tick thread after each tick with its number (a test stalls the tick
  // loop with it). Never set by the command line.
  std::function<void(std::uint64_t)> tick_hook_for_tests;
  // --standby: follow the primary of this domain's match as a hot standby (standby_server.h)
  // instead of hosting one; the scene and match config come from the primary.
  bool standby = false;
  // --takeover-after-ticks: the standby takes the match over when the primary's tick entries stop
  // for this many ticks (0 = never: it only follows).
  std::uint32_t takeover_after_ticks = 3;
  // Tests only: the standby calls it with each tick entry before following it (a test alters one
  // to make the standby diverge on purpose). Never set by the command line.
  std::function<void(std::uint64_t tick, std::vector<std::uint8_t>& entry)> standby_entry_hook_for_tests;
  std::string security_dir;        // --security DIR: DDS Security with the server identity in DIR
  match::MatchConfig match;        // tick rate, clients, interest ... (match_config.h)
};

// Outcome of parsing: options, or text to print and an exit code (--help: 0, errors: 2).
struct ParseResult {
  std::optional<ServerOptions> options;
  std::string message;
  int exit_code = 0;
};

ParseResult parse_server_options(const std::vector<std::string>& args);  // args without argv[0]

}  // namespace throng::server
