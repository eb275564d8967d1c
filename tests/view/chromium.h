#pragma once
// Headless Chromium for the end-to-end tests (Debian's /usr/bin/chromium), driven over the
// DevTools protocol (Cdp in test_support.h), plus the screenshot artifact both e2e tests keep.
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>

#include "test_support.h"

namespace throng::view::testing {

inline const std::string kChromium = "/usr/bin/chromium";

struct Chromium {
  std::unique_ptr<ChildProcess> process;
  std::uint16_t devtools_port = 0;
};

// Starts headless Chromium on about:blank and reads its DevTools port (bounded: 0 on failure).
Chromium start_chromium(const TempDir& dir);

// The DevTools WebSocket path of the first page target ("" if none).
std::string page_target(std::uint16_t devtools_port);

// Captures the page as PNG into <build>/artifacts/<name>; with THRONG_UPDATE_SCREENSHOT=1 also
// copies it to docs/<docs_name> for the README. Returns the PNG bytes ("" if the capture failed).
std::string save_screenshot(Cdp& cdp, const std::string& name, const std::string& docs_name);

}  // namespace throng::view::testing
