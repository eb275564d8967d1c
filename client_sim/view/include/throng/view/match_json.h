#pragma once
// The page's "match" message (scenery, roster, bounds; client_sim/view/README.md), built from a
// MatchInfo. Shared by the live gateway (MatchInfo from DDS) and the log viewer (MatchInfo of the
// re-simulated Match), so the page draws both the same way.
#include <string>
#include <string_view>

#include "throng/protocol/messages.h"

namespace throng::view {

// {"type":"match","mode":mode,...}; mode is "live" or "replay" (the page switches its controls on it).
std::string match_info_json(const protocol::MatchInfo& info, std::string_view mode);

}  // namespace throng::view
