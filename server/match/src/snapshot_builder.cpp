// SnapshotBuilder: per-client interest management over the per-tick InterestGrid.
//
// Per client and object index the builder keeps one 32-byte record (the client's copy of the
// object: quantized position in mm and id, laid out like the grid's SlotPose so that one vector
// compare says "same object, same position"; then the build stamp it was last a candidate in,
// the tick it was last sent, the yaw byte). The record is one struct rather than parallel arrays:
// build() visits the candidates in grid order, i.e. at scattered object indices, and reads every
// field of each one, so one cache line per candidate; with many clients these lines are not in
// cache, and the loop prefetches them a few candidates ahead.
//
// build() in order. Everything it writes is the client's own state or the caller's Scratch, so
// builds for distinct clients can run on several threads at once. The phases are separate loops
// over packed arrays, branch-free where the branch would be data-dependent (a mispredicted branch
// per candidate cost more than the arithmetic):
//  1a. candidate slots: grid rows overlapping the circle; cells entirely inside it are taken
//      whole, the others tested on whole millimetres.
//  1b. compare each candidate with the client's copy: unknown ones are set aside, unchanged ones
//      younger than keepalive skipped (their error still counts in the statistics), the rest
//      keyed as integer differences (KeyIn).
//  1c. priorities (module header: current error x near weight + age) and 64-bit keys
//      (priority float bits << 32 | ~id: larger key = send first, equal priority = lower id
//      first), four at a time with SSE2.
//  1d. unknown candidates: 1e9 x near weight (nearest first).
//  2.  known objects that are not candidates are checked against the index table (same full id
//      = same object) and radius * exit_hysteresis; gone ones join the pending removals.
//  3.  removals that fit the budget are listed (oldest first); the poses: the k-th largest key
//      (radix select) is the threshold, one pass picks the keys at or above it and gathers the
//      error statistics of the rest, the selection is radix-sorted by id and the exact wire size
//      (with id escapes) is checked, dropping the lowest priority until it fits.
//  4.  the pose arrays are written directly (what protocol::encode_poses writes for the decoded
//      poses: offsets (copy - origin) / unit, z / unit, the yaw byte; tests/match check it) and
//      the client's copies updated; a pending removal of an id whose pose is sent again is
//      dropped (the client applies removals before poses, so this snapshot is still right).
//      Equal heights are then written as one shared z, as encode_poses does; phase 3 plans for it
//      when every keyed candidate stands at one height (7 bytes a pose instead of 9).
#include "throng/match/snapshot_builder.h"

#include <algorithm>
#include <bit>
#include <cstddef>
#include <cstring>
#include <cmath>
#include <functional>
#include <limits>
#include <stdexcept>
#include <type_traits>

#if defined(__SSE2__) || defined(_M_X64)
#include <emmintrin.h>
#endif

#include <fmt/format.h>

#include "interest_grid.h"
#include "lazy_zero_array.h"
#include "throng/core/byte_io.h"
#include "throng/core/object_id.h"
#include "throng/protocol/codec.h"

namespace throng::match {

namespace {

using detail::round_half_even;

constexpr double kRadiusUnitOneM = 32.0;        // radius up to which positions go at 1 mm
constexpr double kAgePriorityPerTick = 0.01;    // m per tick since last sent
constexpr double kNearWeight = 3.0;             // w_near = 1 + 3 * (1 - d / radius)
constexpr float kNearWeightF = 3.0f;
constexpr float kUnknownPriorityF = 1.0e9f;     // never-sent objects (x w_near): missing on the client
constexpr double kYawLeverM = 0.5;              // a yaw error counts like this arm swinging
constexpr double kRadPerYawStep = 6.28318530717958647692 / 256.0;
constexpr auto kYawMPerStepF = static_cast<float>(kRadPerYawStep * kYawLeverM);
constexpr auto kAgePerTickF = static_cast<float>(kAgePriorityPerTick);
constexpr double kCellPerRadius = 0.25;         // grid cell = radius / 4 (7.5 m at 30 m)
constexpr std::int32_t kMaxQ = detail::kMaxZQ;  // int16 range of a quantized offset
constexpr std::uint32_t kPrefetchAhead = 16;
// kth_largest buckets: key >> 53 = the priority's float bits >> 21 (sign, exponent, 2 mantissa
// bits). Priorities are >= 0, so the sign bit is 0 and 1024 buckets are used.
constexpr int kHistShift = 53;
constexpr std::uint32_t kHistBuckets = 1u << (64 - kHistShift);

// XCDR1 size of a Snapshot with these sequence lengths: mirrors protocol::snapshot_wire_bytes
// (checked against it in the constructor) so the budget can be planned without building samples.
// heights: poses, or 1 when they share one height (protocol::share_equal_heights).
std::size_t wire_bytes(std::size_t id_codes, std::size_t poses, std::size_t removed, std::size_t heights) {
  std::size_t n = 0;
  auto align = [&](std::size_t a) { n = (n + a - 1) / a * a; };
  auto prim = [&](std::size_t s) {
    align(s);
    n += s;
  };
  auto seq = [&](std::size_t count, std::size_t elem) {
    prim(4);
    if (count) {
      align(elem);
      n += count * elem;
    }
  };
  prim(4);  // client_id
  prim(8);  // tick
  prim(4);  // last_applied_sequence
  prim(8);  // last_applied_tick
  prim(4);  // entity
  for (int i = 0; i < 4; ++i) prim(4);
  prim(4);  // origin_x_mm
  prim(4);  // origin_y_mm
  prim(2);  // unit_mm
  prim(4);  // objects_in_view
  seq(id_codes, 2);
  seq(poses, 2);
  seq(poses, 2);
  seq(heights, 2);
  seq(poses, 1);
  seq(removed, 4);
  return n + 4;
}

void check_wire_mirror() {
  for (std::size_t codes = 0; codes < 5; ++codes)
    for (std::size_t poses = 0; poses < 5; ++poses)
      for (std::size_t removed = 0; removed < 3; ++removed)
        for (const std::size_t heights : {poses, std::min<std::size_t>(poses, 1)}) {
          protocol::Snapshot s;
          s.id_codes.resize(codes);
          s.x.resize(poses);
          s.y.resize(poses);
          s.z.resize(heights);
          s.yaw.resize(poses);
          s.removed.resize(removed);
          if (protocol::snapshot_wire_bytes(s) != wire_bytes(codes, poses, removed, heights))
            throw std::logic_error("SnapshotBuilder: wire size model disagrees with protocol::snapshot_wire_bytes");
        }
}

// Id codes the encoder writes for one id after `previous` (1, or 3 for an escape).
inline std::size_t id_codes_for(std::uint32_t previous, std::uint32_t id) {
  const std::uint32_t delta = id - previous;
  return (delta >= 1 && delta <= 0xFFFF) ? 1 : 3;
}

// Smallest unit (mm) so that +-half_m around an origin snapped to the unit fits in int16.
std::uint16_t unit_for_half_extent(double half_m) {
  const double u = std::ceil((half_m * 1000.0 + 1.0) / 32766.0);
  return static_cast<std::uint16_t>(std::clamp(u, 1.0, 65535.0));
}

inline std::uint64_t priority_key(float priority, std::uint32_t id) {
  return (static_cast<std::uint64_t>(std::bit_cast<std::uint32_t>(priority)) << 32) | static_cast<std::uint32_t>(~id);
}
inline std::uint32_t key_id(std::uint64_t key) { return ~static_cast<std::uint32_t>(key); }

// sqrt of a value known to be >= 0: without the errno branch std::sqrt carries under the
// project's flags (same IEEE result).
inline float sqrt_nonneg(float v) {
#if defined(__SSE2__) || defined(_M_X64)
  return _mm_cvtss_f32(_mm_sqrt_ss(_mm_set_ss(v)));
#else
  return std::sqrt(v);
#endif
}

// |(ex, ey, ez)| mm -> m.
inline float error_m(std::int32_t ex, std::int32_t ey, std::int32_t ez) {
  const auto fx = static_cast<float>(ex), fy = static_cast<float>(ey), fz = static_cast<float>(ez);
  return sqrt_nonneg(fx * fx + fy * fy + fz * fz) * 0.001f;
}

// The client's copy of one object index. The first 16 bytes mirror detail::SlotPose, so the
// compare loop checks "same object, same quantized position" with one vector compare.
struct alignas(32) ObjectState {
  std::int32_t x = 0, y = 0, z = 0;  // position as the client decoded it, mm
  std::uint32_t id = 0;           // ObjectId value the client knows here; 0 = none
  std::uint32_t seen = 0;         // build stamp when it was last a candidate
  std::uint32_t sent_tick = 0;    // low 32 bits of the tick it was last sent
  std::uint8_t yaw = 0;
  std::uint8_t pad_[7] = {};      // 32 bytes: a record never straddles a cache line
};
static_assert(sizeof(ObjectState) == 32);
static_assert(offsetof(ObjectState, x) == offsetof(detail::SlotPose, x) &&
              offsetof(ObjectState, z) == offsetof(detail::SlotPose, z) &&
              offsetof(ObjectState, id) == offsetof(detail::SlotPose, id));

// A keyed candidate as the compare loop leaves it (two 16-byte halves, read four at a time).
struct alignas(16) KeyIn {
  std::int32_t ex, ey, ez;  // truth - client copy, mm
  std::uint32_t id;
  float d2;                 // squared distance to the camera, mm^2
  std::int32_t yaw;         // yaw error, steps (0..128)
  std::int32_t age;         // ticks since last sent (capped)
  std::uint32_t slot;
};
static_assert(sizeof(KeyIn) == 32);

struct KnownEntry {
  std::uint32_t index, id;
};

struct PendingRemoval {
  std::uint32_t id, left;  // snapshots it still has to be listed in
};

struct Client {
  std::uint32_t client_id = 0;
  std::uint32_t stamp = 0;  // builds so far
  detail::LazyZeroArray<ObjectState> obj;  // by object index (lazy_zero_array.h says why not a vector)
  std::vector<KnownEntry> known;      // objects the client holds, in the order they became known
  std::vector<PendingRemoval> pending;

  // A joined client's record table is resident from the join and as the world grows (only the new
  // pages). Why: lazily, a client's table filled in page by page as it met more of the world, and a
  // long-staying client's kept growing for half an hour: a server's memory crept up at a constant
  // number of clients (docs/design/memory.md). A restored client's stays lazy
  // (lazy_zero_array.h: a restore creates every client at once, inside a seek).
  bool resident = false;

  void reserve(std::size_t capacity) {
    obj.grow_to(capacity);
    if (resident) obj.commit();
    known.reserve(capacity);
    pending.reserve(capacity + 64);
  }
};

}  // namespace

struct SnapshotBuilder::Scratch::Impl {
  std::vector<std::uint32_t> cslot;    // candidate slots, grid order
  std::vector<std::uint32_t> cobj;     // their object indices (+ kPrefetchAhead zeros)
  std::vector<std::uint32_t> unknown;  // candidate slots the client does not know
  // Keyed candidates (changed or keepalive-due, then the unknown ones): what the priority is
  // computed from, then the error (m, -1 = unknown to the client) and the key.
  std::vector<KeyIn> kin;
  std::vector<float> kerr;
  std::vector<std::uint64_t> kkey;
  std::vector<std::uint64_t> kth, kth2;  // kth_largest's buffers (also sort_by_id's)
  std::vector<std::uint32_t> hist;     // kth_largest's histogram
  std::vector<std::uint64_t> sel;      // selected: id << 32 | position in the keyed arrays
  BuildStats stats;

  void reserve(std::size_t n) {
    if (cslot.size() >= n) return;
    for (auto* v : {&cslot, &unknown}) v->resize(n);
    cobj.resize(n + kPrefetchAhead);
    kin.resize(n);
    kerr.resize(n);
    kkey.resize(n);
    kth.resize(n);
    kth2.resize(n);
    sel.resize(n);
    hist.resize(kHistBuckets);
  }
};

namespace {

// The k-th largest (1-based, 0 < k < n) of n distinct keys. Radix select, most significant digit
// first: count the digit over the keys still in the running, keep only those in the bucket that
// holds the k-th, next digit. The first digit is the priority's top 11 bits (sign, exponent and
// 2 mantissa bits of a non-negative float, which order like the float), then 8 bits at a time;
// a handful of keys left is finished with nth_element. O(n) and branch-free on the large
// passes (a comparison sort mispredicts on every other comparison here).
// hist: kHistBuckets counters; a, b: room for n keys each.
std::uint64_t kth_largest(const std::uint64_t* keys, std::uint32_t n, std::size_t k, std::uint32_t* hist,
                          std::uint64_t* a, std::uint64_t* b) {
  const std::uint64_t* cur = keys;
  std::size_t m = n, r = k - 1;  // r: 0-based rank of the wanted key among cur, from the top
  int shift = kHistShift, bits = 64 - kHistShift;
  std::uint64_t* buf = a;
  for (;;) {
    if (m <= 16) {
      if (cur == keys) {
        std::copy(cur, cur + m, buf);
        cur = buf;
      }
      std::uint64_t* v = const_cast<std::uint64_t*>(cur);
      std::nth_element(v, v + r, v + m, std::greater<std::uint64_t>());
      return v[r];
    }
    const std::uint32_t nb = 1u << bits;
    const std::uint64_t mask = nb - 1;
    std::fill(hist, hist + nb, 0u);
    std::uint32_t hi = 0;
    for (std::size_t i = 0; i < m; ++i) {
      const auto d = static_cast<std::uint32_t>((cur[i] >> shift) & mask);
      ++hist[d];
      hi = std::max(hi, d);
    }
    std::uint32_t d = hi;
    std::size_t above = 0;
    while (above + hist[d] <= r) above += hist[d--];
    r -= above;
    std::size_t mm = 0;
    for (std::size_t i = 0; i < m; ++i) {
      buf[mm] = cur[i];
      mm += static_cast<std::uint32_t>((cur[i] >> shift) & mask) == d ? 1u : 0u;
    }
    cur = buf;
    m = mm;
    buf = buf == a ? b : a;
    if (shift == 0) return cur[r];  // every bit decided: one key left (keys are distinct)
    bits = std::min(8, shift);
    shift -= bits;
  }
}

// Sorts v (id << 32 | position) by id: LSD radix over the bits in which the ids differ (usually
// just the low bits of the object index: two passes of at most 7 bits), in as few passes of at
// most 8 bits as cover them. Stable and branch-free. hist: 1024 counters, tmp: room for n.
void sort_by_id(std::uint64_t* v, std::size_t n, std::uint64_t* tmp, std::uint32_t* hist) {
  if (n < 2) return;
  std::uint32_t differ = 0;
  const auto id0 = static_cast<std::uint32_t>(v[0] >> 32);
  for (std::size_t i = 1; i < n; ++i) differ |= static_cast<std::uint32_t>(v[i] >> 32) ^ id0;
  const int width = std::bit_width(differ);
  if (width == 0) return;
  const int passes = (width + 7) / 8;
  const int digit = (width + passes - 1) / passes;
  const std::uint32_t buckets = 1u << digit, mask = buckets - 1;
  std::fill(hist, hist + passes * buckets, 0u);
  for (std::size_t i = 0; i < n; ++i) {
    const auto id = static_cast<std::uint32_t>(v[i] >> 32);
    for (int p = 0; p < passes; ++p) ++hist[p * buckets + ((id >> (p * digit)) & mask)];
  }
  std::uint64_t* src = v;
  std::uint64_t* dst = tmp;
  for (int p = 0; p < passes; ++p) {
    std::uint32_t* h = hist + p * buckets;
    const int shift = 32 + p * digit;
    std::uint32_t sum = 0;
    for (std::uint32_t j = 0; j < buckets; ++j) {
      const std::uint32_t c = h[j];
      h[j] = sum;
      sum += c;
    }
    for (std::size_t i = 0; i < n; ++i) dst[h[(src[i] >> shift) & mask]++] = src[i];
    std::swap(src, dst);
  }
  if (src != v) std::copy(src, src + n, v);
}

}  // namespace

SnapshotBuilder::Scratch::Scratch() : impl_(std::make_unique<Impl>()) {}
SnapshotBuilder::Scratch::~Scratch() = default;
SnapshotBuilder::Scratch::Scratch(Scratch&&) noexcept = default;
SnapshotBuilder::Scratch& SnapshotBuilder::Scratch::operator=(Scratch&&) noexcept = default;

struct SnapshotBuilder::Impl {
  detail::InterestGrid grid;
  std::uint64_t tick = 0;
  bool indexed = false;
  std::size_t capacity = 0;  // per-client table size (>= grid.index_bound())
  std::vector<std::unique_ptr<Client>> clients;  // sorted by client_id
  std::uint16_t radius_unit = 1;
  std::uint16_t world_unit = 1;  // radius 0: unit for the current world extent (with hysteresis)
  Scratch scratch;               // for the build() overload without one

  Client* find(std::uint32_t client_id) const {
    auto it = std::lower_bound(clients.begin(), clients.end(), client_id,
                               [](const std::unique_ptr<Client>& c, std::uint32_t v) { return c->client_id < v; });
    return it != clients.end() && (*it)->client_id == client_id ? it->get() : nullptr;
  }
};

SnapshotBuilder::SnapshotBuilder(const InterestConfig& config) : config_(config), impl_(std::make_unique<Impl>()) {
  if (!std::isfinite(config.radius_m) || config.radius_m < 0.0 || config.radius_m > detail::kMaxCoordinateM)
    throw std::invalid_argument(
        fmt::format("SnapshotBuilder: interest radius_m {} is not in [0, 1e6]", config.radius_m));
  if (!std::isfinite(config.exit_hysteresis) || config.exit_hysteresis < 1.0 || config.exit_hysteresis > 100.0)
    throw std::invalid_argument(
        fmt::format("SnapshotBuilder: interest exit_hysteresis {} is not in [1, 100]", config.exit_hysteresis));
  check_wire_mirror();
  if (config.radius_m > kRadiusUnitOneM)
    impl_->radius_unit = unit_for_half_extent(config.radius_m * config.exit_hysteresis);
}

SnapshotBuilder::~SnapshotBuilder() = default;
SnapshotBuilder::SnapshotBuilder(SnapshotBuilder&&) noexcept = default;
SnapshotBuilder& SnapshotBuilder::operator=(SnapshotBuilder&&) noexcept = default;

void SnapshotBuilder::add_client(std::uint32_t client_id, Residency residency) {
  Impl& m = *impl_;
  if (m.find(client_id))
    throw std::invalid_argument(fmt::format("SnapshotBuilder::add_client: client {} already added", client_id));
  auto c = std::make_unique<Client>();
  c->client_id = client_id;
  c->resident = residency == Residency::kResident;
  c->reserve(m.capacity);
  auto it = std::lower_bound(m.clients.begin(), m.clients.end(), client_id,
                             [](const std::unique_ptr<Client>& x, std::uint32_t v) { return x->client_id < v; });
  m.clients.insert(it, std::move(c));
}

void SnapshotBuilder::remove_client(std::uint32_t client_id) {
  Impl& m = *impl_;
  std::erase_if(m.clients, [&](const std::unique_ptr<Client>& c) { return c->client_id == client_id; });
}

bool SnapshotBuilder::has_client(std::uint32_t client_id) const { return impl_->find(client_id) != nullptr; }

std::uint32_t SnapshotBuilder::client_count() const { return static_cast<std::uint32_t>(impl_->clients.size()); }

void SnapshotBuilder::index(const BodyView& bodies, std::uint64_t tick) {
  Impl& m = *impl_;
  m.indexed = false;
  m.grid.build(bodies, config_.radius_m > 0.0 ? config_.radius_m * kCellPerRadius : 0.0);
  m.tick = tick;

  if (m.grid.index_bound() > m.capacity) {
    m.capacity = m.grid.index_bound();
    for (auto& c : m.clients) c->reserve(m.capacity);
  }
  m.scratch.impl_->reserve(m.grid.size());

  if (config_.radius_m == 0.0) {
    // Grow the unit at once; shrink it only when the world got 25% smaller than the unit allows,
    // so a world breathing around a threshold does not flip every client's quantization.
    const double half = 0.5 * std::max(m.grid.max_x() - m.grid.min_x(), m.grid.max_y() - m.grid.min_y());
    const std::uint16_t need = unit_for_half_extent(half);
    if (need > m.world_unit) {
      m.world_unit = need;
    } else {
      const std::uint16_t relaxed = unit_for_half_extent(half * 1.25);
      if (relaxed < m.world_unit) m.world_unit = relaxed;
    }
  }
  m.indexed = true;
}

void SnapshotBuilder::reserve(Scratch& scratch) const { scratch.impl_->reserve(impl_->grid.size()); }

const BuildStats& SnapshotBuilder::build(std::uint32_t client_id, double camera_x, double camera_y,
                                         protocol::Snapshot& out) {
  return build(client_id, camera_x, camera_y, out, impl_->scratch);
}

// The frame one build() works in (origin, unit, radii, the client's stamp, the grid's arrays):
// fixed before its first phase.
struct Frame {
  std::uint32_t stamp = 0;
  std::uint32_t tick32 = 0;
  bool whole = false;
  std::uint16_t unit = 1;
  double inv_unit = 1.0;
  std::uint32_t repeat = 0, keepalive = 0, budget = 0;
  double camera_x = 0.0, camera_y = 0.0, r = 0.0;
  std::int64_t cam_mx = 0, cam_my = 0;  // camera, whole mm
  std::int32_t ox = 0, oy = 0;          // origin, mm, a multiple of the unit
  std::int64_t r2_mm = 0, rh2_mm = 0;   // radius and exit radius squared, mm^2
  float near_scale = 0.0f;
  const detail::SlotPose* gp = nullptr;
  const double* gx = nullptr;
  const double* gy = nullptr;
  const double* gz = nullptr;
  const std::int32_t* gzmm = nullptr;
  const std::uint8_t* gyaw = nullptr;
  ObjectState* obj = nullptr;

  // The client's decoded height (mm) of slot s: absolute, clamped to the int16 range of the unit.
  std::int32_t quantized_z(std::uint32_t s) const {
    if (unit == 1) return gp[s].z;  // clamped in the index
    const double fz = std::clamp(round_half_even(gz[s] * 1000.0 * inv_unit), -double(kMaxQ), double(kMaxQ));
    return static_cast<std::int32_t>(fz) * unit;
  }
  // The client's decoded position (mm) of slot s at this origin/unit; false if it does not fit.
  // At 1 mm this is the body's position rounded to a mm (a candidate within radius <= 32 m of an
  // origin at the camera always fits); coarser units round the exact value.
  bool quantize(std::uint32_t s, std::int32_t& qx, std::int32_t& qy, std::int32_t& qz) const {
    qz = quantized_z(s);
    if (unit == 1) {
      qx = gp[s].x;
      qy = gp[s].y;
      const std::int64_t dx = static_cast<std::int64_t>(qx) - ox, dy = static_cast<std::int64_t>(qy) - oy;
      return dx >= -kMaxQ && dx <= kMaxQ && dy >= -kMaxQ && dy <= kMaxQ;
    }
    const double fx = round_half_even((gx[s] * 1000.0 - ox) * inv_unit);
    const double fy = round_half_even((gy[s] * 1000.0 - oy) * inv_unit);
    qx = static_cast<std::int32_t>(ox + static_cast<std::int64_t>(std::clamp(fx, -40000.0, 40000.0)) * unit);
    qy = static_cast<std::int32_t>(oy + static_cast<std::int64_t>(std::clamp(fy, -40000.0, 40000.0)) * unit);
    return std::fabs(fx) <= kMaxQ && std::fabs(fy) <= kMaxQ;
  }
  float near_weight(std::int64_t d2) const {
    return std::max(1.0f, (1.0f + kNearWeightF) - sqrt_nonneg(static_cast<float>(d2)) * near_scale);
  }
};

// One build(): its frame and what the phases hand each other, each phase a method named as in the
// file header. Everything it writes is the client's own state, the scratch and the snapshot.
struct SnapshotBuilder::Build {
  const Impl& m;
  Client& c;
  Scratch::Impl& sc;
  protocol::Snapshot& out;
  const detail::InterestGrid& g;
  BuildStats& st;

  Frame f;  // set once; the hot phases work on a local copy (a member could alias their stores)

  // Error statistics of known in-view objects that are not sent (those that are sent are added
  // when they are written, with their quantization error).
  double err_sum = 0.0;
  float err_max = 0.0f;
  std::uint32_t err_count = 0;

  // What the phases hand on.
  std::uint32_t n_cand = 0, n_keys = 0, skipped = 0, n_unknown = 0;
  bool flat = true;
  std::size_t n_removed = 0, pose_cap = 0, n_sel = 0, codes = 0;

  Build(const SnapshotBuilder& b, Client& client, Scratch::Impl& scratch, double cx, double cy, protocol::Snapshot& o)
      : m(*b.impl_), c(client), sc(scratch), out(o), g(m.grid), st(scratch.stats) {
    sc.reserve(g.size());
    st = BuildStats{};
    set_frame(b.config_, cx, cy);
  }

  void set_frame(const InterestConfig& config, double cx, double cy);
  void gather_candidates();                              // 1a
  template <bool kUnitOne> void compare_with_copies();  // 1b
  void key_changed();                                   // 1c
  void key_unknown();                                   // 1d
  void forget_left_behind();                            // 2
  void plan_budget();                                   // 3: removals listed, pose cap
  void select_poses();                                  // 3: the poses that fit, by id
  void write_poses();                                   // 4
  const BuildStats& finish();

  void count_error(float e) {
    ++err_count;
    err_sum += e;
    err_max = std::max(err_max, e);
  }
  std::uint32_t sel_id(std::size_t j) const { return static_cast<std::uint32_t>(sc.sel[j] >> 32); }
  std::uint32_t sel_pos(std::size_t j) const { return static_cast<std::uint32_t>(sc.sel[j]); }
  // Id codes of the selection as the encoder writes them (1 per id, 3 for an escape).
  std::size_t count_codes() const {
    std::size_t n = 0;
    std::uint32_t previous = 0;
    for (std::size_t j = 0; j < n_sel; ++j) {
      n += id_codes_for(previous, sel_id(j));
      previous = sel_id(j);
    }
    return n;
  }
  // Heights the wire carries for this many poses: one when the plan is flat.
  std::size_t heights(std::size_t poses) const { return flat ? std::min<std::size_t>(poses, 1) : poses; }
};

void SnapshotBuilder::Build::set_frame(const InterestConfig& config, double cx, double cy) {
  if (++c.stamp == 0) {  // wrapped after 2^32 builds: forget stale stamps
    for (ObjectState& o : c.obj) o.seen = 0;
    c.stamp = 1;
  }
  f.stamp = c.stamp;
  f.tick32 = static_cast<std::uint32_t>(m.tick);
  f.whole = config.radius_m == 0.0;
  f.unit = f.whole ? m.world_unit : m.radius_unit;
  f.inv_unit = 1.0 / f.unit;
  f.repeat = config.removed_repeat;
  f.keepalive = config.keepalive_ticks;
  f.budget = config.budget_bytes;
  f.camera_x = cx;
  f.camera_y = cy;

  // Distances are measured in whole millimetres (the camera and the bodies rounded to a mm):
  // integer arithmetic, and at 1 mm the candidate test matches what the client decodes.
  f.cam_mx = static_cast<std::int64_t>(round_half_even(f.camera_x * 1000.0));
  f.cam_my = static_cast<std::int64_t>(round_half_even(f.camera_y * 1000.0));
  // Origin: camera (or world centre) in mm, a multiple of the unit.
  const auto snap_mm = [this](double v_m) {
    double mm = round_half_even(v_m * 1000.0);
    if (f.unit > 1) mm = round_half_even(mm * f.inv_unit) * f.unit;
    return static_cast<std::int32_t>(mm);
  };
  const double ref_x = f.whole ? 0.5 * (g.min_x() + g.max_x()) : f.camera_x;
  const double ref_y = f.whole ? 0.5 * (g.min_y() + g.max_y()) : f.camera_y;
  f.ox = snap_mm(ref_x);
  f.oy = snap_mm(ref_y);

  f.r = config.radius_m;
  const double r_mm = f.r * 1000.0, rh_mm = r_mm * config.exit_hysteresis;
  const auto square_mm = [](double v) {  // saturates: no radius is larger than the coordinate range
    const double q = std::floor(v * v);
    return q >= 9.0e18 ? std::numeric_limits<std::int64_t>::max() : static_cast<std::int64_t>(q);
  };
  f.r2_mm = f.whole ? std::numeric_limits<std::int64_t>::max() : square_mm(r_mm);
  f.rh2_mm = square_mm(rh_mm);
  // w_near = 1 + 3 * (1 - d / R) = 4 - d * (3 / R); R = radius, or the world's half diagonal.
  const double near_r_mm =
      f.whole ? 1000.0 * std::max(1.0, 0.5 * std::hypot(g.max_x() - g.min_x(), g.max_y() - g.min_y())) : r_mm;
  f.near_scale = static_cast<float>(kNearWeight / near_r_mm);

  f.gp = g.pose();
  f.gx = g.x();
  f.gy = g.y();
  f.gz = g.z();
  f.gzmm = g.z_mm();
  f.gyaw = g.yaw_q();
  f.obj = c.obj.data();
}

// 1a. Candidate slots (and their object indices): grid runs, distance test on whole mm except in
// cells entirely inside. Branchless: every slot is written, the cursor advances only for those
// inside.
void SnapshotBuilder::Build::gather_candidates() {
  const Frame fr = f;
  std::uint32_t* const cslot = sc.cslot.data();
  std::uint32_t* const cobj = sc.cobj.data();
  const detail::SlotPose* const l_gp = fr.gp;
  const std::int64_t l_cx = fr.cam_mx, l_cy = fr.cam_my, l_r2 = fr.r2_mm;
  std::uint32_t n_total = 0;
  // Each run counts in a local (the stores into cslot/cobj are u32 like the running total, whose
  // address the lambdas hold) and adds it at the end.
  const auto all = [&](std::uint32_t first, std::uint32_t end) {
    std::uint32_t n = n_total;
    for (std::uint32_t s = first; s < end; ++s, ++n) {
      cslot[n] = s;
      cobj[n] = (l_gp[s].id & ObjectId::kIndexMask) - 1u;
    }
    n_total = n;
  };
  const auto tested = [&](std::uint32_t first, std::uint32_t end) {
    std::uint32_t n = n_total;
    for (std::uint32_t s = first; s < end; ++s) {
      const detail::SlotPose p = l_gp[s];
      const std::int64_t dx = p.x - l_cx, dy = p.y - l_cy;
      cslot[n] = s;
      cobj[n] = (p.id & ObjectId::kIndexMask) - 1u;
      n += (dx * dx + dy * dy <= l_r2) ? 1u : 0u;
    }
    n_total = n;
  };
  if (fr.whole) {
    all(0, g.size());
  } else {
    // The grid assigns cells on exact positions; 2 mm more radius covers the mm rounding of the
    // bodies and the camera, and the inner cells are taken 2 mm smaller.
    g.for_each_run(fr.camera_x, fr.camera_y, fr.r + 0.002, fr.r - 0.002,
                   [&](std::uint32_t a, std::uint32_t b, std::uint32_t ia, std::uint32_t ib) {
                     if (ia >= ib) {
                       tested(a, b);
                       return;
                     }
                     tested(a, ia);
                     all(ia, ib);
                     tested(ib, b);
                   });
  }
  n_cand = n_total;
  // The prefetch in 1b reads kPrefetchAhead entries past the end: harmless index 0.
  std::fill(cobj + n_cand, cobj + n_cand + kPrefetchAhead, 0u);
  st.in_view = n_cand;
}

// 1b. Compare each candidate with the client's copy (records at scattered indices: the hot part,
// prefetched a few candidates ahead). Changed (or keepalive-due) ones go to the keyed arrays as
// integer differences; unknown ones wait for 1d. The loop works on local copies of everything it
// reads, so the compiler keeps them in registers.
template <bool kUnitOne>
void SnapshotBuilder::Build::compare_with_copies() {
  const Frame fr = f;
  const detail::SlotPose* const l_pose = fr.gp;
  const std::uint8_t* const l_yaw = fr.gyaw;
  const std::int32_t* const l_zmm = fr.gzmm;
  ObjectState* const l_obj = fr.obj;
  const std::uint32_t* const l_cslot = sc.cslot.data();
  const std::uint32_t* const l_cobj = sc.cobj.data();
  KeyIn* const l_kin = sc.kin.data();
  std::uint32_t* const l_unknown = sc.unknown.data();
  const std::int64_t l_cx = fr.cam_mx, l_cy = fr.cam_my;
  const std::uint32_t l_stamp = fr.stamp, l_tick = fr.tick32, l_keepalive = fr.keepalive, l_n = n_cand;
  std::uint32_t nk = 0, sk = 0, nu = 0, ec = 0;
  double esum = 0.0;
  float emax = 0.0f;
  for (std::uint32_t i = 0; i < l_n; ++i) {
    __builtin_prefetch(&l_obj[l_cobj[i + kPrefetchAhead]], 1, 1);
    const std::uint32_t s = l_cslot[i];
    const detail::SlotPose& p = l_pose[s];
    ObjectState& o = l_obj[l_cobj[i]];
    o.seen = l_stamp;
    const std::uint32_t age = l_tick - o.sent_tick;
    const std::uint8_t dyaw = static_cast<std::uint8_t>(l_yaw[s] - o.yaw);
    std::int32_t ex, ey, ez;  // truth (mm) - client copy
    bool unchanged, fits = true;
    KeyIn& k = l_kin[nk];  // written in place; kept only if the candidate is keyed
    if constexpr (kUnitOne) {
#if defined(__SSE2__) || defined(_M_X64)
      // (x, y, z, id) of the truth minus the copy: all zero = same object, same position.
      const __m128i d = _mm_sub_epi32(_mm_load_si128(reinterpret_cast<const __m128i*>(&p)),
                                      _mm_load_si128(reinterpret_cast<const __m128i*>(&o)));
      const int same = _mm_movemask_ps(_mm_castsi128_ps(_mm_cmpeq_epi32(d, _mm_setzero_si128())));
      if (!(same & 8)) [[unlikely]] {  // another id: unknown to the client
        l_unknown[nu++] = s;
        continue;
      }
      unchanged = (same | (dyaw == 0 ? 16 : 0)) == 31;
      _mm_store_si128(reinterpret_cast<__m128i*>(&k), d);
      ex = k.ex;
      ey = k.ey;
      ez = k.ez;
#else
      if (o.id != p.id) [[unlikely]] {
        l_unknown[nu++] = s;
        continue;
      }
      ex = p.x - o.x;
      ey = p.y - o.y;
      ez = p.z - o.z;
      unchanged = (ex | ey | ez | dyaw) == 0;
#endif
      // A height beyond the 1 mm range: the clamped copy is compared, the error is measured on
      // the real height.
      if (p.z == kMaxQ || p.z == -kMaxQ) [[unlikely]] ez = l_zmm[s] - o.z;
    } else {
      if (o.id != p.id) [[unlikely]] {
        l_unknown[nu++] = s;
        continue;
      }
      ex = p.x - o.x;
      ey = p.y - o.y;
      ez = l_zmm[s] - o.z;
      std::int32_t qx, qy, qz;
      fits = fr.quantize(s, qx, qy, qz);
      unchanged = qx == o.x && qy == o.y && qz == o.z && dyaw == 0;
    }
    if ((unchanged && age < l_keepalive) || !fits) [[unlikely]] {
      // Not sent: only its error counts (0 for an unchanged object at 1 mm, unless its height is
      // clamped). !fits: coarse unit only, cannot be sent from this origin.
      sk += unchanged ? 1u : 0u;
      ++ec;
      if (kUnitOne && unchanged && ez == 0) continue;
      const float e = error_m(ex, ey, ez);
      esum += e;
      emax = std::max(emax, e);
      continue;
    }
    const std::int64_t dx = p.x - l_cx, dy = p.y - l_cy;
    k.ex = ex;
    k.ey = ey;
    k.ez = ez;
    k.id = p.id;
    k.d2 = static_cast<float>(dx * dx + dy * dy);
    k.yaw = dyaw < 128 ? dyaw : 256 - dyaw;  // steps along the shorter way round
    k.age = static_cast<std::int32_t>(std::min<std::uint32_t>(age, 1u << 30));
    k.slot = s;
    ++nk;
  }
  n_keys = nk;
  skipped = sk;
  n_unknown = nu;
  err_count += ec;
  err_sum += esum;
  err_max = std::max(err_max, emax);
  st.skipped_unchanged = skipped;
}

// 1c. Priorities and keys of the changed candidates, four at a time (the same IEEE operations in
// the same order as the scalar tail, so the keys do not depend on the batching).
void SnapshotBuilder::Build::key_changed() {
  const Frame fr = f;
  const KeyIn* const kin = sc.kin.data();
  std::uint64_t* const kkey = sc.kkey.data();
  float* const kerr = sc.kerr.data();
  const float l_near = fr.near_scale;
  const std::uint32_t nk = n_keys;  // local: the SSE stores below may alias anything
  std::uint32_t i = 0;
#if defined(__SSE2__) || defined(_M_X64)
  const __m128 v_near = _mm_set1_ps(l_near), v_mm = _mm_set1_ps(0.001f), v_one = _mm_set1_ps(1.0f),
               v_w0 = _mm_set1_ps(1.0f + kNearWeightF), v_yaw = _mm_set1_ps(kYawMPerStepF),
               v_age = _mm_set1_ps(kAgePerTickF);
  const __m128i v_ones = _mm_set1_epi32(-1);
  for (; i + 4 <= nk; i += 4) {
    // Transpose four records into (ex, ey, ez, id) and (d2, yaw, age, slot) lanes.
    const auto* rec = reinterpret_cast<const __m128*>(kin + i);
    __m128 a0 = _mm_load_ps(reinterpret_cast<const float*>(rec + 0)), a1 = _mm_load_ps(reinterpret_cast<const float*>(rec + 2)),
           a2 = _mm_load_ps(reinterpret_cast<const float*>(rec + 4)), a3 = _mm_load_ps(reinterpret_cast<const float*>(rec + 6));
    __m128 b0 = _mm_load_ps(reinterpret_cast<const float*>(rec + 1)), b1 = _mm_load_ps(reinterpret_cast<const float*>(rec + 3)),
           b2 = _mm_load_ps(reinterpret_cast<const float*>(rec + 5)), b3 = _mm_load_ps(reinterpret_cast<const float*>(rec + 7));
    _MM_TRANSPOSE4_PS(a0, a1, a2, a3);  // a0 = ex, a1 = ey, a2 = ez, a3 = id (as bits)
    _MM_TRANSPOSE4_PS(b0, b1, b2, b3);  // b0 = d2, b1 = yaw, b2 = age
    const __m128 fx = _mm_cvtepi32_ps(_mm_castps_si128(a0));
    const __m128 fy = _mm_cvtepi32_ps(_mm_castps_si128(a1));
    const __m128 fz = _mm_cvtepi32_ps(_mm_castps_si128(a2));
    const __m128 e2 = _mm_add_ps(_mm_add_ps(_mm_mul_ps(fx, fx), _mm_mul_ps(fy, fy)), _mm_mul_ps(fz, fz));
    const __m128 e = _mm_mul_ps(_mm_sqrt_ps(e2), v_mm);
    const __m128 w = _mm_max_ps(v_one, _mm_sub_ps(v_w0, _mm_mul_ps(_mm_sqrt_ps(b0), v_near)));
    const __m128 fyaw = _mm_cvtepi32_ps(_mm_castps_si128(b1));
    const __m128 fage = _mm_cvtepi32_ps(_mm_castps_si128(b2));
    const __m128 pri = _mm_add_ps(_mm_mul_ps(_mm_add_ps(e, _mm_mul_ps(fyaw, v_yaw)), w), _mm_mul_ps(v_age, fage));
    _mm_storeu_ps(kerr + i, e);
    const __m128i ids = _mm_xor_si128(_mm_castps_si128(a3), v_ones);
    const __m128i bits = _mm_castps_si128(pri);
    _mm_storeu_si128(reinterpret_cast<__m128i*>(kkey + i), _mm_unpacklo_epi32(ids, bits));
    _mm_storeu_si128(reinterpret_cast<__m128i*>(kkey + i + 2), _mm_unpackhi_epi32(ids, bits));
  }
#endif
  for (; i < nk; ++i) {
    const KeyIn& k = kin[i];
    const float e = error_m(k.ex, k.ey, k.ez);
    const float w = std::max(1.0f, (1.0f + kNearWeightF) - sqrt_nonneg(k.d2) * l_near);
    const float priority = (e + static_cast<float>(k.yaw) * kYawMPerStepF) * w + kAgePerTickF * static_cast<float>(k.age);
    kerr[i] = e;
    kkey[i] = priority_key(priority, k.id);
  }
}

// 1d. Candidates the client does not know (never sent, removed, or a new object at a recycled
// index): the highest priorities, nearest first.
void SnapshotBuilder::Build::key_unknown() {
  const Frame fr = f;
  KeyIn* const kin = sc.kin.data();
  std::uint64_t* const kkey = sc.kkey.data();
  float* const kerr = sc.kerr.data();
  const std::uint32_t* const unknown = sc.unknown.data();
  // Local counts: the stores into kin below are u32 and could otherwise alias the members.
  const std::uint32_t l_unknown = n_unknown;
  std::uint32_t nk = n_keys;
  for (std::uint32_t i = 0; i < l_unknown; ++i) {
    const std::uint32_t s = unknown[i];
    const detail::SlotPose p = fr.gp[s];
    ObjectState& o = fr.obj[(p.id & ObjectId::kIndexMask) - 1u];
    if (o.id != 0 && fr.repeat > 0) c.pending.push_back({o.id, fr.repeat});  // the old object was destroyed
    o = ObjectState{};
    o.seen = fr.stamp;
    std::int32_t qx, qy, qz;
    if (!fr.quantize(s, qx, qy, qz)) continue;
    const std::int64_t dx = p.x - fr.cam_mx, dy = p.y - fr.cam_my;
    kin[nk].slot = s;
    kerr[nk] = -1.0f;
    kkey[nk] = priority_key(kUnknownPriorityF * fr.near_weight(dx * dx + dy * dy), p.id);
    ++nk;
  }
  n_keys = nk;
}

// 2. Known objects that are gone or beyond the hysteresis radius.
void SnapshotBuilder::Build::forget_left_behind() {
  const Frame fr = f;
  std::size_t w = 0;
  KnownEntry* const known = c.known.data();
  const std::size_t n_known = c.known.size();
  for (std::size_t i = 0; i < n_known; ++i) {
    const KnownEntry e = known[i];
    ObjectState& o = fr.obj[e.index];
    if (o.id == e.id && o.seen == fr.stamp) [[likely]] {  // a candidate: in view
      known[w++] = e;
      continue;
    }
    if (o.id != e.id) continue;  // replaced at this index (removal already queued)
    bool keep = false;
    const std::int32_t s = g.slot_of(e.index);
    if (s >= 0 && fr.gp[s].id == e.id) {
      const std::int64_t dx = fr.gp[s].x - fr.cam_mx, dy = fr.gp[s].y - fr.cam_my;
      keep = fr.whole || dx * dx + dy * dy <= fr.rh2_mm;
    }
    if (keep) {
      known[w++] = e;
      continue;
    }
    if (fr.repeat > 0) c.pending.push_back({e.id, fr.repeat});
    o = ObjectState{};
  }
  c.known.resize(w);
}

// 3. Removals that fit, oldest first; each is listed in `repeat` snapshots in total.
// Flat: every keyed candidate has the same quantized height, so whatever is selected shares it and
// travels as one z (protocol::share_equal_heights): poses cost 7 bytes instead of 9, and the
// budget holds more of them. Otherwise the plan counts a z per pose (a selection that happens to
// share one height is still written shared, and is then smaller than planned).
void SnapshotBuilder::Build::plan_budget() {
  const Frame fr = f;
  const KeyIn* const kin = sc.kin.data();
  flat = true;
  if (fr.budget > 0 && n_keys > 1) {
    const std::int32_t z0 = fr.quantized_z(kin[0].slot);
    for (std::uint32_t i = 1; i < n_keys && flat; ++i) flat = fr.quantized_z(kin[i].slot) == z0;
  }
  n_removed = c.pending.size();
  pose_cap = n_keys;
  if (fr.budget > 0) {
    const std::size_t base = wire_bytes(0, 0, 0, 0);
    if (fr.budget < base) {
      n_removed = 0;
      pose_cap = 0;
    } else {
      n_removed = std::min(n_removed, (fr.budget - base) / 4 + 1);
      while (n_removed > 0 && wire_bytes(0, 0, n_removed, 0) > fr.budget) --n_removed;
      const std::size_t with_removed = wire_bytes(0, 0, n_removed, 0);
      const std::size_t per_pose = flat ? protocol::kSharedZPoseWireBytes : protocol::kPoseWireBytes;
      pose_cap = std::min(pose_cap, (fr.budget - with_removed) / per_pose + 1);
      while (pose_cap > 0 && wire_bytes(pose_cap, pose_cap, n_removed, heights(pose_cap)) > fr.budget) --pose_cap;
    }
  }
  out.removed.resize(n_removed);
  for (std::size_t i = 0; i < n_removed; ++i) {
    out.removed[i] = c.pending[i].id;
    --c.pending[i].left;
  }
  std::erase_if(c.pending, [](const PendingRemoval& p) { return p.left == 0; });
}

// 3. Poses: the largest keys that fit. Keys are unique (ids are), so "key >= the k-th largest"
// selects exactly k; the others' errors go to the statistics. The selection is kept as
// (id << 32 | position in the keyed arrays), sorted by id.
void SnapshotBuilder::Build::select_poses() {
  const Frame fr = f;
  std::uint64_t* const sel = sc.sel.data();
  const std::uint64_t* const kkey = sc.kkey.data();
  const float* const kerr = sc.kerr.data();
  const std::size_t k = std::min(pose_cap, static_cast<std::size_t>(n_keys));
  std::size_t ns = 0;  // local: the stores into sel are the same type as the member n_sel
  {
    std::uint64_t threshold = 0;
    if (k < n_keys)
      threshold = k == 0 ? std::numeric_limits<std::uint64_t>::max()
                         : kth_largest(kkey, n_keys, k, sc.hist.data(), sc.kth.data(), sc.kth2.data());
    // Branch-free: which keys pass is data-dependent. Not sent and known: the error counts.
    // (k == 0: the threshold is above every key, a NaN priority being impossible.)
    std::uint32_t count = 0;
    float sum = 0.0f, emax = 0.0f;
    for (std::uint32_t i = 0; i < n_keys; ++i) {
      const auto take = static_cast<std::uint32_t>(kkey[i] >= threshold);
      sel[ns] = static_cast<std::uint64_t>(key_id(kkey[i])) << 32 | i;
      ns += take;
      // Error of a known object that is not sent, else -1 (as bits: all-ones mask selects -1).
      const std::uint32_t bits = (std::bit_cast<std::uint32_t>(kerr[i]) & (take - 1u)) |
                                 (std::bit_cast<std::uint32_t>(-1.0f) & (0u - take));
      const float e = std::bit_cast<float>(bits);
      count += static_cast<std::uint32_t>(e >= 0.0f);
      sum += std::max(e, 0.0f);
      emax = std::max(emax, e);
    }
    err_count += count;
    err_sum += sum;
    err_max = std::max(err_max, emax);
  }
  n_sel = ns;
  sort_by_id(sel, n_sel, sc.kth.data(), sc.hist.data());
  codes = count_codes();
  if (fr.budget == 0) return;
  while (n_sel > 0 && wire_bytes(codes, n_sel, n_removed, heights(n_sel)) > fr.budget) {
    // Drop the lowest priority (rare: only when id escapes did not fit), then recount.
    std::size_t lowest = 0;
    for (std::size_t j = 1; j < n_sel; ++j)
      if (kkey[sel_pos(j)] < kkey[sel_pos(lowest)]) lowest = j;
    const float e = kerr[sel_pos(lowest)];
    if (e >= 0.0f) count_error(e);
    std::copy(sel + lowest + 1, sel + n_sel, sel + lowest);
    --n_sel;
    codes = count_codes();
  }
}

// 4. Write the pose arrays and update the client's copies.
void SnapshotBuilder::Build::write_poses() {
  const Frame fr = f;
  const KeyIn* const kin = sc.kin.data();
  out.origin_x_mm = fr.ox;
  out.origin_y_mm = fr.oy;
  out.unit_mm = fr.unit;
  out.id_codes.resize(codes);
  out.x.resize(n_sel);
  out.y.resize(n_sel);
  out.z.resize(n_sel);
  out.yaw.resize(n_sel);
  std::uint16_t* oc = out.id_codes.data();
  std::int16_t* px = out.x.data();
  std::int16_t* py = out.y.data();
  std::int16_t* pz = out.z.data();
  std::uint8_t* pyaw = out.yaw.data();
  std::uint32_t previous = 0;
  std::size_t ci = 0;
  // Local error sums (a running sum continued, so the additions happen in the same order).
  std::uint32_t ec = 0;
  double esum = err_sum;
  float emax = err_max;
  // Locals: the byte stores below may alias any member.
  const std::uint64_t* const sel = sc.sel.data();
  const std::size_t ns = n_sel;
  for (std::size_t i = 0; i < ns; ++i) {
    const auto id = static_cast<std::uint32_t>(sel[i] >> 32);
    const std::uint32_t s = kin[static_cast<std::uint32_t>(sel[i])].slot;
    const std::uint32_t idx = (id & ObjectId::kIndexMask) - 1u;
    ObjectState& o = fr.obj[idx];
    std::int32_t qx, qy, qz;
    if (!fr.quantize(s, qx, qy, qz))  // selected candidates fit: checked when they were keyed
      throw std::logic_error("SnapshotBuilder::build: a selected pose did not fit the quantization range");
    if (o.id != id) c.known.push_back({idx, id});
    o.id = id;
    o.x = qx;
    o.y = qy;
    o.z = qz;
    o.yaw = fr.gyaw[s];
    o.sent_tick = fr.tick32;
    const std::uint32_t delta = id - previous;
    if (delta >= 1 && delta <= 0xFFFF) {
      oc[ci++] = static_cast<std::uint16_t>(delta);
    } else {
      oc[ci++] = 0;
      oc[ci++] = static_cast<std::uint16_t>(id >> 16);
      oc[ci++] = static_cast<std::uint16_t>(id & 0xFFFF);
    }
    previous = id;
    // What protocol::encode_poses writes for the decoded copy: the offsets are exact multiples of
    // the unit (the origin is one), z too.
    px[i] = static_cast<std::int16_t>((qx - fr.ox) / fr.unit);
    py[i] = static_cast<std::int16_t>((qy - fr.oy) / fr.unit);
    pz[i] = static_cast<std::int16_t>(qz / fr.unit);
    pyaw[i] = o.yaw;
    // Error right after the update: the quantization (and a clamped height).
    const detail::SlotPose p = fr.gp[s];
    const float e = error_m(p.x - qx, p.y - qy, fr.gzmm[s] - qz);
    ++ec;
    esum += e;
    emax = std::max(emax, e);
  }
  err_count += ec;
  err_sum = esum;
  err_max = emax;
  protocol::share_equal_heights(out);  // as protocol::encode_poses ends
  // A removal still pending for an id whose pose was just sent again would delete it on the client
  // later: drop it (if it was listed in this snapshot, the client applies the removal before the
  // poses).
  if (!c.pending.empty() && n_sel > 0) {
    std::erase_if(c.pending, [&](const PendingRemoval& p) {
      const std::uint64_t* it = std::lower_bound(sel, sel + n_sel, static_cast<std::uint64_t>(p.id) << 32);
      return it != sel + n_sel && static_cast<std::uint32_t>(*it >> 32) == p.id;
    });
  }
}

const BuildStats& SnapshotBuilder::Build::finish() {
  if (f.budget > 0 && protocol::snapshot_wire_bytes(out) > f.budget)
    throw std::logic_error("SnapshotBuilder::build: snapshot exceeds the byte budget (wire size model out of date)");
  out.objects_in_view = st.in_view;
  st.sent = static_cast<std::uint32_t>(n_sel);
  st.view_error_max_m = err_max;
  st.view_error_mean_m = err_count ? err_sum / err_count : 0.0;
  return st;
}

const BuildStats& SnapshotBuilder::build(std::uint32_t client_id, double camera_x, double camera_y,
                                         protocol::Snapshot& out, Scratch& scratch) {
  Client* c = impl_->find(client_id);
  if (!c) throw std::invalid_argument(fmt::format("SnapshotBuilder::build: unknown client {}", client_id));
  if (!(std::fabs(camera_x) <= detail::kMaxCoordinateM))
    throw std::invalid_argument(
        fmt::format("SnapshotBuilder::build: camera_x {} is not a finite coordinate within 1e6 m", camera_x));
  if (!(std::fabs(camera_y) <= detail::kMaxCoordinateM))
    throw std::invalid_argument(
        fmt::format("SnapshotBuilder::build: camera_y {} is not a finite coordinate within 1e6 m", camera_y));
  if (!impl_->indexed) throw std::logic_error("SnapshotBuilder::build: index() was not called (or failed) before build()");

  Build b(*this, *c, *scratch.impl_, camera_x, camera_y, out);
  b.gather_candidates();
  if (b.f.unit == 1)
    b.compare_with_copies<true>();
  else
    b.compare_with_copies<false>();
  b.key_changed();
  b.key_unknown();
  b.forget_left_behind();
  b.plan_budget();
  b.select_poses();
  b.write_poses();
  return b.finish();
}


// --- checkpoints ----------------------------------------------------------------------------------
// Per client: id, stamp, then each known entry (index, id) with the client's copy at that index
// (field by field: the struct has padding), then the pending removals, in their current order.
// Only records at known indices are saved, the rest restore as empty: every record with a non-zero
// id is in `known` (a copy is added to known when first sent, and zeroed when it leaves it), and
// a record with id 0 is never read before it is rewritten (1b sends it to the unknown path, 1d
// resets it, phase 2 only visits known indices). That keeps a save proportional to what the
// clients know instead of clients x object indices.

namespace {
constexpr std::size_t kKnownRecordBytes = 33;  // index, entry id, x, y, z, copy id, seen, sent tick, yaw
}  // namespace

void SnapshotBuilder::save_state(ByteWriter& w) const {
  const Impl& m = *impl_;
  w.put(m.world_unit);
  w.put(static_cast<std::uint32_t>(m.capacity));
  w.put(static_cast<std::uint32_t>(m.clients.size()));
  for (const auto& cp : m.clients) {
    const Client& c = *cp;
    w.put(c.client_id);
    w.put(c.stamp);
    w.put(static_cast<std::uint32_t>(c.known.size()));
    std::uint8_t* p = w.grow(c.known.size() * kKnownRecordBytes);
    const std::size_t n_known = c.known.size();
    for (std::size_t i = 0; i < n_known; ++i) {
      // Known entries are in the order objects became known, i.e. scattered object indices.
      if (i + kPrefetchAhead < n_known) __builtin_prefetch(&c.obj[c.known[i + kPrefetchAhead].index], 0, 1);
      const KnownEntry& e = c.known[i];
      const ObjectState& o = c.obj[e.index];
      const std::uint32_t v[8] = {e.index, e.id, static_cast<std::uint32_t>(o.x), static_cast<std::uint32_t>(o.y),
                                  static_cast<std::uint32_t>(o.z), o.id, o.seen, o.sent_tick};
      std::memcpy(p, v, sizeof v);
      p[sizeof v] = o.yaw;
      p += kKnownRecordBytes;
    }
    w.put(static_cast<std::uint32_t>(c.pending.size()));
    for (const PendingRemoval& pr : c.pending) { w.put(pr.id); w.put(pr.left); }
  }
}

void SnapshotBuilder::restore_state(ByteReader& r, std::size_t max_capacity) {
  const std::size_t kMaxObjects = std::min<std::size_t>(max_capacity, std::size_t{ObjectId::kMaxIndex} + 1);
  const auto world_unit = r.get<std::uint16_t>("snapshot world unit");
  if (world_unit == 0) r.fail("snapshot world unit 0");
  const std::size_t capacity = std::max<std::size_t>(impl_->capacity, r.get_count("snapshot capacity", kMaxObjects));
  std::vector<std::unique_ptr<Client>> clients(r.get_count("snapshot clients", 1u << 20, 16));
  std::uint32_t previous = 0;
  for (auto& cp : clients) {
    cp = std::make_unique<Client>();
    Client& c = *cp;
    c.client_id = r.get<std::uint32_t>("snapshot client id");
    if (c.client_id <= previous) r.fail("snapshot client ids not ascending");
    previous = c.client_id;
    c.stamp = r.get<std::uint32_t>("snapshot stamp");
    c.reserve(capacity);  // lazy: a restored client is not made resident
    c.known.resize(r.get_count("snapshot known", 2 * capacity + 64, kKnownRecordBytes));
    const std::uint8_t* p = r.take(c.known.size() * kKnownRecordBytes, "snapshot known");
    for (KnownEntry& e : c.known) {
      std::uint32_t v[8];
      std::memcpy(v, p, sizeof v);
      if (v[0] >= capacity) r.fail("snapshot known index beyond the capacity");
      e.index = v[0];
      e.id = v[1];
      ObjectState& o = c.obj[e.index];
      o.x = static_cast<std::int32_t>(v[2]);
      o.y = static_cast<std::int32_t>(v[3]);
      o.z = static_cast<std::int32_t>(v[4]);
      o.id = v[5];
      o.seen = v[6];
      o.sent_tick = v[7];
      o.yaw = p[sizeof v];
      p += kKnownRecordBytes;
    }
    c.pending.resize(r.get_count("snapshot pending", 4 * capacity + 1024, 8));
    for (PendingRemoval& pr : c.pending) {
      pr.id = r.get<std::uint32_t>("snapshot pending");
      pr.left = r.get<std::uint32_t>("snapshot pending");
    }
  }
  Impl& m = *impl_;
  m.world_unit = world_unit;
  m.capacity = capacity;
  m.clients = std::move(clients);
  m.indexed = false;  // build() needs this tick's index() first, as after construction
}

}  // namespace throng::match
