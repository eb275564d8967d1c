#include "chromium.h"

#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <vector>

namespace throng::view::testing {

Chromium start_chromium(const TempDir& dir) {
  Chromium c;
  std::vector<std::string> args{"--headless=new",
                                "--remote-debugging-port=0",
                                "--user-data-dir=" + (dir / "chrome-profile").string(),
                                "--no-first-run",
                                "--no-default-browser-check",
                                "--disable-dev-shm-usage",
                                "--mute-audio",
                                "--window-size=1280,800"};
  if (::geteuid() == 0) args.push_back("--no-sandbox");  // Chromium refuses to run as root with it
  args.push_back("about:blank");
  c.process = std::make_unique<ChildProcess>(kChromium, args, dir / "chrome.out", dir / "chrome.err", /*own_group=*/true);
  const auto port_file = dir / "chrome-profile" / "DevToolsActivePort";
  if (!wait_until([&] { return !read_file(port_file).empty() && read_file(port_file).find('\n') != std::string::npos; },
                  30s))
    return c;
  c.devtools_port = static_cast<std::uint16_t>(std::stoi(read_file(port_file)));
  return c;
}

std::string page_target(std::uint16_t devtools_port) {
  const auto list = nlohmann::json::parse(http_request("127.0.0.1", devtools_port, "/json/list").body);
  for (const auto& t : list) {
    if (t.value("type", "") == "page") {
      const std::string url = t.value("webSocketDebuggerUrl", "");
      const auto slash = url.find('/', std::string("ws://").size());
      if (slash != std::string::npos) return url.substr(slash);
    }
  }
  return {};
}

std::string save_screenshot(Cdp& cdp, const std::string& name, const std::string& docs_name) {
  const auto shot = cdp.call("Page.captureScreenshot", {{"format", "png"}});
  std::string png = base64_decode(shot.value("data", ""));
  if (png.size() < 8) return {};
  const auto artifacts = std::filesystem::path(THRONG_BIN_DIR) / ".." / "artifacts";
  std::filesystem::create_directories(artifacts);
  std::ofstream(artifacts / name, std::ios::binary) << png;
  if (const char* update = std::getenv("THRONG_UPDATE_SCREENSHOT"); update && std::string(update) == "1") {
    const auto docs = std::filesystem::path(THRONG_SOURCE_DIR) / "docs";
    std::filesystem::create_directories(docs);
    std::filesystem::copy_file(artifacts / name, docs / docs_name, std::filesystem::copy_options::overwrite_existing);
  }
  return png;
}

}  // namespace throng::view::testing
