#pragma once
// Where a participant's DDS Security files are in a directory made by throng-pki
// (protocol/security/README.md): the CAs and the governance are shared, each identity has its own
// certificate, key and permissions. Programs take `--security DIR` and pick their identity by role.
#include <string>

#include "throng/protocol/dds_transport.h"

namespace throng::protocol {

// Identities throng-pki init makes; a player is `throng-pki client DIR NAME` (kept in players/NAME).
inline constexpr const char* kServerIdentity = "server";
inline constexpr const char* kOperatorIdentity = "operator";
inline constexpr const char* kBotsIdentity = "bots";

// The files of `identity` (server, operator, bots, or a player's NAME) under `dir`. Throws
// TransportError naming the first missing file and the throng-pki command that makes it.
SecurityFiles security_files(const std::string& dir, const std::string& identity);

}  // namespace throng::protocol
