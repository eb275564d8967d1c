#include "child_process.h"

#include <signal.h>

#include <memory>

#include <gtest/gtest.h>

namespace throng::client_sim::testing {

std::vector<std::string> server_args(int domain, const std::filesystem::path& dir, std::vector<std::string> extra) {
  std::vector<std::string> a{"--scene",       "battle", "--npcs",         "300",
                             "--domain",      std::to_string(domain),
                             "--admin-port",  "-1",     "--duration",     "60",
                             "--summary-json", (dir / "summary.json").string(),
                             "--client-timeout", "60", "--log-level", "warn", "--no-log"};
  a.insert(a.end(), extra.begin(), extra.end());
  return a;
}

std::unique_ptr<ChildProcess> start_server(int domain, const TempDir& dir, std::vector<std::string> extra) {
  return std::make_unique<ChildProcess>(THRONG_BIN_DIR "/throng-server", server_args(domain, dir.path(), std::move(extra)),
                                        dir / "server.out", dir / "server.log");
}

nlohmann::json stop_server_and_read_summary(ChildProcess& server, const TempDir& dir) {
  server.signal(SIGINT);
  const auto code = server.wait(std::chrono::seconds(20));
  EXPECT_TRUE(code.has_value()) << "throng-server did not exit within 20 s of SIGINT";
  EXPECT_EQ(code.value_or(-1), 0) << read_file(dir / "server.log");
  const std::string text = read_file(dir / "summary.json");
  if (text.empty()) {
    ADD_FAILURE() << "no summary JSON; server log:\n" << read_file(dir / "server.log");
    return nlohmann::json::object();
  }
  return nlohmann::json::parse(text);
}

const nlohmann::json* find_client(const nlohmann::json& summary, const std::string& name) {
  if (!summary.contains("clients")) return nullptr;
  for (const auto& c : summary["clients"])
    if (c.value("name", std::string()) == name) return &c;
  return nullptr;
}

}  // namespace throng::client_sim::testing
