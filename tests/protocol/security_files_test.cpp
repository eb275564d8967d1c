// Where --security DIR finds an identity's files, and the errors that name what is missing.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "throng/protocol/security.h"

namespace throng::protocol {
namespace {

namespace fs = std::filesystem;

std::string error_of(const std::string& dir, const std::string& identity) {
  try {
    security_files(dir, identity);
  } catch (const TransportError& e) {
    return e.what();
  }
  return "";
}

void touch(const fs::path& p) {
  fs::create_directories(p.parent_path());
  std::ofstream(p) << "x";
}

TEST(SecurityFiles, RolesAndPlayersAndClearErrors) {
  const fs::path dir = fs::temp_directory_path() / ("throng_secfiles_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  EXPECT_NE(error_of(dir.string(), "server").find("is not a directory (make one with: throng-pki init"), std::string::npos);
  fs::create_directories(dir);
  EXPECT_NE(error_of(dir.string(), "server").find("identity_ca.pem is missing"), std::string::npos) << error_of(dir.string(), "server");
  touch(dir / "ca" / "identity_ca.pem");
  touch(dir / "ca" / "permissions_ca.pem");
  touch(dir / "governance.p7s");
  EXPECT_NE(error_of(dir.string(), "server").find("throng-pki init"), std::string::npos);
  EXPECT_NE(error_of(dir.string(), "alice").find("throng-pki client " + dir.string() + " alice"), std::string::npos)
      << error_of(dir.string(), "alice");
  for (const char* bad : {"", "../server", "a/b", "x y", "name-longer-than-thirty-two-chars"})
    EXPECT_NE(error_of(dir.string(), bad).find("must be 1..32 letters"), std::string::npos) << bad;

  for (const char* f : {"cert.pem", "key.pem", "permissions.p7s"}) {
    touch(dir / "server" / f);
    touch(dir / "players" / "alice" / f);
  }
  const SecurityFiles server = security_files(dir.string(), "server");
  EXPECT_EQ(server.certificate, (dir / "server" / "cert.pem").string());
  EXPECT_EQ(server.governance, (dir / "governance.p7s").string());
  const SecurityFiles alice = security_files(dir.string(), "alice");
  EXPECT_EQ(alice.permissions, (dir / "players" / "alice" / "permissions.p7s").string());
  EXPECT_EQ(alice.identity_ca, (dir / "ca" / "identity_ca.pem").string());
  fs::remove_all(dir);
}

}  // namespace
}  // namespace throng::protocol
