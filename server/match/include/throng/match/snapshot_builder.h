#pragma once
// Interest management and snapshot content: which objects each client is sent this tick.
//
// Per client: the objects within InterestConfig::radius_m of its camera are candidates. Each
// candidate carries a priority accumulator; every tick it grows by how wrong the client's copy of
// the object is (distance moved since the client was last sent it, weighted up near the camera)
// plus a small age term, so stale far objects are eventually refreshed too. Objects whose
// quantized pose did not change since they were last sent are skipped unless keepalive_ticks
// passed. The highest accumulators are sent until the byte budget is spent; their accumulators
// reset. Objects the client knows that leave radius * exit_hysteresis (or are destroyed) are
// listed in `removed` for removed_repeat snapshots. Ties break by id: fully deterministic.
//
// Details (snapshot_builder.cpp says more):
//  - index() copies the bodies into a uniform grid (cells of radius/4, about 8 m; counting sort, so
//    the order is deterministic) and a table object index -> slot, so every build() sees the same
//    tick. The BodyView spans are not kept: they may die right after index() returns.
//  - Quantization: origin = camera rounded to a mm; unit_mm = 1 while radius_m <= 32, else the
//    smallest unit that fits radius_m * exit_hysteresis in int16. radius_m = 0 ("whole world"):
//    origin = centre of the bodies' bounding box, unit from its half extent (grows at once,
//    shrinks only with 25% slack). For unit > 1 the origin is a multiple of the unit, so a
//    resting object keeps its quantized pose while the camera moves. A height beyond the int16
//    range is clamped; bodies with a non-finite or > 1000 km coordinate are not indexed.
//  - In view = within radius_m of the camera, both rounded to a millimetre (integer distances).
//  - "Changed" means the quantized pose the client would decode (position in mm, yaw byte) differs
//    from the one it was last sent. Priority increment per tick for a changed object:
//      (|truth - client copy| + 0.5 m * yaw error) * (1 + 3 * (1 - d / radius)) + 0.01 * age_ticks
//    never-sent objects get 1e9 * (1 + 3 * (1 - d / radius)) (missing on the client). Errors
//    (also BuildStats::view_error_*) are measured against the truth rounded to a millimetre.
//  - Budget: budget_bytes is the whole serialized sample (snapshot_wire_bytes, headers and XCDR
//    padding included; 0 = unlimited). Removals are listed first (4 bytes each; those that do not
//    fit wait, so each id is still listed exactly removed_repeat times), the rest goes to poses
//    (9 bytes, + 4 for an id escape). The size is computed exactly and checked after encoding.
//  - No allocation in index()/build() after warm-up (the world's largest index, the largest body
//    count and the caller's reused Snapshot vectors), except when the world grows.
#include <cstdint>
#include <memory>
#include <span>

#include "throng/match/match_config.h"
#include "throng/protocol/messages.h"

namespace throng::match {

// The bodies of this tick, dense (any order). id = ObjectId value; yaw in radians.
struct BodyView {
  std::span<const std::uint32_t> id;
  std::span<const double> x, y, z;
  std::span<const float> yaw;
};

struct BuildStats {
  std::uint32_t in_view = 0;   // candidates inside the radius
  std::uint32_t sent = 0;      // poses written
  std::uint32_t skipped_unchanged = 0;
  double view_error_max_m = 0; // after this snapshot: max |truth - client's copy| over in-view known objects
  double view_error_mean_m = 0;
};

class SnapshotBuilder {
 public:
  // config as validate_config accepts it; a negative/non-finite radius or exit_hysteresis < 1:
  // std::invalid_argument.
  explicit SnapshotBuilder(const InterestConfig& config);
  ~SnapshotBuilder();
  SnapshotBuilder(SnapshotBuilder&&) noexcept;
  SnapshotBuilder& operator=(SnapshotBuilder&&) noexcept;
  SnapshotBuilder(const SnapshotBuilder&) = delete;
  SnapshotBuilder& operator=(const SnapshotBuilder&) = delete;

  // Allocates the client's per-object state (not in the tick's hot path: at join). A client id
  // that is already added: std::invalid_argument. remove_client of an unknown id does nothing.
  void add_client(std::uint32_t client_id);
  void remove_client(std::uint32_t client_id);

  // Once per tick, before build(): grids the bodies. Spans of different lengths, id 0, an id
  // index beyond ObjectId::kMaxIndex or two bodies with the same index: std::invalid_argument.
  void index(const BodyView& bodies, std::uint64_t tick);

  // Fills out's origin/unit, pose arrays, removed and objects_in_view for this client (other
  // Snapshot fields are the caller's). Unknown client or a non-finite / > 1000 km camera
  // coordinate: std::invalid_argument; build() before any index(): std::logic_error.
  const BuildStats& build(std::uint32_t client_id, double camera_x, double camera_y, protocol::Snapshot& out);

  const InterestConfig& config() const { return config_; }
  bool has_client(std::uint32_t client_id) const;
  std::uint32_t client_count() const;

 private:
  struct Impl;
  InterestConfig config_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace throng::match
