#include "throng/protocol/security.h"

#include <filesystem>

namespace throng::protocol {

namespace fs = std::filesystem;

SecurityFiles security_files(const std::string& dir, const std::string& identity) {
  if (identity.empty() || identity.size() > 32 ||
      identity.find_first_not_of("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789_-") != std::string::npos)
    throw TransportError("--security: identity '" + identity + "' must be 1..32 letters, digits, '_' or '-'");
  const bool role = identity == kServerIdentity || identity == kOperatorIdentity || identity == kBotsIdentity;
  const fs::path root(dir);
  const fs::path own = role ? root / identity : root / "players" / identity;
  SecurityFiles f;
  f.identity_ca = (root / "ca" / "identity_ca.pem").string();
  f.permissions_ca = (root / "ca" / "permissions_ca.pem").string();
  f.governance = (root / "governance.p7s").string();
  f.certificate = (own / "cert.pem").string();
  f.private_key = (own / "key.pem").string();
  f.permissions = (own / "permissions.p7s").string();
  std::error_code ec;
  if (!fs::is_directory(root, ec))
    throw TransportError("--security: '" + dir + "' is not a directory (make one with: throng-pki init " + dir + ")");
  for (const std::string* path : {&f.identity_ca, &f.permissions_ca, &f.governance})
    if (!fs::is_regular_file(*path, ec))
      throw TransportError("--security: " + *path + " is missing (make the match's PKI with: throng-pki init " + dir + ")");
  for (const std::string* path : {&f.certificate, &f.private_key, &f.permissions})
    if (!fs::is_regular_file(*path, ec))
      throw TransportError("--security: " + *path + " is missing (" +
                           (role ? "throng-pki init " + dir + " makes the server, operator and bots identities"
                                 : "make player '" + identity + "' with: throng-pki client " + dir + " " + identity) +
                           ")");
  return f;
}

}  // namespace throng::protocol
