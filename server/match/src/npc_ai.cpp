#include "npc_ai.h"

#include <array>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "dense_order.h"
#include "throng/params/group_table.h"
#include "throng/params/object_params.h"
#include "throng/params/push_policy.h"
#include "throng/world/world.h"

namespace throng::match {
namespace {

constexpr std::uint16_t kNoSlot = 0xFFFF;
// Cells per faction slot; a world so spread out that 3 m cells would exceed this gets coarser
// cells instead (the grid's memory stays bounded whatever the bodies do).
constexpr double kMaxCells = 131072.0;
constexpr std::uint32_t kNoTarget = 0xFFFFFFFFu;

// atan2 by a minimax polynomial on [0, 1] (max error ~1e-5 rad, far below the 256-step yaw of a
// snapshot): a third of libm's cost here, and plain arithmetic, so the same on every machine.
float fast_atan2(double y, double x) {
  const double ax = std::abs(x);
  const double ay = std::abs(y);
  const double hi = std::max(ax, ay);
  if (!(hi > 0.0)) return 0.0f;
  const double a = std::min(ax, ay) / hi;
  const double s = a * a;
  double r = ((-0.0464964749 * s + 0.15931422) * s - 0.327622764) * s * a + a;
  if (ay > ax) r = std::numbers::pi / 2 - r;
  if (x < 0.0) r = std::numbers::pi - r;
  if (y < 0.0) r = -r;
  return static_cast<float>(r);
}

}  // namespace

NpcAi::NpcAi(const NpcAiSettings& settings) : settings_(settings) {
  std::fill(std::begin(faction_slot_), std::end(faction_slot_), kNoSlot);
}

std::uint32_t NpcAi::slot_of_faction(std::uint8_t faction) {
  if (faction_slot_[faction] == kNoSlot) {
    faction_slot_[faction] = static_cast<std::uint16_t>(slot_faction_.size());
    slot_faction_.push_back(faction);
    rebuild_enemy_slots();
  }
  return faction_slot_[faction];
}

void NpcAi::rebuild_enemy_slots() {
  const std::size_t n = slot_faction_.size();
  enemy_slots_.assign(n, {});
  for (std::size_t s = 0; s < n; ++s) {
    for (std::size_t t = 0; t < n; ++t) {
      if (s != t && slot_faction_[s] != params::kNeutralFaction && slot_faction_[t] != params::kNeutralFaction) {
        enemy_slots_[s].push_back(static_cast<std::uint32_t>(t));
      }
    }
  }
}

std::uint32_t NpcAi::group_index(std::uint8_t faction, std::uint32_t group_id, double x, double y) {
  const auto key = std::make_pair(faction, group_id);
  auto it = group_by_key_.find(key);
  if (it != group_by_key_.end()) return it->second;
  AiGroup g;
  g.faction = faction;
  g.group_id = group_id;
  g.faction_slot = slot_of_faction(faction);
  g.anchor_x = g.centroid_x = x;
  g.anchor_y = g.centroid_y = y;
  const auto index = static_cast<std::uint32_t>(groups_.size());
  groups_.push_back(g);
  group_by_key_.emplace(key, index);
  sum_x_.resize(groups_.size());
  sum_y_.resize(groups_.size());
  return index;
}

void NpcAi::init(const World& world) {
  const std::size_t n = world.body_count();
  const auto xs = world.pos_x();
  const auto ys = world.pos_y();
  ids_.resize(n);
  group_.resize(n);
  fslot_.resize(n);
  slot_x_.resize(n);
  slot_y_.resize(n);
  body_cell_.resize(n);
  ex_.resize(n);
  ey_.resize(n);
  ei_.resize(n);
  target_.assign(n, kNoTarget);
  for (std::size_t i = 0; i < n; ++i) {
    ids_[i] = world.id_at(i);
    const params::ObjectParams& p = world.params(ids_[i]);
    group_[i] = group_index(p.faction, p.group_id, xs[i], ys[i]);
    fslot_[i] = static_cast<std::uint8_t>(groups_[group_[i]].faction_slot);
  }
  // Spawn centroids: the anchors start there and the slots are the offsets from them.
  std::fill(sum_x_.begin(), sum_x_.end(), 0.0);
  std::fill(sum_y_.begin(), sum_y_.end(), 0.0);
  for (AiGroup& g : groups_) g.members = 0;
  for (std::size_t i = 0; i < n; ++i) {
    sum_x_[group_[i]] += xs[i];
    sum_y_[group_[i]] += ys[i];
    ++groups_[group_[i]].members;
  }
  for (std::size_t g = 0; g < groups_.size(); ++g) {
    AiGroup& G = groups_[g];
    if (G.members == 0) continue;
    G.anchor_x = G.centroid_x = sum_x_[g] / G.members;
    G.anchor_y = G.centroid_y = sum_y_[g] / G.members;
  }
  std::size_t slots = 0;
  for (std::size_t i = 0; i < n; ++i) slots = std::max<std::size_t>(slots, std::size_t{ids_[i].index()} + 1);
  spawn_id_.assign(slots, kNoSpawn);
  spawn_slot_x_.assign(slots, 0.0);
  spawn_slot_y_.assign(slots, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    slot_x_[i] = xs[i] - groups_[group_[i]].anchor_x;
    slot_y_[i] = ys[i] - groups_[group_[i]].anchor_y;
    const std::uint32_t k = ids_[i].index();
    spawn_id_[k] = ids_[i].value;
    spawn_slot_x_[k] = slot_x_[i];
    spawn_slot_y_[k] = slot_y_[i];
  }
}

bool NpcAi::align_with(const World& world) {
  const std::size_t n = ids_.size();
  bool same = true;
  for (std::size_t d = 0; d < n && same; ++d) same = world.id_at(d) == ids_[d];
  if (same) return false;
  for (std::size_t d = 0; d < n; ++d) {
    const std::uint32_t slot = ids_[d].index();
    if (old_dense_of_slot_.size() <= slot) old_dense_of_slot_.resize(slot + 1);
    old_dense_of_slot_[slot] = static_cast<std::uint32_t>(d);
  }
  perm_.resize(n);
  for (std::size_t d = 0; d < n; ++d) perm_[d] = old_dense_of_slot_[world.id_at(d).index()];
  apply_reorder(perm_);
  return true;
}

void NpcAi::apply_reorder(std::span<const std::uint32_t> perm) {
  const std::size_t n = perm.size();
  apply_permutation(ids_, perm, scratch_ids_);
  apply_permutation(group_, perm, scratch_u32_);
  apply_permutation(fslot_, perm, scratch_u8_);
  apply_permutation(slot_x_, perm, scratch_f64_);
  apply_permutation(slot_y_, perm, scratch_f64_);
  // Targets are dense indices too: map old -> new, then move them with their bodies.
  scratch_u32_.resize(n);
  for (std::size_t d = 0; d < n; ++d) scratch_u32_[perm[d]] = static_cast<std::uint32_t>(d);  // old -> new
  for (std::uint32_t& t : target_) {
    if (t != kNoTarget) t = scratch_u32_[t];
  }
  apply_permutation(target_, perm, scratch_u32_);
}

void NpcAi::reassign(const World& world, std::size_t i) {
  const params::ObjectParams& p = world.params(ids_[i]);
  const double x = world.pos_x()[i];
  const double y = world.pos_y()[i];
  group_[i] = group_index(p.faction, p.group_id, x, y);
  fslot_[i] = static_cast<std::uint8_t>(groups_[group_[i]].faction_slot);
  slot_x_[i] = x - groups_[group_[i]].anchor_x;
  slot_y_[i] = y - groups_[group_[i]].anchor_y;
  target_[i] = kNoTarget;
}

void NpcAi::compute_centroids(std::span<const double> xs, std::span<const double> ys,
                              std::span<const std::uint32_t> controlled) {
  std::fill(sum_x_.begin(), sum_x_.end(), 0.0);
  std::fill(sum_y_.begin(), sum_y_.end(), 0.0);
  for (AiGroup& g : groups_) g.members = g.npcs = 0;
  const std::size_t n = xs.size();
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t g = group_[i];
    sum_x_[g] += xs[i];
    sum_y_[g] += ys[i];
    ++groups_[g].members;
    groups_[g].npcs += controlled[i] == 0 ? 1u : 0u;
  }
  for (std::size_t g = 0; g < groups_.size(); ++g) {
    AiGroup& G = groups_[g];
    if (G.members == 0) continue;  // keeps its last centroid
    G.centroid_x = sum_x_[g] / G.members;
    G.centroid_y = sum_y_[g] / G.members;
  }
}

// The grid's per-cell arrays at the size of the largest grid (kMaxCells per faction slot), made
// on the first tick and again only if an operator moves a body to a faction the match had not had
// (a new slot): sized to each tick's grid they grew as a battle spread out (routed troops flee
// outwards) and reallocated in the tick for a quarter of an hour, and the server's resident memory
// grew with them. Written whole here, so their pages are the process's from the first tick.
void NpcAi::size_grid_for_max_cells() {
  const auto cells = static_cast<std::size_t>(kMaxCells);
  const std::size_t per_slot = slot_faction_.size() * cells;
  if (start_.size() >= per_slot + 1) return;
  start_.assign(per_slot + 1, 0u);
  cursor_.assign(per_slot, 0u);
  window_.assign(cells, 0u);
  near_.assign(per_slot, 0);
  enemy_near_.assign(per_slot, 0);
}

void NpcAi::build_grid(std::span<const double> xs, std::span<const double> ys) {
  const std::size_t n = xs.size();
  double min_x = std::numeric_limits<double>::infinity(), min_y = min_x;
  double max_x = -min_x, max_y = -min_x;
  for (std::size_t i = 0; i < n; ++i) {
    min_x = std::min(min_x, xs[i]);
    max_x = std::max(max_x, xs[i]);
    min_y = std::min(min_y, ys[i]);
    max_y = std::max(max_y, ys[i]);
  }
  if (n == 0) min_x = max_x = min_y = max_y = 0.0;
  double cell = settings_.cell_m;
  double cx = std::floor((max_x - min_x) / cell) + 1.0;
  double cy = std::floor((max_y - min_y) / cell) + 1.0;
  while (cx * cy > kMaxCells) {
    cell *= 2.0;
    cx = std::floor((max_x - min_x) / cell) + 1.0;
    cy = std::floor((max_y - min_y) / cell) + 1.0;
  }
  min_x_ = min_x;
  min_y_ = min_y;
  cell_m_ = cell;
  inv_cell_ = 1.0 / cell;
  nx_ = static_cast<std::uint32_t>(cx);
  ny_ = static_cast<std::uint32_t>(cy);
  ncells_ = nx_ * ny_;
  rings_ = static_cast<std::uint32_t>(std::ceil(settings_.engage_radius_m / cell));
  const std::size_t total = slot_faction_.size() * ncells_;
  size_grid_for_max_cells();
  std::fill(start_.begin(), start_.begin() + static_cast<std::ptrdiff_t>(total + 1), 0u);
  for (std::size_t i = 0; i < n; ++i) {
    const auto ix = std::min(nx_ - 1, static_cast<std::uint32_t>((xs[i] - min_x) * inv_cell_));
    const auto iy = std::min(ny_ - 1, static_cast<std::uint32_t>((ys[i] - min_y) * inv_cell_));
    const std::uint32_t c = iy * nx_ + ix;
    body_cell_[i] = c;
    ++start_[fslot_[i] * ncells_ + c + 1];
  }
  for (std::size_t k = 0; k < total; ++k) start_[k + 1] += start_[k];
  std::copy(start_.begin(), start_.begin() + static_cast<std::ptrdiff_t>(total), cursor_.begin());
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t pos = cursor_[fslot_[i] * ncells_ + body_cell_[i]]++;
    ex_[pos] = xs[i];
    ey_[pos] = ys[i];
    ei_[pos] = static_cast<std::uint32_t>(i);
  }
}

void NpcAi::dilate() {
  const std::size_t nslots = slot_faction_.size();
  const std::uint32_t nx = nx_, ny = ny_, r = rings_;
  for (std::size_t s = 0; s < nslots; ++s) {
    const std::uint32_t* st = start_.data() + s * ncells_;
    // Rows: how many occupied cells within r columns.
    for (std::uint32_t y = 0; y < ny; ++y) {
      const std::uint32_t row = y * nx;
      auto occ = [&](std::uint32_t x) -> std::uint32_t { return st[row + x + 1] > st[row + x] ? 1u : 0u; };
      std::uint32_t run = 0;
      for (std::uint32_t x = 0; x <= std::min(r, nx - 1); ++x) run += occ(x);
      for (std::uint32_t x = 0; x < nx; ++x) {
        window_[row + x] = run;
        if (x + r + 1 < nx) run += occ(x + r + 1);
        if (x >= r) run -= occ(x - r);
      }
    }
    // Columns over the row result.
    std::uint8_t* out = near_.data() + s * ncells_;
    for (std::uint32_t x = 0; x < nx; ++x) {
      auto w = [&](std::uint32_t y) -> std::uint32_t { return window_[y * nx + x] > 0 ? 1u : 0u; };
      std::uint32_t run = 0;
      for (std::uint32_t y = 0; y <= std::min(r, ny - 1); ++y) run += w(y);
      for (std::uint32_t y = 0; y < ny; ++y) {
        out[y * nx + x] = run > 0 ? 1 : 0;
        if (y + r + 1 < ny) run += w(y + r + 1);
        if (y >= r) run -= w(y - r);
      }
    }
  }
  std::fill(enemy_near_.begin(), enemy_near_.begin() + static_cast<std::ptrdiff_t>(nslots * ncells_), std::uint8_t{0});
  for (std::size_t s = 0; s < nslots; ++s) {
    std::uint8_t* out = enemy_near_.data() + s * ncells_;
    for (std::uint32_t t : enemy_slots_[s]) {
      const std::uint8_t* in = near_.data() + t * ncells_;
      for (std::uint32_t c = 0; c < ncells_; ++c) out[c] |= in[c];
    }
  }
}

std::uint32_t NpcAi::count_near(double x, double y, double r, std::uint32_t slot) const {
  const auto clampi = [](double v, std::uint32_t n) {
    if (!(v > 0.0)) return 0u;
    return std::min(n - 1, static_cast<std::uint32_t>(v));
  };
  const std::uint32_t x0 = clampi((x - r - min_x_) * inv_cell_, nx_);
  const std::uint32_t x1 = clampi((x + r - min_x_) * inv_cell_, nx_);
  const std::uint32_t y0 = clampi((y - r - min_y_) * inv_cell_, ny_);
  const std::uint32_t y1 = clampi((y + r - min_y_) * inv_cell_, ny_);
  const double r2 = r * r;
  std::uint32_t count = 0;
  const std::uint32_t* st = start_.data() + static_cast<std::size_t>(slot) * ncells_;
  for (std::uint32_t cy = y0; cy <= y1; ++cy) {
    for (std::uint32_t cx = x0; cx <= x1; ++cx) {
      const std::uint32_t c = cy * nx_ + cx;
      for (std::uint32_t j = st[c]; j < st[c + 1]; ++j) {
        const double dx = ex_[j] - x;
        const double dy = ey_[j] - y;
        count += dx * dx + dy * dy <= r2 ? 1u : 0u;
      }
    }
  }
  return count;
}

std::uint32_t NpcAi::nearest_enemy(double x, double y, std::uint32_t fslot, std::uint32_t cell) const {
  const std::vector<std::uint32_t>& enemies = enemy_slots_[fslot];
  const auto cx = static_cast<std::int64_t>(cell % nx_);
  const auto cy = static_cast<std::int64_t>(cell / nx_);
  const double r_max2 = settings_.engage_radius_m * settings_.engage_radius_m;
  double best = std::numeric_limits<double>::infinity();
  std::uint32_t found = kNoTarget;
  // Distance from the point to its own cell's border: ring r + 1 is at least r cells plus this away.
  const double fx = x - (min_x_ + static_cast<double>(cx) * cell_m_);
  const double fy = y - (min_y_ + static_cast<double>(cy) * cell_m_);
  const double margin = std::max(0.0, std::min(std::min(fx, cell_m_ - fx), std::min(fy, cell_m_ - fy)));
  const auto visit = [&](std::int64_t ix, std::int64_t iy) {
    if (ix < 0 || iy < 0 || ix >= nx_ || iy >= ny_) return;
    const auto c = static_cast<std::uint32_t>(iy * nx_ + ix);
    for (std::uint32_t t : enemies) {
      const std::uint32_t* st = start_.data() + static_cast<std::size_t>(t) * ncells_;
      for (std::uint32_t j = st[c]; j < st[c + 1]; ++j) {
        const double dx = ex_[j] - x;
        const double dy = ey_[j] - y;
        const double d2 = dx * dx + dy * dy;
        if (d2 < best) {
          best = d2;
          found = ei_[j];
        }
      }
    }
  };
  for (std::int64_t r = 0; r <= static_cast<std::int64_t>(rings_); ++r) {
    if (r == 0) {
      visit(cx, cy);
    } else {
      for (std::int64_t ix = cx - r; ix <= cx + r; ++ix) {
        visit(ix, cy - r);
        visit(ix, cy + r);
      }
      for (std::int64_t iy = cy - r + 1; iy <= cy + r - 1; ++iy) {
        visit(cx - r, iy);
        visit(cx + r, iy);
      }
    }
    const double reach = static_cast<double>(r) * cell_m_ + margin;
    if (best <= reach * reach) break;
  }
  return best <= r_max2 ? found : kNoTarget;
}

std::optional<std::uint8_t> routed_faction(std::span<const AiGroup> groups) {
  // Per faction: any group with NPCs, and any such group that still holds.
  std::array<bool, 256> fielded{}, holding{};
  for (const AiGroup& g : groups) {
    if (g.npcs == 0 || g.faction == params::kNeutralFaction) continue;
    fielded[g.faction] = true;
    if (!g.retreating) holding[g.faction] = true;
  }
  for (std::size_t f = 1; f < fielded.size(); ++f)
    if (fielded[f] && !holding[f]) return static_cast<std::uint8_t>(f);
  return std::nullopt;
}

void NpcAi::update_groups(const World& world) {
  const params::GroupTable& table = world.groups();
  const params::MoraleConfig& morale_cfg = table.morale_config();
  const bool engine_morale = world.policy().uses_morale();
  const double step = settings_.speed_mps * settings_.dt_s;
  const std::size_t ng = groups_.size();
  for (std::size_t g = 0; g < ng; ++g) {
    AiGroup& G = groups_[g];
    G.target_group = -1;
    G.retreating = false;
    if (G.members == 0) continue;
    // Nearest enemy formation by centroid (ties: lower index).
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t h = 0; h < ng; ++h) {
      const AiGroup& H = groups_[h];
      if (H.members == 0 || H.faction == G.faction || H.faction == params::kNeutralFaction ||
          G.faction == params::kNeutralFaction) {
        continue;
      }
      const double dx = H.centroid_x - G.centroid_x;
      const double dy = H.centroid_y - G.centroid_y;
      const double d2 = dx * dx + dy * dy;
      if (d2 < best) {
        best = d2;
        G.target_group = static_cast<std::int32_t>(h);
      }
    }
    if (G.npcs == 0) continue;
    // Morale.
    G.allies_near = count_near(G.centroid_x, G.centroid_y, settings_.morale_radius_m, G.faction_slot);
    G.enemies_near = 0;
    for (std::uint32_t t : enemy_slots_[G.faction_slot]) {
      G.enemies_near += count_near(G.centroid_x, G.centroid_y, settings_.morale_radius_m, t);
    }
    G.own_morale = params::update_morale(G.own_morale, G.allies_near, G.enemies_near, morale_cfg);
    const params::Group* known = G.group_id != 0 ? table.find(G.group_id) : nullptr;
    if (engine_morale && known != nullptr) {
      G.morale = table.morale(G.group_id);
    } else {
      G.morale = (known != nullptr ? known->base_morale : 0.0) + morale_cfg.offset(G.own_morale);
    }
    if (G.target_group < 0) continue;
    G.retreating = G.morale < settings_.retreat_below_morale;
    // Anchor: towards (or away from) the enemy formation, waiting for the group to keep up.
    const AiGroup& T = groups_[static_cast<std::size_t>(G.target_group)];
    const double lx = G.anchor_x - G.centroid_x;
    const double ly = G.anchor_y - G.centroid_y;
    if (lx * lx + ly * ly >= settings_.anchor_leash_m * settings_.anchor_leash_m) continue;
    const double dx = T.centroid_x - G.anchor_x;
    const double dy = T.centroid_y - G.anchor_y;
    const double d = std::sqrt(dx * dx + dy * dy);
    if (!(d > 1e-9)) continue;
    const double move = G.retreating ? -step : std::min(step, d);
    G.anchor_x += dx / d * move;
    G.anchor_y += dy / d * move;
  }
}

std::uint32_t NpcAi::update(World& world, std::span<const std::uint32_t> controlled, std::span<float> yaw) {
  const auto xs = world.pos_x();
  const auto ys = world.pos_y();
  const std::size_t n = xs.size();
  compute_centroids(xs, ys, controlled);
  build_grid(xs, ys);
  dilate();
  update_groups(world);

  const double speed = settings_.speed_mps;
  const double gain = settings_.arrive_gain_per_s;
  const double tol = settings_.arrive_tolerance_m;
  const double engage2 = settings_.engage_radius_m * settings_.engage_radius_m;
  const double still2 = 0.05 * 0.05;
  const auto phase = static_cast<std::uint32_t>(ticks_ % kTargetRefreshTicks);
  ++ticks_;
  std::uint32_t engaged = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (controlled[i] != 0) {
      target_[i] = kNoTarget;
      continue;
    }
    const AiGroup& G = groups_[group_[i]];
    const double x = xs[i];
    const double y = ys[i];
    // Choose (every kTargetRefreshTicks ticks) or keep following the nearest enemy.
    std::uint32_t t = kNoTarget;
    if (!G.retreating) {
      const std::size_t near_cell = static_cast<std::size_t>(fslot_[i]) * ncells_ + body_cell_[i];
      if ((static_cast<std::uint32_t>(i) + phase) % kTargetRefreshTicks == 0) {
        if (enemy_near_[near_cell] != 0) t = nearest_enemy(x, y, fslot_[i], body_cell_[i]);
      } else {
        t = target_[i];
        if (t != kNoTarget) {
          const double dx = xs[t] - x;
          const double dy = ys[t] - y;
          if (dx * dx + dy * dy > engage2) t = kNoTarget;
        }
      }
    }
    target_[i] = t;
    double vx = 0.0, vy = 0.0;
    if (t != kNoTarget) {
      const double dx = xs[t] - x;
      const double dy = ys[t] - y;
      const double d = std::sqrt(dx * dx + dy * dy);
      if (d > 1e-6) {
        vx = dx / d * speed;
        vy = dy / d * speed;
      }
      ++engaged;
    } else {
      const double dx = G.anchor_x + slot_x_[i] - x;
      const double dy = G.anchor_y + slot_y_[i] - y;
      const double d = std::sqrt(dx * dx + dy * dy);
      if (d > tol) {
        const double s = std::min(speed, gain * d);
        vx = dx / d * s;
        vy = dy / d * s;
      }
    }
    world.set_desired_velocity(ids_[i], Vec3{vx, vy, 0.0});
    if (vx * vx + vy * vy > still2) yaw[i] = fast_atan2(vy, vx);
  }
  return engaged;
}

}  // namespace throng::match
