#include "throng/params/morale.h"

#include <gtest/gtest.h>

#include <cmath>

#include "params_test_util.h"
#include "throng/params/group_table.h"

namespace throng::params {
namespace {

constexpr std::uint32_t kNearby = 1000;

// Ally count out of kNearby whose fraction lies `offset` (in units of 1/kNearby) past threshold t.
std::uint32_t allies_at(double t, int offset) {
  return static_cast<std::uint32_t>(static_cast<int>(std::lround(t * kNearby)) + offset);
}

MoraleState step(MoraleState s, std::uint32_t allies, const MoraleConfig& c) {
  return update_morale(s, allies, kNearby - allies, c);
}

TEST(ParamsMorale, ChangesLevelWhenCrossingThresholds) {
  const MoraleConfig c;
  EXPECT_EQ(step(MoraleState::normal, allies_at(c.low_enter, -1), c), MoraleState::low);
  EXPECT_EQ(step(MoraleState::low, allies_at(c.low_exit, +1), c), MoraleState::normal);
  EXPECT_EQ(step(MoraleState::normal, allies_at(c.high_enter, +1), c), MoraleState::high);
  EXPECT_EQ(step(MoraleState::high, allies_at(c.high_exit, -1), c), MoraleState::normal);
  // Big swings jump straight across.
  EXPECT_EQ(step(MoraleState::low, allies_at(c.high_enter, +1), c), MoraleState::high);
  EXPECT_EQ(step(MoraleState::high, allies_at(c.low_enter, -1), c), MoraleState::low);
  // Exactly on a threshold does not move.
  EXPECT_EQ(step(MoraleState::normal, allies_at(c.low_enter, 0), c), MoraleState::normal);
}

TEST(ParamsMorale, DoesNotFlickerInsideTheDeadBand) {
  const MoraleConfig c;
  // Oscillate between just above low_enter and just below low_exit for many ticks.
  const std::uint32_t lo = allies_at(c.low_enter, +1);
  const std::uint32_t hi = allies_at(c.low_exit, -1);
  for (MoraleState start : {MoraleState::low, MoraleState::normal}) {
    MoraleState s = start;
    for (int tick = 0; tick < 500; ++tick) {
      s = step(s, tick % 2 == 0 ? lo : hi, c);
      ASSERT_EQ(s, start) << "tick " << tick;
    }
  }
  // Same on the high side.
  const std::uint32_t hlo = allies_at(c.high_exit, +1);
  const std::uint32_t hhi = allies_at(c.high_enter, -1);
  for (MoraleState start : {MoraleState::normal, MoraleState::high}) {
    MoraleState s = start;
    for (int tick = 0; tick < 500; ++tick) {
      s = step(s, tick % 2 == 0 ? hlo : hhi, c);
      ASSERT_EQ(s, start) << "tick " << tick;
    }
  }
}

TEST(ParamsMorale, OscillationAcrossBothThresholdsDoesChange) {
  const MoraleConfig c;
  const std::uint32_t below = allies_at(c.low_enter, -1);
  const std::uint32_t above = allies_at(c.low_exit, +1);
  MoraleState s = MoraleState::normal;
  int changes = 0;
  for (int tick = 0; tick < 10; ++tick) {
    const MoraleState next = step(s, tick % 2 == 0 ? below : above, c);
    changes += next != s ? 1 : 0;
    s = next;
  }
  EXPECT_EQ(changes, 10);
}

TEST(ParamsMorale, TooFewNearbyKeepsTheLevel) {
  MoraleConfig c;
  c.min_nearby = 5;
  EXPECT_EQ(update_morale(MoraleState::high, 0, 4, c), MoraleState::high);
  EXPECT_EQ(update_morale(MoraleState::high, 0, 5, c), MoraleState::low);
  EXPECT_EQ(update_morale(MoraleState::normal, 0, 0, MoraleConfig{}), MoraleState::normal);
}

TEST(ParamsMorale, ConfigValidationNamesTheField) {
  using test::config_error_of;
  MoraleConfig c;
  c.low_exit = c.low_enter;
  EXPECT_EQ(config_error_of([&] { c.validate(); }).path(), "morale.low_exit");
  c = MoraleConfig{};
  c.high_exit = c.low_exit - 0.01;
  EXPECT_EQ(config_error_of([&] { c.validate(); }).path(), "morale.high_exit");
  c = MoraleConfig{};
  c.high_enter = c.high_exit;
  EXPECT_EQ(config_error_of([&] { c.validate(); }).path(), "morale.high_enter");
  c = MoraleConfig{};
  c.low_offset = std::nan("");
  EXPECT_EQ(config_error_of([&] { c.validate(); }).path(), "morale.low_offset");
  c = MoraleConfig{};
  c.high_enter = 1.2;
  EXPECT_EQ(config_error_of([&] { c.validate(); }).path(), "morale.high_enter");
}

TEST(ParamsMorale, GroupMoraleIsBasePlusLevelOffset) {
  GroupTable groups;
  Group g;
  g.base_morale = 7.0;
  groups.set(3, g);
  const MoraleConfig& c = groups.morale_config();
  EXPECT_EQ(groups.morale(3), g.base_morale);
  EXPECT_EQ(groups.update_morale(3, 1, 9), MoraleState::low);
  EXPECT_EQ(groups.morale(3), g.base_morale + c.low_offset);
  EXPECT_EQ(groups.update_morale(3, 9, 1), MoraleState::high);
  EXPECT_EQ(groups.morale(3), g.base_morale + c.high_offset);
  EXPECT_EQ(groups.morale(0), 0.0);   // no group
  EXPECT_EQ(groups.morale(99), 0.0);  // unknown group
  EXPECT_THROW(groups.set_base_morale(3, std::nan("")), std::invalid_argument);
  EXPECT_THROW(groups.set(0, g), std::invalid_argument);
}

}  // namespace
}  // namespace throng::params
