#pragma once
// The thin-client gateway's game side, transport-free: one client of the match (the same client
// path as a bot) whose world is drawn by a web page and whose character the page controls.
//
//  - Join: a random nonce, re-sent by the owner until the reply for that nonce arrives.
//  - World: a ClientWorld (client_sim) fed with this client's snapshots: objects interpolated at
//    the render time (newest tick - 2), the own entity from the unquantized own pose.
//  - Commands: make_command() is called once per server tick; the gateway owns the sequence
//    numbers (1, 2, ...). The page's latest valid input is used while it is fresh (input_timeout);
//    a stale or absent page means "stand still", so a closed tab never keeps walking. The camera
//    is the page's camera when it panned, else the controlled entity.
//  - Latency, like the bots: the send time of sequence s -> the arrival of the first snapshot
//    whose last_applied_sequence >= s (median over the last second). Bandwidth: snapshot payload
//    bytes received over the last second.
//  - JSON for the page: match_json() once per MatchInfo, frame_json() per applied snapshot.
//  - Contacts overlay: while the page's input carries protocol::kActionContacts the commands do
//    too, and the server (if it grants the channel) sends this client ContactPairs; frames carry
//    the newest valid ones (contacts_json) while the page still asks, null otherwise.
//
// Not thread-safe: the owner (the gateway loop) serializes every call; DDS callbacks and the web
// thread only hand data to that loop.
#include <array>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <memory>
#include <optional>
#include <string>

#include "throng/client_sim/client_world.h"
#include "throng/client_sim/join_handshake.h"
#include "throng/client_sim/match_view.h"
#include "throng/protocol/messages.h"
#include "throng/view/page_input.h"

namespace throng::view {

using Clock = std::chrono::steady_clock;
using TimePoint = Clock::time_point;

struct GatewayOptions {
  std::string name = "throng-view";  // at most 64 bytes (the server refuses longer)
  std::uint64_t nonce = 0;           // 0 draws one from std::random_device
  std::chrono::milliseconds input_timeout{500};
  std::size_t max_pending_commands = 1024;  // unresolved latency probes kept (oldest dropped)
  client_sim::ClientWorld::Options world{};
};

// What the gateway loop adds to a frame from outside the game side.
struct FrameExtras {
  std::array<std::uint64_t, kInputErrorCount> input_errors{};
  std::size_t pages = 0;  // WebSocket sessions open
};

class Gateway {
 public:
  // The join protocol's states; the gateway re-sends its join until answered, so it never reaches
  // timed_out.
  using State = client_sim::JoinHandshake::State;
  static const char* to_string(State s) { return client_sim::JoinHandshake::to_string(s); }

  explicit Gateway(GatewayOptions options);

  State state() const { return join_.state(); }
  std::uint64_t nonce() const { return join_.nonce(); }
  const protocol::JoinReply& reply() const { return join_.reply(); }
  std::optional<TimePoint> join_sent_at() const { return join_.join_sent_at(); }
  std::optional<TimePoint> last_join_sent_at() const { return join_.last_join_sent_at(); }

  // Marks the gateway joining; called again it returns the same request (a resend).
  protocol::JoinRequest join_request(TimePoint now);
  // Returns true when this reply accepted us now (the owner subscribes the snapshots then).
  bool on_join_reply(const protocol::JoinReply& reply);
  // nullopt unless joined; marks the gateway left.
  std::optional<protocol::JoinRequest> leave_request();

  void on_match_info(const protocol::MatchInfo& info);
  bool has_match() const { return match_ != nullptr; }
  bool match_ended() const { return match_ && match_->ended(); }
  // Returns whether the world applied it (not stale, not malformed, ours).
  bool on_snapshot(const protocol::Snapshot& snapshot, std::size_t wire_bytes, TimePoint now);
  // Returns whether it was kept as the newest contact pairs (ours, well-formed, not older).
  bool on_contacts(const protocol::ContactPairs& contacts, std::size_t wire_bytes, TimePoint now);

  // The command for this tick, or nullopt before the own entity was seen in a snapshot.
  std::optional<protocol::Command> make_command(TimePoint now, const std::optional<PageInput>& input,
                                                std::optional<TimePoint> input_received);

  // {"type":"match", ...}: empty before the first MatchInfo.
  const std::string& match_json() const { return match_json_; }
  // {"type":"frame", ...} for the newest applied snapshot.
  std::string frame_json(TimePoint now, const FrameExtras& extras) const;

  // Measurements (also in every frame).
  std::optional<double> latency_ms(TimePoint now) const;  // median over the last second
  double kbit_per_s(TimePoint now) const;                 // snapshot payload, last second
  double contacts_kbit_per_s(TimePoint now) const;        // contact-pairs payload, last second
  std::uint64_t contacts_received() const { return contacts_received_; }
  std::uint64_t contacts_rejected() const { return contacts_rejected_; }  // malformed or foreign
  std::uint64_t commands_sent() const { return commands_sent_; }
  std::uint64_t snapshots_applied() const { return world_.applied_count(); }
  std::uint32_t last_applied_sequence() const { return last_applied_sequence_; }
  std::uint32_t objects_in_view() const { return objects_in_view_; }  // the server's count
  const client_sim::ClientWorld& world() const { return world_; }

 private:
  void expire_windows(TimePoint now) const;

  GatewayOptions options_;
  client_sim::JoinHandshake join_;
  std::shared_ptr<const client_sim::MatchView> match_;
  std::string match_json_;
  client_sim::ClientWorld world_;

  std::uint32_t next_sequence_ = 1;
  std::uint64_t commands_sent_ = 0;
  std::uint32_t last_applied_sequence_ = 0;
  std::uint32_t objects_in_view_ = 0;
  bool panned_ = false;
  float camera_x_ = 0, camera_y_ = 0;

  struct Pending {
    std::uint32_t sequence;
    TimePoint sent;
  };
  std::deque<Pending> pending_;
  // Sliding one-second windows; mutable so the const readers can drop expired entries.
  mutable std::deque<std::pair<TimePoint, double>> latency_window_;
  mutable std::deque<std::pair<TimePoint, std::size_t>> bytes_window_;
  std::optional<TimePoint> first_snapshot_;

  bool contacts_requested_ = false;  // the last command carried kActionContacts
  std::optional<protocol::ContactPairs> contacts_;
  std::uint64_t contacts_received_ = 0, contacts_rejected_ = 0;
  mutable std::deque<std::pair<TimePoint, std::size_t>> contacts_bytes_window_;
};

// {"tick":..,"near":..,"camera":[x,y],"radius":..,"pairs":[a, b, share_a, depth_mm, push_mm, ...]}
// (share_a to 5 decimals, millimetres to 0.1): the page's form of ContactPairs, in live and log
// frames alike.
std::string contacts_json(const protocol::ContactPairs& c);

}  // namespace throng::view
