#pragma once
// Interest management and snapshot content: which objects each client is sent this tick.
//
// Per client: the objects within InterestConfig::radius_m of its camera are candidates. Each
// candidate the client knows gets a priority every tick: how wrong the client's copy of it is
// right now (distance between the truth and the copy, weighted up near the camera) plus a small
// age term, so stale far objects are eventually refreshed too. Objects whose quantized pose did
// not change since they were last sent are skipped unless keepalive_ticks passed. The highest
// priorities are sent until the byte budget is spent. Objects the client knows that leave
// radius * exit_hysteresis (or are destroyed) are listed in `removed` for removed_repeat
// snapshots. Ties break by id: fully deterministic.
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
//    from the one it was last sent. Priority of a changed (or keepalive-due) known object:
//      (|truth - client copy| + 0.5 m * yaw error) * (1 + 3 * (1 - d / radius)) + 0.01 m * age_ticks
//    recomputed every tick from the current error (not summed over ticks: an object that comes
//    back into view with a stale copy ranks by how stale it is at once, and a large error always
//    outranks a small one at the same distance). Never-sent objects get 1e9 * (1 + 3 * (1 - d /
//    radius)) (missing on the client). Errors (also BuildStats::view_error_*) are measured
//    against the truth rounded to a millimetre.
//  - What it bounds (tests/match/snapshot_view_error_test.cpp): largest weighted error first
//    refreshes each of N objects in view about every N / B ticks (B poses per snapshot); an
//    object far out (w = 1) may wait until its error is 4x the near ones' (w = 4), so in-view
//    errors stay below about 4 * v * dt * (N / B + 1): 2.2 m for 1,000 objects at <= 1.5 m/s and
//    ~100 poses (the scenes there reach 0.5-0.8 m, also with a crowd marching with the camera).
//  - Heights: a copy's z is the truth clamped to the int16 range of the unit (+-32.767 m at
//    1 mm); the comparison ("changed") uses the clamped value, the error the real height.
//  - Budget: budget_bytes is the whole serialized sample (snapshot_wire_bytes, headers and XCDR
//    padding included; 0 = unlimited). Removals are listed first (4 bytes each; those that do not
//    fit wait, so each id is still listed exactly removed_repeat times, unless the object's pose
//    is sent again first: then the rest of its removal is dropped), the rest goes to poses
//    (9 bytes, 7 when all candidates share one height, + 4 for an id escape). The size is
//    computed exactly and checked after encoding.
//  - No allocation in index()/build() after warm-up (the world's largest index, the largest body
//    count, the caller's reused Snapshot vectors and Scratch), except when the world grows.
//
// Threads: index(), add_client() and remove_client() need the builder to themselves. Between
// them, build() may run concurrently on several threads for DISTINCT clients, each thread with
// its own Scratch (the per-client state is disjoint and the tick's index is only read). The
// overload without a Scratch uses one inside the builder: never two of those at the same time.
// The result is the same bytes whatever the threads or the order of the builds: a client's
// snapshot depends only on the index and that client's own history.
#include <cstdint>
#include <memory>
#include <span>

#include "throng/match/match_config.h"
#include "throng/protocol/messages.h"

namespace throng {
class ByteWriter;
class ByteReader;
}  // namespace throng

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
  // Residency (docs/design/memory.md): a joining client's table is made resident now and as the
  // world grows (kResident), so a server's memory is a function of the clients present; a restore
  // adds its clients lazily (kLazy: a seek creates every client at once and must stay short).
  enum class Residency { kResident, kLazy };
  void add_client(std::uint32_t client_id, Residency residency = Residency::kResident);
  void remove_client(std::uint32_t client_id);

  // Once per tick, before build(): grids the bodies. Spans of different lengths, id 0, an id
  // index beyond ObjectId::kMaxIndex or two bodies with the same index: std::invalid_argument.
  void index(const BodyView& bodies, std::uint64_t tick);

  // Working memory of one build() at a time (candidate lists, keys, the returned BuildStats).
  // One per thread that builds concurrently; reusable across builders and ticks. Grows to the
  // largest index it served, then build() does not allocate.
  class Scratch {
   public:
    Scratch();
    ~Scratch();
    Scratch(Scratch&&) noexcept;
    Scratch& operator=(Scratch&&) noexcept;
    Scratch(const Scratch&) = delete;
    Scratch& operator=(const Scratch&) = delete;

   private:
    friend class SnapshotBuilder;
    struct Impl;
    std::unique_ptr<Impl> impl_;
  };

  // Grows `scratch` to what a build() on the current index needs, so that the build itself does
  // not allocate. Call it on the tick thread for every worker's scratch after index(): a worker
  // that first gets a client late in the match (which worker builds which client depends on the
  // threads) would otherwise allocate its working memory then.
  void reserve(Scratch& scratch) const;

  // Fills out's origin/unit, pose arrays, removed and objects_in_view for this client (other
  // Snapshot fields are the caller's). Unknown client or a non-finite / > 1000 km camera
  // coordinate: std::invalid_argument; build() before any index(): std::logic_error. The
  // returned stats live in `scratch` until its next build. Safe concurrently for distinct
  // clients with distinct scratches (see "Threads" above).
  const BuildStats& build(std::uint32_t client_id, double camera_x, double camera_y, protocol::Snapshot& out,
                          Scratch& scratch);
  // The same with the builder's own Scratch: one thread at a time.
  const BuildStats& build(std::uint32_t client_id, double camera_x, double camera_y, protocol::Snapshot& out);

  // Checkpoints: each client's copy of every object it was sent (that decides what its future
  // snapshots contain), its build stamp, known list and pending removals, and the whole-world
  // unit. Not saved: the tick's index (index() rebuilds it before any build) and Scratch.
  // restore_state replaces every client; it throws CheckpointError (builder unchanged) on bad bytes
  // or a per-client table larger than max_capacity (1 + the largest object index the caller's
  // world can have). Not concurrent with build().
  void save_state(ByteWriter& w) const;
  void restore_state(ByteReader& r, std::size_t max_capacity);

  const InterestConfig& config() const { return config_; }
  bool has_client(std::uint32_t client_id) const;
  std::uint32_t client_count() const;

 private:
  struct Impl;
  struct Build;  // one build() call, phase by phase (snapshot_builder.cpp)
  InterestConfig config_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace throng::match
