// DDS Security end to end (throng-pki makes the PKI in a temporary directory; the server runs with
// --security): a participant without credentials sees none of the match; a player reads only its
// own partition, commands only its own client, cannot kick another or change parameters; the
// operator can; an expired certificate, a tampered permissions document and a foreign CA are
// refused.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <random>

#include "server_test_support.h"
#include "throng/protocol/security.h"
#include "throng/server/standby_server.h"

namespace throng::test {
namespace {

namespace fs = std::filesystem;

// Runs throng-pki; its output goes to DIR/../pki.log (shown on failure).
void pki(const std::string& args, const std::string& env = "") {
  const fs::path log = fs::temp_directory_path() / ("throng_pki_" + std::to_string(::getpid()) + ".log");
  const std::string cmd = env + " " + std::string(THRONG_BIN_DIR) + "/throng-pki " + args + " >" + log.string() + " 2>&1";
  const int rc = std::system(cmd.c_str());
  std::ifstream f(log);
  const std::string out((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  ASSERT_EQ(rc, 0) << cmd << "\n" << out;
}

// One PKI per test process: the match's (with players alice and bob, and an expired player old),
// and a foreign one (its own CAs) with a player eve.
struct Pki {
  fs::path dir, foreign;
};

const Pki& pki_dirs() {
  static const Pki p = [] {
    Pki d;
    const fs::path root = fs::temp_directory_path() / ("throng_security_" + std::to_string(::getpid()));
    fs::remove_all(root);
    d.dir = root / "match";
    d.foreign = root / "foreign";
    pki("init " + d.dir.string());
    pki("client " + d.dir.string() + " alice");
    pki("client " + d.dir.string() + " bob");
    const auto forty_days_ago =
        std::chrono::duration_cast<std::chrono::seconds>(std::chrono::system_clock::now().time_since_epoch()).count() -
        40 * 86400;
    pki("client " + d.dir.string() + " old --days 1", "THRONG_PKI_NOW=" + std::to_string(forty_days_ago));
    pki("init " + d.foreign.string());
    pki("client " + d.foreign.string() + " eve");
    return d;
  }();
  return p;
}

protocol::TransportOptions secure(int domain, const std::string& identity, const fs::path& dir, const std::string& name) {
  protocol::TransportOptions t{domain, true, name, std::nullopt};
  t.security = protocol::security_files(dir.string(), identity);
  return t;
}

// A client with credentials: TestClient on a secure transport.
std::unique_ptr<TestClient> secure_client(int domain, const std::string& identity, const fs::path& dir) {
  return std::make_unique<TestClient>(secure(domain, identity, dir, identity), 20s);
}

TEST(SecureMatch, PlayersAreConfinedToTheirOwnClientAndPartitionAndOnlyOperatorsChangeParameters) {
  const Pki& p = pki_dirs();
  auto options = small_server_options(156);
  options.security_dir = p.dir.string();
  nlohmann::json summary;
  {
    ServerThread server(options);
    const auto alice_client = secure_client(156, "alice", p.dir);
    const auto bob_client = secure_client(156, "bob", p.dir);
    TestClient& alice = *alice_client;
    TestClient& bob = *bob_client;
    const auto ra = alice.join(1, "secure");
    const auto rb = bob.join(2, "secure");
    ASSERT_TRUE(ra && ra->result == protocol::JoinResult::accepted);
    ASSERT_TRUE(rb && rb->result == protocol::JoinResult::accepted);
    // The partition follows from the authenticated certificate's name.
    EXPECT_EQ(ra->snapshot_partition, "throng_p_player-alice_" + std::to_string(ra->client_id));
    EXPECT_EQ(rb->snapshot_partition, "throng_p_player-bob_" + std::to_string(rb->client_id));
    EXPECT_TRUE(alice.wait_until([&] { return snapshots_of(alice.snapshots(), ra->client_id) > 0; }))
        << "alice gets her own snapshots";

    // Wallhack: a reader in bob's partition cannot even be created with alice's permissions ...
    EXPECT_THROW(alice.transport().subscribe_contacts(rb->client_id, rb->snapshot_partition, [](protocol::ContactPairs&&, std::size_t) {}),
                 protocol::TransportError);
    EXPECT_THROW(alice.transport().subscribe_snapshots(rb->client_id, rb->snapshot_partition, [](protocol::Snapshot&&, std::size_t) {}),
                 protocol::TransportError);
    // ... and moving her own reader there (a QoS change Fast DDS checks only on the server's side)
    // delivers nothing of bob's.
    alice.subscribe(ra->client_id, rb->snapshot_partition);
    std::this_thread::sleep_for(1500ms);
    EXPECT_EQ(alice.with_lock([&] { return snapshots_of(alice.snapshots(), rb->client_id); }), 0u) << "alice read bob's snapshots";

    // Hijack and kick: alice writes commands and a leave for bob's client.
    bob.transport().send_command(standing_command(*rb, 1));
    ASSERT_TRUE(bob.wait_until([&] { return last_applied(bob.snapshots(), rb->client_id) == 1; }));
    hijack_and_kick(alice.transport(), *rb, 10, 500);
    bob.transport().send_command(standing_command(*rb, 2));
    EXPECT_TRUE(bob.wait_until([&] { return last_applied(bob.snapshots(), rb->client_id) == 2; })) << "bob lost control";

    // Parameters: a player cannot even create the writer; the operator's change applies.
    protocol::ParamUpdate u;
    u.request_id = 5;
    u.entity = rb->entity;
    u.param = "weight";
    u.value = 300.0;
    EXPECT_THROW(alice.transport().send_param_update(u), protocol::TransportError);
    const auto op_client = secure_client(156, protocol::kOperatorIdentity, p.dir);
    TestClient& op = *op_client;
    ASSERT_TRUE(op.transport().wait_for_server(20s));
    op.transport().send_param_update(u);
    ASSERT_TRUE(op.wait_until([&] { return !op.param_replies().empty(); }));
    const protocol::ParamReply reply = op.with_lock([&] { return op.param_replies().at(0); });
    EXPECT_TRUE(reply.ok) << reply.error;

    // No credentials: nothing of the match is visible.
    TestClient anonymous(156);
    EXPECT_FALSE(anonymous.transport().wait_for_server(3s));
    EXPECT_TRUE(anonymous.with_lock([&] { return anonymous.match_infos().empty(); }));
    server.stop();
    summary = server.server().summary();
  }
  EXPECT_EQ(summary["rejected_by_reason"]["foreign_participant"], 10) << summary.dump(2);
  EXPECT_EQ(summary["joins_foreign_participant"], 1);
  EXPECT_EQ(summary["clients_connected_at_end"], 2);
  EXPECT_EQ(summary["param_updates_not_operator"], 0);
}

// The hot standby's topics carry every player's commands and the whole match: only the server
// identity holds them. A player or the bot fleet cannot even create a standby's endpoints; a
// standby with the server identity follows the secured match.
TEST(SecureMatch, OnlyTheServerIdentityCanFollowAsAHotStandby) {
  const Pki& p = pki_dirs();
  auto options = small_server_options(208);
  options.security_dir = p.dir.string();
  ServerThread primary(options);
  EXPECT_THROW(protocol::StandbyTransport(secure(208, "alice", p.dir, "alice-standby")), protocol::TransportError);
  EXPECT_THROW(protocol::StandbyTransport(secure(208, protocol::kBotsIdentity, p.dir, "bots-standby")),
               protocol::TransportError);

  auto so = options;
  so.standby = true;
  so.takeover_after_ticks = 0;  // following only (a loaded machine must not turn this into a takeover)
  so.duration_s = 30.0;  // a bound; stopped below once it follows
  server::StandbyServer standby(so);
  std::thread follow([&] { standby.run(false); });
  bool followed = false;
  for (auto deadline = std::chrono::steady_clock::now() + 25s; !followed && std::chrono::steady_clock::now() < deadline;
       std::this_thread::sleep_for(20ms)) {
    const server::StandbyStatus st = standby.status();
    followed = st.synced && st.following && st.follower.applied >= 30;
  }
  standby.request_stop();
  follow.join();
  EXPECT_TRUE(followed) << standby.summary().dump(2);
  EXPECT_EQ(standby.summary()["mismatches"], 0u);
}

TEST(SecureMatch, ExpiredCertificatesTamperedPermissionsAndForeignCasAreRefused) {
  const Pki& p = pki_dirs();
  // Refused where the participant is made: its own certificate has expired ...
  try {
    protocol::ClientTransport expired(secure(157, "old", p.dir, "old"));
    ADD_FAILURE() << "a participant with an expired certificate was created";
  } catch (const protocol::TransportError& e) {
    EXPECT_NE(std::string(e.what()).find("refused the DDS Security files"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("throng-pki check"), std::string::npos) << e.what();
  }
  // ... or its permissions no longer carry the permissions CA's signature.
  const fs::path tampered = p.dir.parent_path() / "tampered";
  fs::remove_all(tampered);
  fs::create_directories(tampered / "players");
  fs::copy(p.dir / "ca", tampered / "ca", fs::copy_options::recursive);
  fs::copy_file(p.dir / "governance.p7s", tampered / "governance.p7s");
  fs::copy(p.dir / "players" / "alice", tampered / "players" / "alice", fs::copy_options::recursive);
  {
    std::fstream f(tampered / "players" / "alice" / "permissions.p7s", std::ios::in | std::ios::out | std::ios::binary);
    std::string text((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
    const auto at = text.find("<subscribe>");
    ASSERT_NE(at, std::string::npos);
    text.replace(at, 11, "<publish>  ");  // same length: a grant widened after signing
    f.seekp(0);
    f << text;
  }
  EXPECT_THROW(protocol::ClientTransport(secure(157, "alice", tampered, "tampered")), protocol::TransportError);

  // A foreign CA: the participant exists, but the match's server never authenticates it.
  auto options = small_server_options(157);
  options.security_dir = p.dir.string();
  nlohmann::json summary;
  {
    ServerThread server(options);
    {
      const auto eve = secure_client(157, "eve", p.foreign);
      EXPECT_FALSE(eve->transport().wait_for_server(5s));
      EXPECT_TRUE(eve->with_lock([&] { return eve->match_infos().empty(); }));
    }
    // Counted once eve is gone without ever having authenticated.
    const auto deadline = std::chrono::steady_clock::now() + 10s;
    while (server.server().transport_counters().participants_refused == 0 &&
           std::chrono::steady_clock::now() < deadline)
      std::this_thread::sleep_for(100ms);
    server.stop();
    summary = server.server().summary();
  }
  EXPECT_GE(summary["participants_refused"].get<std::uint64_t>(), 1u) << summary.dump(2);
}

}  // namespace
}  // namespace throng::test
