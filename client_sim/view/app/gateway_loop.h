#pragma once
// The gateway loop of throng-view: DDS in, web out. Threads:
//  - Fast DDS listener threads: only copy what arrives into the Inbox (match info, join replies,
//    snapshots with their arrival time) and wake the loop;
//  - the web thread (WebServer): parses and validates page messages into the InputSlot;
//  - the loop thread (run_gateway): everything else — the Gateway, commands at the tick rate,
//    frames to the pages after each applied snapshot.
#include <atomic>
#include <chrono>
#include <string>

namespace throng::view {

struct ViewOptions {
  int domain = 0;
  bool loopback = true;
  std::string server;        // --server tcp://HOST:PORT (empty: discovery on the domain)
  std::string security_dir;  // --security DIR (empty: off)
  std::string identity;      // --identity NAME: the player (or operator) the viewer authenticates as
  std::string bind = "127.0.0.1";
  int port = 8088;
  std::string name = "throng-view";
  std::string web_root;
  double server_wait_s = 10.0;
  double join_timeout_s = 10.0;
  bool quiet = false;
};

// Exit codes: 0 stopped (SIGINT/SIGTERM), 1 usage/port/DDS error, 2 no server, 3 join refused or
// unanswered.
int run_gateway(const ViewOptions& options, const std::atomic<bool>& stop);

}  // namespace throng::view
