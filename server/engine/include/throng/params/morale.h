#pragma once
// Group morale as a dynamic parameter (the patent: "if the number of enemy characters is greater
// than the number of friendly characters in a specific area ... the morale parameter can change").
//
// The engine counts allies and enemies near a group; update_morale turns that into one of three
// levels. Why levels with hysteresis instead of using the ally fraction directly: the fraction
// jitters every tick as bodies walk in and out of range, and a push share that follows it would
// make the crowd visibly shiver — exactly the alternating push the patent warns about for the
// priority baseline. Two thresholds per boundary (enter / exit) give a dead band that absorbs the
// jitter.
#include <cstdint>
#include <optional>
#include <string_view>

namespace throng::params {

enum class MoraleState : std::uint8_t { low = 0, normal = 1, high = 2 };

std::string_view morale_state_name(MoraleState s);
std::optional<MoraleState> parse_morale_state(std::string_view name);

struct MoraleConfig {
  // Thresholds on the ally fraction f = allies / (allies + enemies), all in [0, 1].
  // Required order: low_enter < low_exit <= high_exit < high_enter.
  double low_enter = 0.35;   // normal/high -> low when f < low_enter
  double low_exit = 0.45;    // low -> normal when f > low_exit
  double high_exit = 0.55;   // high -> normal when f < high_exit
  double high_enter = 0.65;  // normal/low -> high when f > high_enter
  // Added to the group's base morale to give the morale value the push policy reads.
  double low_offset = -20.0;   // [-100, 100]
  double high_offset = 20.0;   // [-100, 100]
  // With fewer bodies than this nearby the sample is too small to judge: the level is kept.
  std::uint32_t min_nearby = 1;

  // Throws ConfigError with path "morale.<field>".
  void validate() const;
  double offset(MoraleState s) const {
    return s == MoraleState::low ? low_offset : (s == MoraleState::high ? high_offset : 0.0);
  }
};

// Next morale level. Pure and deterministic; comparisons are strict so a fraction sitting exactly
// on a threshold does not move the level.
MoraleState update_morale(MoraleState current, std::uint32_t allies_near, std::uint32_t enemies_near,
                          const MoraleConfig& config);

}  // namespace throng::params
