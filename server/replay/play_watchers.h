#pragma once
// Watchers of a played log: bots and viewers that send a JoinRequest to `throng-replay play`.
//
// The logged match cannot take new inputs (that would change every hash after it), so a watcher
// is accepted as a SPECTATOR:
//   - it gets its own client id (kWatcherIdBase + n, never a logged id) and its own snapshot
//     partition ("w<n>", never a logged "c<id>"), so any number of watchers, several bots on one
//     participant included, each have a channel of their own;
//   - it FOLLOWS an entity: the logged clients' entities in turn (round-robin over the clients
//     connected at its join tick), or, when no logged client is connected then, the movable
//     nearest the centre of all bodies. JoinReply.entity and Snapshot.entity are that entity, and
//     the snapshot's own pose is its pose, so a viewer's "follow my character" follows it;
//   - its snapshots are built by the player with a SnapshotBuilder of its own (the logged
//     interest settings, camera on the followed entity), so its first snapshot already brings
//     everything in view, whatever the logged clients were sent before;
//   - its commands and parameter updates change nothing: they are counted (ignored), and keep it
//     alive (no command for the timeout: dropped, like the live server's client timeout).
// DDS-free: the session (play_session.h) carries its replies and snapshots to the transport.
#include <chrono>
#include <cstdint>
#include <string>
#include <unordered_map>
#include <vector>

#include "throng/match/match.h"
#include "throng/match/snapshot_builder.h"
#include "throng/protocol/messages.h"

namespace throng::replay {

inline constexpr std::uint32_t kWatcherIdBase = 1'000'000'000;  // far above any logged client id

struct WatcherOptions {
  std::uint32_t max_watchers = 64;
  std::chrono::steady_clock::duration timeout{};  // zero = never time out
};

// What the session must do on the transport after a call.
struct WatcherChanges {
  std::vector<protocol::JoinReply> replies;
  struct Channel {
    std::uint32_t client_id = 0;
    std::string partition;  // empty: close
  };
  std::vector<Channel> channels;
  void clear() {
    replies.clear();
    channels.clear();
  }
};

struct WatcherTotals {
  std::uint64_t joined = 0, refused = 0, left = 0, timed_out = 0;
  std::uint64_t commands_ignored = 0;
};

class Watchers {
 public:
  using Clock = std::chrono::steady_clock;
  Watchers(const match::InterestConfig& interest, WatcherOptions options);

  // Joins and leaves sent to the player, at the match's current tick. ending: refuse joins with
  // shutting_down (the playback is stopping).
  void handle_requests(const std::vector<protocol::JoinRequest>& requests, const match::Match& match, bool ending,
                       Clock::time_point now, WatcherChanges& out);
  // A command from client_id (a watcher's keeps it alive; any is counted as ignored).
  void note_command(std::uint32_t client_id, Clock::time_point now);
  // Drops watchers silent for longer than the timeout.
  void expire(Clock::time_point now, WatcherChanges& out);
  // One snapshot per watcher of the match's current tick (out is resized; its vectors are reused).
  void build_snapshots(const match::Match& match, std::vector<protocol::Snapshot>& out);

  std::size_t count() const { return watchers_.size(); }
  const WatcherTotals& totals() const { return totals_; }

 private:
  struct Watcher {
    std::uint64_t nonce = 0;
    std::string name;
    std::string partition;           // w<n>, or throng_p_<identity>_<id> under DDS Security
    protocol::ParticipantKey owner;  // only it may make the watcher leave
    std::uint32_t entity = 0;
    Clock::time_point last_heard{};
  };
  std::uint32_t pick_entity(const match::Match& match);
  void index_bodies(const match::Match& match);

  match::SnapshotBuilder builder_;
  match::SnapshotBuilder::Scratch scratch_;
  WatcherOptions options_;
  std::unordered_map<std::uint32_t, Watcher> watchers_;  // by client id
  std::uint32_t next_id_ = kWatcherIdBase + 1;
  std::uint64_t round_robin_ = 0;
  WatcherTotals totals_;
  // Per tick: the bodies in dense order, and their facing (the Match keeps its own facings
  // private, so the player derives one from the velocity; see play_watchers.cpp).
  std::vector<std::uint32_t> ids_;
  std::vector<float> yaw_dense_;
  std::vector<float> yaw_by_index_;    // by ObjectId index, kept across ticks (resting bodies keep theirs)
  std::vector<std::uint32_t> dense_by_index_;
};

}  // namespace throng::replay
