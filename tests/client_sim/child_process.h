#pragma once
// Test helpers for running throng-server next to the bots (the process and temp-dir plumbing is
// tests/support/child_process.h).
#include <sys/types.h>

#include <chrono>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "support/child_process.h"

namespace throng::client_sim::testing {

using throng::test::ChildProcess;
using throng::test::read_file;
using throng::test::TempDir;

// throng-server from THRONG_BIN_DIR with the test defaults (loopback, no admin port, summary in
// dir/summary.json, log in dir/server.log).
std::vector<std::string> server_args(int domain, const std::filesystem::path& dir, std::vector<std::string> extra);
std::unique_ptr<ChildProcess> start_server(int domain, const TempDir& dir, std::vector<std::string> extra = {});
// Interrupts the server, waits (bounded) for it to exit and reads its summary JSON.
nlohmann::json stop_server_and_read_summary(ChildProcess& server, const TempDir& dir);

const nlohmann::json* find_client(const nlohmann::json& summary, const std::string& name);

}  // namespace throng::client_sim::testing
