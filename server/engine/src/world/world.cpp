// World's public API: object lifetime, inputs and read access. The tick itself is in world_step.cpp.
#include "throng/world/world.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include "world/body_limits.h"
#include "world/world_impl.h"

namespace throng {
namespace {

void require_finite(const Vec3& v, const char* what) {
  if (!is_finite(v)) throw std::invalid_argument(std::string(what) + ": coordinates must be finite (got NaN or Inf)");
}
void require_range(double v, double lo, double hi, const char* what) {
  if (!std::isfinite(v) || v < lo || v > hi) {
    throw std::invalid_argument(std::string(what) + ": " + std::to_string(v) + " is outside [" + std::to_string(lo) +
                                ", " + std::to_string(hi) + "]");
  }
}
std::string id_text(ObjectId id) { return "object id " + std::to_string(id.value); }

}  // namespace

ObjectId World::Impl::allocate_slot(SlotKind kind, std::uint32_t ref) {
  std::uint32_t index;
  if (!free_slots.empty()) {
    index = free_slots.back();
    free_slots.pop_back();
  } else {
    if (slots.size() > ObjectId::kMaxIndex) throw std::length_error("world is full: no free object ids");
    index = static_cast<std::uint32_t>(slots.size());
    slots.emplace_back();
  }
  Slot& s = slots[index];
  s.kind = kind;
  s.ref = ref;
  // Generation 0 is skipped so that no live id ever equals a freshly zeroed value.
  if (s.generation == 0) s.generation = 1;
  return ObjectId::make(index, s.generation);
}

const World::Impl::Slot* World::Impl::find(ObjectId id) const {
  if (!id.valid()) return nullptr;
  const std::uint32_t index = id.index();
  if (index >= slots.size()) return nullptr;
  const Slot& s = slots[index];
  if (s.kind == SlotKind::kFree || (s.generation & ObjectId::kGenerationMask) != id.generation()) return nullptr;
  return &s;
}

std::uint32_t World::Impl::body_index(ObjectId id, const char* what) const {
  const Slot* s = find(id);
  if (s == nullptr || s->kind != SlotKind::kBody) throw std::invalid_argument(std::string(what) + ": unknown " + id_text(id));
  return s->ref;
}

World::World(const WorldSettings& settings, const params::ParamTable& table, const params::PushPolicy& policy) {
  settings.validate();
  impl_ = std::make_unique<Impl>(settings, table, policy);
  if (settings.threads > 1) impl_->pool = std::make_unique<WorkerPool>(settings.threads);
}
World::~World() = default;
World::World(World&&) noexcept = default;
World& World::operator=(World&&) noexcept = default;

ObjectId World::Impl::add_fixed(std::uint32_t shape_index, const std::string& archetype) {
  const ObjectId id = allocate_slot(SlotKind::kFixed, shape_index);
  params::ObjectParams p = table.resolve(archetype, id.value, 0);
  p.fixed = true;
  if (fixed_ids.size() <= shape_index) { fixed_ids.resize(shape_index + 1); fixed_params.resize(shape_index + 1); }
  fixed_ids[shape_index] = id;
  fixed_params[shape_index] = p;
  scenery_dirty = true;
  return id;
}

ObjectId World::add_fixed_box(Vec3 centre, Vec3 half_extents_m, double yaw_rad, const std::string& archetype) {
  (void)impl_->table.resolve(archetype, 0, 0);  // unknown archetype: throw before changing anything
  return impl_->add_fixed(impl_->scenery.add_box(centre, half_extents_m, yaw_rad), archetype);
}
ObjectId World::add_fixed_cylinder(Vec3 centre, double radius_m, double half_height_m, const std::string& archetype) {
  (void)impl_->table.resolve(archetype, 0, 0);
  return impl_->add_fixed(impl_->scenery.add_cylinder(centre, radius_m, half_height_m), archetype);
}
ObjectId World::add_fixed_mesh(std::vector<Vec3> vertices, std::vector<std::array<std::uint32_t, 3>> triangles,
                               const std::string& archetype) {
  (void)impl_->table.resolve(archetype, 0, 0);
  return impl_->add_fixed(impl_->scenery.add_mesh(std::move(vertices), std::move(triangles)), archetype);
}

ObjectId World::create_body(const BodyDef& def) {
  require_finite(def.position, "create_body.position");
  require_range(def.radius_m, detail::kMinBodyRadiusM, detail::kMaxBodyRadiusM, "create_body.radius_m");
  require_range(def.half_height_m, 0.0, detail::kMaxBodyHalfHeightM, "create_body.half_height_m");
  Impl& w = *impl_;
  const auto dense = static_cast<std::uint32_t>(w.bodies.size());
  w.last_reorder.clear();  // the order changes at the caller's request (see World::last_reorder)
  // Resolve parameters first so that an unknown archetype leaves the world untouched.
  (void)w.table.resolve(def.archetype, 0, def.collision_id);
  const ObjectId id = w.allocate_slot(Impl::SlotKind::kBody, dense);
  params::ObjectParams p = w.table.resolve(def.archetype, id.value, def.collision_id);
  p.fixed = false;
  w.bodies.push_back_default();
  w.cell0_dirty = true;
  w.list.drop();
  w.bodies.x[dense] = def.position.x;
  w.bodies.y[dense] = def.position.y;
  w.bodies.z[dense] = def.position.z;
  w.bodies.r[dense] = def.radius_m;
  w.bodies.hh[dense] = def.half_height_m;
  w.bodies.grounded[dense] = def.grounded ? 1 : 0;
  w.bodies.id[dense] = id;
  w.bodies.coeff_dirty[dense] = 1;
  w.settle_params();
  w.body_params.push_back(p);
  w.max_body_reach_m = std::max(w.max_body_reach_m, def.radius_m + w.settings.contact_margin_m);
  return id;
}

void World::destroy_body(ObjectId id) {
  Impl& w = *impl_;
  const std::uint32_t dense = w.body_index(id, "destroy_body");
  w.last_reorder.clear();
  const std::size_t last = w.bodies.size() - 1;
  w.settle_params();
  if (dense != last) {
    const ObjectId moved = w.bodies.id[last];
    w.slots[moved.index()].ref = dense;
    w.body_params[dense] = w.body_params[last];
  }
  w.bodies.swap_remove(dense);
  w.cell0_dirty = true;
  w.list.drop();
  w.body_params.pop_back();
  Impl::Slot& s = w.slots[id.index()];
  s.kind = Impl::SlotKind::kFree;
  s.generation = (s.generation + 1) & ObjectId::kGenerationMask;
  w.free_slots.push_back(id.index());
}

bool World::is_body(ObjectId id) const {
  const Impl::Slot* s = impl_->find(id);
  return s != nullptr && s->kind == Impl::SlotKind::kBody;
}
bool World::is_fixed(ObjectId id) const {
  const Impl::Slot* s = impl_->find(id);
  return s != nullptr && s->kind == Impl::SlotKind::kFixed;
}

void World::set_desired_velocity(ObjectId id, Vec3 v) {
  require_finite(v, "set_desired_velocity");
  if (length(v) > detail::kMaxDesiredSpeedMps) throw std::invalid_argument("set_desired_velocity: speed above 1000 m/s");
  const std::uint32_t i = impl_->body_index(id, "set_desired_velocity");
  impl_->bodies.vx[i] = v.x;
  impl_->bodies.vy[i] = v.y;
  impl_->bodies.vz[i] = v.z;
}

void World::set_position(ObjectId id, Vec3 p) {
  require_finite(p, "set_position");
  const std::uint32_t i = impl_->body_index(id, "set_position");
  impl_->bodies.x[i] = p.x;
  impl_->bodies.y[i] = p.y;
  impl_->bodies.z[i] = p.z;
  impl_->bodies.warm_count[i] = 0;  // a teleport invalidates last tick's pushes
  impl_->list.drop();                 // and the kept pair list
}

void World::set_grounded(ObjectId id, bool grounded) {
  std::uint8_t& flag = impl_->bodies.grounded[impl_->body_index(id, "set_grounded")];
  // The kept pair list's separation targets assume every body stays as grounded as it was.
  if (flag != (grounded ? 1 : 0)) impl_->list.drop();
  flag = grounded ? 1 : 0;
}

void World::set_param(ObjectId id, params::Param param, double value) {
  Impl& w = *impl_;
  const Impl::Slot* s = w.find(id);
  if (s == nullptr) throw std::invalid_argument("set_param: unknown " + id_text(id));
  if (s->kind == Impl::SlotKind::kFixed) {
    params::ObjectParams copy = w.fixed_params[s->ref];
    copy.set(param, value);  // validates, throws naming the field
    w.fixed_params[s->ref] = copy;
    return;
  }
  params::ObjectParams copy = w.params_of(s->ref);
  copy.set(param, value);
  w.params_of(s->ref) = copy;
  w.bodies.coeff_dirty[s->ref] = 1;
}

void World::set_policy(const params::PushPolicy& policy) {
  impl_->policy = policy;
  ++impl_->policy_version;
  impl_->all_coefficients_dirty = true;
}

void World::set_group_base_morale(std::uint32_t group_id, double morale) {
  impl_->groups.set_base_morale(group_id, morale);  // validates; throws naming the group
  impl_->all_coefficients_dirty = true;
}

const params::GroupTable& World::groups() const { return impl_->groups; }

void World::set_cameras(std::span<const Vec3> camera_positions) {
  for (const Vec3& c : camera_positions) require_finite(c, "set_cameras");
  impl_->cameras.assign(camera_positions.begin(), camera_positions.end());
}

void World::set_iterations(std::uint32_t iterations) {
  WorldSettings s = impl_->settings;
  s.iterations = iterations;
  s.validate();
  impl_->settings = s;
}

std::uint64_t World::tick() const { return impl_->tick; }
std::size_t World::body_count() const { return impl_->bodies.size(); }
std::span<const double> World::pos_x() const { return impl_->bodies.x; }
std::span<const double> World::pos_y() const { return impl_->bodies.y; }
std::span<const double> World::pos_z() const { return impl_->bodies.z; }
std::span<const double> World::radius() const { return impl_->bodies.r; }
std::span<const double> World::half_height() const { return impl_->bodies.hh; }
ObjectId World::id_at(std::size_t dense_index) const { return impl_->bodies.id.at(dense_index); }
std::optional<std::size_t> World::dense_index(ObjectId id) const {
  const Impl::Slot* s = impl_->find(id);
  if (s == nullptr || s->kind != Impl::SlotKind::kBody) return std::nullopt;
  return s->ref;
}
std::span<const std::uint32_t> World::last_reorder() const { return impl_->last_reorder; }
Vec3 World::position(ObjectId id) const {
  const std::uint32_t i = impl_->body_index(id, "position");
  return {impl_->bodies.x[i], impl_->bodies.y[i], impl_->bodies.z[i]};
}
Vec3 World::velocity(ObjectId id) const {
  const std::uint32_t i = impl_->body_index(id, "velocity");
  return {impl_->bodies.ax[i], impl_->bodies.ay[i], impl_->bodies.az[i]};
}
const params::ObjectParams& World::params(ObjectId id) const {
  const Impl::Slot* s = impl_->find(id);
  if (s == nullptr) throw std::invalid_argument("params: unknown " + id_text(id));
  return s->kind == Impl::SlotKind::kFixed ? impl_->fixed_params[s->ref] : impl_->params_of(s->ref);
}
const params::PushPolicy& World::policy() const { return impl_->policy; }
const WorldSettings& World::settings() const { return impl_->settings; }
std::span<const PushEvent> World::push_events() const { return {impl_->events.data(), impl_->event_count}; }

void World::set_push_events_recorded(bool on) {
  impl_->push_events_off = !on;
  if (!on) impl_->event_count = 0;
}

}  // namespace throng
