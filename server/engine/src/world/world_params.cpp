// Parameters inside the tick: the dynamic ones recomputed from the world (speed and facing from
// motion, height above ground, distance to the nearest camera, group morale from the local count of
// allies and enemies), then the push coefficients of every body whose parameters changed, and the
// per-pair share the solver uses.
#include <algorithm>
#include <array>
#include <cmath>

#include "throng/params/dynamic_params.h"
#include "world/world_impl.h"

namespace throng {
namespace {

bool rules_read(const params::PushPolicy& policy, params::Param p) {
  for (const params::PairRule& r : policy.rules()) {
    for (const params::ParamBound& b : r.a.ranges) if (b.param == p) return true;
    for (const params::ParamBound& b : r.b.ranges) if (b.param == p) return true;
  }
  return false;
}

bool terms_read(const params::PushPolicy& policy, params::TermInput t) {
  return std::any_of(policy.terms().begin(), policy.terms().end(), [t](const params::Term& term) { return term.input == t; });
}

}  // namespace

void World::Impl::refresh_dynamic_use() {
  using params::Param;
  using params::TermInput;
  dyn.speed_facing = terms_read(policy, TermInput::speed_mps) || terms_read(policy, TermInput::facing) ||
                     rules_read(policy, Param::speed_mps) || rules_read(policy, Param::facing_yaw_rad);
  dyn.height = terms_read(policy, TermInput::height_above_ground_m) || rules_read(policy, Param::height_above_ground_m);
  dyn.camera = terms_read(policy, TermInput::camera_distance_m) || rules_read(policy, Param::camera_distance_m);
  dyn.morale = policy.uses_morale();
  // Pair shares need more than the two resistances when any of these hold.
  dyn.slow_share = policy.mode() != params::PushMode::ratio || !policy.rules().empty() ||
                   policy.has_pair_dependent_terms();
  dyn.policy_version = policy_version;
}

void World::Impl::update_dynamic_params() {
  if (dyn.policy_version != policy_version) refresh_dynamic_use();
  const std::size_t n = bodies.size();
  const bool per_body = dyn.speed_facing || dyn.height || dyn.camera;
  // These read (or write) every body's record each tick: in dense order, not through params_order.
  if (per_body || dyn.morale || dyn.slow_share) settle_params();
  if (per_body) {
    camera_xyz.resize(cameras.size());
    for (std::size_t c = 0; c < cameras.size(); ++c) camera_xyz[c] = {cameras[c].x, cameras[c].y, cameras[c].z};
    for (std::size_t i = 0; i < n; ++i) {
      params::ObjectParams& p = body_params[i];  // settled above
      if (dyn.speed_facing) params::apply_velocity(p, bodies.ax[i], bodies.ay[i], bodies.az[i]);
      const double base_z = bodies.z[i] - bodies.hh[i] - bodies.r[i];
      if (dyn.height) {
        const double ground = scenery.size() > 0 ? scenery.ground_height(bodies.x[i], bodies.y[i], base_z) : 0.0;
        p.height_above_ground_m = std::clamp(params::height_above_ground_m(base_z, ground), -1e6, 1e6);
      }
      if (dyn.camera) p.camera_distance_m = params::camera_distance_m(camera_xyz, bodies.x[i], bodies.y[i], bodies.z[i]);
    }
    all_coefficients_dirty = true;
  }
  if (dyn.morale) update_morale_counts();
}

// Morale is judged per group from the allies and enemies around its members. Counting the whole
// crowd every tick would cost as much as the solve, so 1/morale_refresh_ticks of the bodies (by
// dense index, round robin) are counted each tick and the groups' levels advance once per period.
void World::Impl::update_morale_counts() {
  const std::size_t n = bodies.size();
  const std::uint32_t period = settings.morale_refresh_ticks;
  const std::uint32_t phase = static_cast<std::uint32_t>(tick % period);
  // Also when the counts were never started: a policy that turns morale on mid-period (an
  // operator's change) would otherwise count into empty tables (out of bounds).
  if (phase == 0 || morale_allies.empty()) {
    morale_allies.assign(params::kMaxGroupId + 1, 0);
    morale_enemies.assign(params::kMaxGroupId + 1, 0);
  }
  const double r2 = settings.morale_radius_m * settings.morale_radius_m;
  morale_index.build(bodies.x.data(), bodies.y.data(), n, settings.morale_radius_m);
  for (std::size_t i = phase; i < n; i += period) {
    const params::ObjectParams& p = body_params[i];
    if (p.group_id == 0) continue;
    morale_index.for_each_near(bodies.x[i], bodies.y[i], [&](std::uint32_t j) {
      if (j == i) return;
      const double dx = bodies.x[j] - bodies.x[i], dy = bodies.y[j] - bodies.y[i];
      if (dx * dx + dy * dy > r2) return;
      const params::ObjectParams& q = body_params[j];
      if (q.faction == params::kNeutralFaction || p.faction == params::kNeutralFaction) return;
      if (q.faction == p.faction) ++morale_allies[p.group_id];
      else ++morale_enemies[p.group_id];
    });
  }
  if (phase + 1 == period) {
    bool changed = false;
    // Walk ids instead of groups.ids(): that returns a fresh vector, and the tick must not allocate.
    for (std::uint32_t g = 1; g <= params::kMaxGroupId; ++g) {
      if (!groups.contains(g)) continue;
      const params::MoraleState before = groups.at(g).morale_state;
      changed |= groups.update_morale(g, morale_allies[g], morale_enemies[g]) != before;
    }
    if (changed) all_coefficients_dirty = true;
  }
}

void World::Impl::refresh_coefficients() {
  const std::size_t n = bodies.size();
  for (std::size_t i = 0; i < n; ++i) {
    if (!all_coefficients_dirty && bodies.coeff_dirty[i] == 0) continue;
    const params::ObjectParams& p = params_of(i);
    const params::PushCoefficients c = policy.coefficients(p, groups);
    // A kept pair list keeps its pairs' shares until a resistance changes.
    if (!(bodies.resistance[i] == c.resistance)) list.shares_stale = true;
    bodies.resistance[i] = c.resistance;
    bodies.rule_lhs[i] = c.rule_mask_lhs;
    bodies.rule_rhs[i] = c.rule_mask_rhs;
    // A new collision filter changes which pairs exist: the kept pair list is dropped.
    if (bodies.group[i] != p.collision_group || bodies.mask[i] != p.collision_mask) list.drop();
    bodies.group[i] = p.collision_group;
    bodies.mask[i] = p.collision_mask;
    bodies.coeff_dirty[i] = 0;
  }
  all_coefficients_dirty = false;
}

double World::Impl::pair_share(std::uint32_t a, std::uint32_t b, double nx, double ny) const {
  if (!dyn.slow_share) return params::share_a_fast(bodies.resistance[a], bodies.resistance[b]);
  const params::PairView va{{bodies.resistance[a], bodies.rule_lhs[a], bodies.rule_rhs[a]},
                            &params_of(a), bodies.id[a].value, nx, ny, 0.0};
  const params::PairView vb{{bodies.resistance[b], bodies.rule_lhs[b], bodies.rule_rhs[b]},
                            &params_of(b), bodies.id[b].value, -nx, -ny, 0.0};
  return policy.share_a(va, vb, groups);
}

}  // namespace throng
