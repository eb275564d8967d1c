#pragma once
// throng-bots' command line, parsed into one struct (main.cpp owns the CLI11 definitions).
#include <cstdint>
#include <string>

#include "throng/client_sim/ramp.h"

namespace throng::bots {

struct Options {
  std::uint32_t clients = 10;
  double duration_s = 30.0;
  int domain = 0;
  std::string behavior = "wander";
  std::string json_path;
  bool participant_per_client = false;
  bool loopback = true;
  std::string server;                  // --server tcp://HOST:PORT (empty: discovery on the domain)
  std::string security_dir;            // --security DIR (empty: off)
  std::string identity = "bots";       // --identity: whose files in DIR the bots use
  bool ramp = false;
  client_sim::RampOptions ramp_options;
  std::uint64_t seed = 0;
  double server_wait_s = 10.0;
  double join_timeout_s = 10.0;
  double rejoin_after_s = 0.0;  // 0: never (FleetOptions::rejoin_after)
  bool progress = true;
  std::string name_prefix = "bot";
  std::uint32_t send_phases = 8;
};

}  // namespace throng::bots
