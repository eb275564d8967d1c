// The contact-pairs debug channel (match.h, contacts.h): which clients are served, and one
// ContactPairs per served client after the step. Reads the world, never writes it, so the state
// hash does not depend on who watches (tests/match/match_contacts_test.cpp).
//
// Grants are first come: a client's applied command with kActionContacts takes a free place (of
// config.contacts.max_clients) or is refused and counted; a command without the bit gives the
// place back, and so does leaving. The phase costs nothing while nobody is served; otherwise one
// pass over the tick's push events plus one per served client, without allocation once warm.
#include <algorithm>

#include "match_impl.h"
#include "throng/world/world.h"

namespace throng::match {

void Match::Impl::note_contacts_request(const ClientRecord& c, bool wants) {
  const auto it = std::lower_bound(contacts_granted.begin(), contacts_granted.end(), c.id);
  const bool granted = it != contacts_granted.end() && *it == c.id;
  if (wants == granted) return;
  if (!wants) {
    contacts_granted.erase(it);
  } else if (contacts_granted.size() < config.contacts.max_clients) {
    contacts_granted.insert(it, c.id);  // capacity reserved: no allocation
  } else {
    ++contacts_refused;
    ++report.contacts_refused;
  }
}

void Match::Impl::build_contacts(std::uint64_t tick, Outbox& out) {
  // Clients that left or timed out this tick give their place back.
  std::erase_if(contacts_granted, [this](std::uint32_t id) { return clients.find_connected(id) == nullptr; });
  out.contacts_count = 0;
  if (contacts_granted.empty()) return;
  contact_selector.prepare(world());
  double radius = config.contacts.radius_m;
  if (config.interest.radius_m > 0.0) radius = std::min(radius, config.interest.radius_m);
  if (out.contacts.size() < contacts_granted.size()) out.contacts.resize(contacts_granted.size());
  for (std::size_t k = 0; k < contacts_granted.size(); ++k) {
    const ClientRecord& c = *clients.find(contacts_granted[k]);
    protocol::ContactPairs& cp = out.contacts[k];
    cp.client_id = c.id;
    cp.tick = tick;
    const Vec3 cam = camera_of(c);
    contact_selector.select(cam.x, cam.y, radius, config.contacts.max_pairs, cp);
    report.contact_pairs += static_cast<std::uint32_t>(cp.a.size());
  }
  out.contacts_count = contacts_granted.size();
}

std::span<const std::uint32_t> Match::contacts_clients() const { return impl_->contacts_granted; }
std::uint64_t Match::contacts_refused_total() const { return impl_->contacts_refused; }

std::optional<float> Match::facing_rad(ObjectId id) const {
  const std::uint32_t d = impl_->dense_of(id);
  if (d == kNoDense) return std::nullopt;
  return impl_->yaw[d];
}

}  // namespace throng::match
