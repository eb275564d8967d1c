// diff_world_states: decode both sections, pair the bodies by object id, compare field by field.
#include "throng/world/world_state_diff.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "throng/params/object_params.h"
#include "world/world_state.h"

namespace throng {
namespace {

detail::WorldState decode_exact(std::span<const std::uint8_t> bytes) {
  ByteReader r(bytes);
  detail::WorldState st = detail::decode_world_state(r);
  if (r.remaining() != 0) r.fail(std::to_string(r.remaining()) + " bytes after the world state");
  return st;
}

// Dense index of the body with this id, or -1.
std::int64_t dense_of(const detail::WorldState& st, ObjectId id) {
  const std::uint32_t s = id.index();
  if (s >= st.slot_kind.size() || st.slot_kind[s] != 1) return -1;
  const std::uint32_t d = st.slot_ref[s];
  return st.bodies.id[d] == id ? static_cast<std::int64_t>(d) : -1;
}

void add(std::string& what, const char* name, double a, double b) {
  // Bitwise: the checkpoints must be bit-identical, and NaN == NaN must count as equal.
  if (std::memcmp(&a, &b, sizeof a) == 0) return;
  if (!what.empty()) what += "; ";
  char buf[96];
  std::snprintf(buf, sizeof buf, " %.17g vs %.17g", a, b);
  what += name;
  what += buf;
}

// A body's differences, and how far apart it went: the largest difference of its position,
// velocities or push (infinite when a size or parameter differs, which is never a rounding
// difference spreading through the crowd).
struct Compared {
  std::string what;
  double size = 0.0;
};

void motion(Compared& c, const char* name, double a, double b) {
  if (std::memcmp(&a, &b, sizeof a) == 0) return;  // equal bits (NaN or inf alike): no difference
  add(c.what, name, a, b);
  const double d = std::fabs(a - b);
  if (d != d) {  // a NaN on either side
    c.size = HUGE_VAL;
  } else if (d > c.size) {
    c.size = d;
  }
}

Compared compare(const detail::WorldState& A, std::size_t i, const detail::WorldState& B, std::size_t j) {
  Compared c;
  std::string& w = c.what;
  const detail::BodyStore& a = A.bodies;
  const detail::BodyStore& b = B.bodies;
  motion(c, "x", a.x[i], b.x[j]); motion(c, "y", a.y[i], b.y[j]); motion(c, "z", a.z[i], b.z[j]);
  motion(c, "desired_vx", a.vx[i], b.vx[j]); motion(c, "desired_vy", a.vy[i], b.vy[j]); motion(c, "desired_vz", a.vz[i], b.vz[j]);
  motion(c, "vx", a.ax[i], b.ax[j]); motion(c, "vy", a.ay[i], b.ay[j]); motion(c, "vz", a.az[i], b.az[j]);
  motion(c, "push_x", a.push_x[i], b.push_x[j]); motion(c, "push_y", a.push_y[i], b.push_y[j]);
  const std::size_t before_size = w.size();
  add(w, "radius", a.r[i], b.r[j]); add(w, "half_height", a.hh[i], b.hh[j]);
  if (w.size() != before_size) c.size = HUGE_VAL;
  add(w, "grounded", a.grounded[i], b.grounded[j]);
  add(w, "resistance", a.resistance[i], b.resistance[j]);
  add(w, "morale_level", a.morale_level[i], b.morale_level[j]);
  add(w, "warm_count", a.warm_count[i], b.warm_count[j]);
  if (a.warm_count[i] == b.warm_count[j]) {
    for (std::uint32_t k = 0; k < a.warm_count[i]; ++k) {
      const detail::WarmEntry& ea = a.warm[i * detail::kWarmSlots + k];
      const detail::WarmEntry& eb = b.warm[j * detail::kWarmSlots + k];
      add(w, "warm.partner", ea.partner, eb.partner);
      add(w, "warm.lambda", ea.lambda, eb.lambda);
    }
  }
  // Where a kept pair list was searched (the list follows from it).
  if (A.pair_list_kept != B.pair_list_kept) {
    add(w, "pair_list_kept", A.pair_list_kept, B.pair_list_kept);
  } else if (A.pair_list_kept) {
    add(w, "pair_list.x", A.pair_list_x[i], B.pair_list_x[j]);
    add(w, "pair_list.y", A.pair_list_y[i], B.pair_list_y[j]);
    add(w, "pair_list.z", A.pair_list_z[i], B.pair_list_z[j]);
  }
  const params::ObjectParams& pa = A.body_params[i];
  const params::ObjectParams& pb = B.body_params[j];
  const std::size_t before_params = w.size();
  for (std::size_t k = 0; k < params::kParamCount; ++k) {
    const auto p = static_cast<params::Param>(k);
    const std::string name = "params." + std::string(params::param_name(p));
    add(w, name.c_str(), pa.get(p), pb.get(p));
  }
  if (w.size() != before_params) c.size = HUGE_VAL;
  return c;
}

}  // namespace

std::vector<BodyDifference> diff_world_states(std::span<const std::uint8_t> a_bytes, std::span<const std::uint8_t> b_bytes,
                                              std::size_t max) {
  const detail::WorldState a = decode_exact(a_bytes);
  const detail::WorldState b = decode_exact(b_bytes);
  struct Found {
    BodyDifference d;
    double size;
  };
  std::vector<Found> found;
  for (std::size_t i = 0; i < a.bodies.size(); ++i) {
    const ObjectId id = a.bodies.id[i];
    const std::int64_t j = dense_of(b, id);
    if (j < 0) {
      found.push_back({{id.value, "only in the first checkpoint"}, HUGE_VAL});
      continue;
    }
    Compared c = compare(a, i, b, static_cast<std::size_t>(j));
    if (!c.what.empty()) found.push_back({{id.value, std::move(c.what)}, c.size});
  }
  for (std::size_t j = 0; j < b.bodies.size(); ++j) {
    if (dense_of(a, b.bodies.id[j]) < 0) found.push_back({{b.bodies.id[j].value, "only in the second checkpoint"}, HUGE_VAL});
  }
  // The pair list's counters belong to no body: reported under object id 0 (no object has it).
  std::string list_what;
  add(list_what, "pair_list.kept_ticks", a.pair_list_kept_ticks, b.pair_list_kept_ticks);
  add(list_what, "pair_list.cooldown", a.pair_list_cooldown, b.pair_list_cooldown);
  add(list_what, "pair_list.backoff", a.pair_list_backoff, b.pair_list_backoff);
  add(list_what, "pair_list.ahead_begun", static_cast<std::uint32_t>(a.pair_list_ahead_begun),
      static_cast<std::uint32_t>(b.pair_list_ahead_begun));
  if (!list_what.empty()) found.push_back({{0, "world: " + list_what}, HUGE_VAL});
  // A divergence spreads: one wrong body nudges its neighbours by rounding-sized amounts within a
  // tick. When more differ than are reported, the ones that went furthest apart are the cause.
  if (found.size() > max) {
    std::stable_sort(found.begin(), found.end(), [](const Found& x, const Found& y) {
      return x.size != y.size ? x.size > y.size : x.d.object_id < y.d.object_id;
    });
    found.resize(max);
  }
  std::sort(found.begin(), found.end(), [](const Found& x, const Found& y) { return x.d.object_id < y.d.object_id; });
  std::vector<BodyDifference> out;
  out.reserve(found.size());
  for (Found& f : found) out.push_back(std::move(f.d));
  return out;
}

}  // namespace throng
