#pragma once
// A bot's own copy of the world, rebuilt from the snapshots it receives — what a real client
// would draw. Not thread-safe: the owner (Bot) serializes access.
//
//  - Each snapshot's poses are decoded (codec.h) and appended to a per-object interpolation
//    buffer holding the last kSamples timestamped samples (timestamps are server ticks).
//  - Objects are read at the render time: newest received tick - interp_delay_ticks. Between two
//    samples the pose is interpolated linearly (yaw along the shorter arc); before the oldest
//    sample the oldest is held, after the newest the newest is held (an object the server did not
//    re-send because it did not move).
//  - An object listed in `removed` is dropped at once; an object not seen for expiry_s (in server
//    ticks at the match's tick rate) is dropped too.
//  - The client's own entity comes from the snapshot's unquantized entity_* fields and is kept in
//    the same buffers (overriding its quantized pose in that snapshot, if any).
//  - A malformed snapshot (decode error, non-finite own pose) is counted and dropped whole; a
//    snapshot whose tick is not newer than the newest applied one is counted as stale and dropped.
#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "throng/client_sim/match_view.h"
#include "throng/protocol/codec.h"
#include "throng/protocol/messages.h"

namespace throng::client_sim {

struct ObjectState {
  std::uint32_t id = 0;
  double x = 0, y = 0, z = 0, yaw = 0;
};

class ClientWorld {
 public:
  static constexpr std::size_t kSamples = 3;

  struct Options {
    double interp_delay_ticks = 2.0;
    double expiry_s = 3.0;
    std::uint32_t default_tick_hz = 30;  // until a MatchView says otherwise
  };

  enum class ApplyResult : std::uint8_t { applied, stale, malformed };

  ClientWorld() : ClientWorld(Options{}) {}
  explicit ClientWorld(const Options& options);

  void set_match(std::shared_ptr<const MatchView> match);
  const MatchView* match() const { return match_.get(); }
  std::uint32_t tick_hz() const { return match_ ? match_->tick_hz() : options_.default_tick_hz; }

  ApplyResult apply(const protocol::Snapshot& snapshot);

  bool has_data() const { return newest_tick_.has_value(); }
  std::optional<std::uint64_t> newest_tick() const { return newest_tick_; }
  // newest tick - interp_delay_ticks (0 before any snapshot).
  double render_tick() const;

  // The object at a given (server tick) time, or at the render time. nullopt when unknown,
  // removed or expired.
  std::optional<ObjectState> object_at(std::uint32_t id, double tick) const;
  std::optional<ObjectState> object(std::uint32_t id) const { return object_at(id, render_tick()); }
  // Every live object at the render time, in unspecified order.
  void for_each(const std::function<void(const ObjectState&)>& fn) const;
  std::size_t object_count() const;  // live (not expired) objects

  // The own entity: id from the newest snapshot (0 = none/gone) and its newest unquantized pose.
  std::uint32_t own_entity() const { return own_entity_; }
  std::optional<ObjectState> own_pose() const { return own_pose_; }

  std::uint64_t applied_count() const { return applied_; }
  std::uint64_t stale_count() const { return stale_; }
  std::uint64_t malformed_count() const { return malformed_; }
  const std::string& last_error() const { return last_error_; }

 private:
  struct Sample {
    std::uint64_t tick = 0;
    double x = 0, y = 0, z = 0, yaw = 0;
  };
  struct Track {
    std::array<Sample, kSamples> s{};
    std::uint8_t n = 0;
  };

  void add_sample(std::uint32_t id, const Sample& sample);
  bool expired(const Track& t) const;
  void update_expiry();
  static ObjectState sample_track(std::uint32_t id, const Track& t, double tick);
  void sweep();

  Options options_;
  std::shared_ptr<const MatchView> match_;
  std::unordered_map<std::uint32_t, Track> tracks_;
  std::optional<std::uint64_t> newest_tick_;
  std::uint64_t last_sweep_tick_ = 0;
  std::uint64_t expiry_ticks_ = 90;  // expiry_s at tick_hz()
  std::uint32_t own_entity_ = 0;
  std::optional<ObjectState> own_pose_;
  std::uint64_t applied_ = 0, stale_ = 0, malformed_ = 0;
  std::string last_error_;
  std::vector<protocol::Pose> scratch_;
};

}  // namespace throng::client_sim
