// ContactSelector (contacts.h): body-body push events near a camera, nearest first.
#include "throng/match/contacts.h"

#include <algorithm>

#include "throng/protocol/contacts.h"
#include "throng/world/world.h"

namespace throng::match {

void ContactSelector::prepare(const World& world) {
  pairs_.clear();
  for (const PushEvent& e : world.push_events()) {
    if (!world.is_body(e.a) || !world.is_body(e.b)) continue;  // scenery contact
    const Vec3 pa = world.position(e.a);
    const Vec3 pb = world.position(e.b);
    pairs_.push_back(Pair{0.5 * (pa.x + pb.x), 0.5 * (pa.y + pb.y), e.a.value, e.b.value, e.share_a, e.depth_m, e.push_m});
  }
}

void ContactSelector::select(double cx, double cy, double radius_m, std::uint32_t max_pairs, protocol::ContactPairs& out) {
  out.pairs_near = 0;
  out.camera_x = static_cast<float>(cx);
  out.camera_y = static_cast<float>(cy);
  out.radius_m = static_cast<float>(radius_m);
  out.a.clear();
  out.b.clear();
  out.share_a.clear();
  out.depth.clear();
  out.push.clear();
  near_.clear();
  if (!(radius_m > 0.0)) return;
  const double r2 = radius_m * radius_m;
  for (std::uint32_t i = 0; i < pairs_.size(); ++i) {
    const double dx = pairs_[i].mx - cx, dy = pairs_[i].my - cy;
    const double d2 = dx * dx + dy * dy;
    if (d2 <= r2) near_.push_back(Near{d2, i});
  }
  out.pairs_near = static_cast<std::uint32_t>(near_.size());
  const auto before = [this](const Near& l, const Near& r) {
    if (l.d2 != r.d2) return l.d2 < r.d2;
    const Pair& p = pairs_[l.pair];
    const Pair& q = pairs_[r.pair];
    return p.a != q.a ? p.a < q.a : p.b < q.b;
  };
  const std::size_t n = std::min<std::size_t>(max_pairs, near_.size());
  std::partial_sort(near_.begin(), near_.begin() + static_cast<std::ptrdiff_t>(n), near_.end(), before);
  for (std::size_t k = 0; k < n; ++k) {
    const Pair& p = pairs_[near_[k].pair];
    protocol::push_contact(out, p.a, p.b, p.share_a, p.depth_m, p.push_m);
  }
}

}  // namespace throng::match
