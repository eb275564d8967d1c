#pragma once
// What a link did, for people (one paragraph) and for scripts (JSON): per direction the packets,
// what was lost and why, and the delay distribution applied; the NAT's mappings and drops.
#include <nlohmann/json.hpp>
#include <string>

#include "throng/link/link.h"

namespace throng::link {

nlohmann::json report_json(const Link& link, const LinkConfig& config);
std::string report_text(const Link& link);
// One line for progress while the link runs.
std::string progress_line(const Link& link);

}  // namespace throng::link
