#pragma once
// What a bot needs from MatchInfo, indexed once per MatchInfo sample and shared (read-only) by
// every bot of a fleet: the roster by object id (faction, size), the tick rate, the world bounds.
#include <cstdint>
#include <string>
#include <unordered_map>
#include <vector>

#include "throng/protocol/messages.h"

namespace throng::client_sim {

struct RosterEntry {
  std::uint32_t id = 0;
  std::uint16_t radius_mm = 0;
  std::uint16_t half_height_mm = 0;
  std::uint8_t faction = 0;
  std::uint8_t character_type = 0;
};

class MatchView {
 public:
  // Roster arrays of unequal length are cut to the shortest (a malformed MatchInfo never throws).
  explicit MatchView(const protocol::MatchInfo& info);

  const RosterEntry* find(std::uint32_t id) const;
  const std::vector<std::uint32_t>& ids() const { return ids_; }  // ascending
  std::uint32_t tick_hz() const { return tick_hz_; }              // never 0
  const std::string& match_id() const { return match_id_; }
  const std::string& scene_name() const { return scene_name_; }
  bool ended() const { return ended_; }
  bool has_bounds() const { return max_x_ > min_x_ && max_y_ > min_y_; }
  float min_x() const { return min_x_; }
  float min_y() const { return min_y_; }
  float max_x() const { return max_x_; }
  float max_y() const { return max_y_; }

 private:
  std::unordered_map<std::uint32_t, RosterEntry> by_id_;
  std::vector<std::uint32_t> ids_;
  std::uint32_t tick_hz_ = 30;
  std::string match_id_, scene_name_;
  bool ended_ = false;
  float min_x_ = 0, min_y_ = 0, max_x_ = 0, max_y_ = 0;
};

}  // namespace throng::client_sim
