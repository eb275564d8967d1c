#include "throng/client_sim/match_view.h"

#include <algorithm>

namespace throng::client_sim {

MatchView::MatchView(const protocol::MatchInfo& info)
    : tick_hz_(info.tick_hz == 0 ? 30 : info.tick_hz),
      match_id_(info.match_id),
      scene_name_(info.scene_name),
      ended_(info.state == protocol::MatchState::ended),
      min_x_(info.world_min_x),
      min_y_(info.world_min_y),
      max_x_(info.world_max_x),
      max_y_(info.world_max_y) {
  const auto& r = info.roster;
  const std::size_t n = std::min({r.id.size(), r.radius_mm.size(), r.half_height_mm.size(), r.faction.size(),
                                  r.character_type.size()});
  by_id_.reserve(n);
  ids_.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    by_id_[r.id[i]] = RosterEntry{r.id[i], r.radius_mm[i], r.half_height_mm[i], r.faction[i], r.character_type[i]};
    ids_.push_back(r.id[i]);
  }
  std::sort(ids_.begin(), ids_.end());
  ids_.erase(std::unique(ids_.begin(), ids_.end()), ids_.end());
}

const RosterEntry* MatchView::find(std::uint32_t id) const {
  auto it = by_id_.find(id);
  return it == by_id_.end() ? nullptr : &it->second;
}

}  // namespace throng::client_sim
