// Morale as a dynamic parameter during play: a group surrounded by enemies loses morale (counted by
// the world from the bodies around its members), and the same pair then splits its push
// differently — with the share derived from the group morale values, not pasted.
#include <gtest/gtest.h>

#include <cmath>

#include "throng/params/group_table.h"
#include "world/world_fixtures.h"

namespace throng {
namespace {

using namespace throng::test;

params::ParamTable morale_table() {
  params::ParamTable t = test_table();
  params::ObjectParams a = archetype_with(80.0);
  a.faction = 1;
  a.group_id = 1;
  t.set_archetype("blue_unit", a);
  params::ObjectParams b = archetype_with(80.0);
  b.faction = 2;
  b.group_id = 2;
  t.set_archetype("red_unit", b);
  params::ObjectParams extra = archetype_with(80.0);
  extra.faction = 2;
  t.set_archetype("red_rabble", extra);
  t.groups().set(1, params::Group{});
  t.groups().set(2, params::Group{});
  return t;
}

double share_of(const World& w, ObjectId a, ObjectId b) {
  for (const PushEvent& e : w.push_events()) {
    if (e.a == a && e.b == b) return e.share_a;
    if (e.a == b && e.b == a) return 1.0 - e.share_a;
  }
  ADD_FAILURE() << "no push event between the pair";
  return -1.0;
}

TEST(WorldMorale, SurroundedGroupLosesMoraleAndIsPushedMore) {
  params::Term morale;
  morale.input = params::TermInput::morale;
  morale.weight = 1.0;
  morale.scale = 10.0;
  WorldSettings s = quiet_settings();
  s.morale_refresh_ticks = 5;
  World w(s, morale_table(), params::PushPolicy(params::PushMode::ratio, {morale}, {}));
  const ObjectId blue = add_sphere(w, 0.0, 0.0, 0.35, "blue_unit");
  const ObjectId red = add_sphere(w, 0.6, 0.0, 0.35, "red_unit");
  w.step();
  EXPECT_NEAR(share_of(w, blue, red), 0.5, 1e-6);  // equal morale: 50/50

  // Twenty red soldiers gather around the blue unit (within the 5 m morale radius).
  for (int k = 0; k < 20; ++k) {
    const double ang = 6.283185307179586 * k / 20.0;
    add_sphere(w, 3.0 * std::cos(ang), 3.0 * std::sin(ang), 0.35, "red_rabble");
  }
  for (std::uint32_t t = 0; t < 2 * s.morale_refresh_ticks; ++t) w.step();
  EXPECT_EQ(w.groups().at(1).morale_state, params::MoraleState::low);
  EXPECT_EQ(w.groups().at(2).morale_state, params::MoraleState::high);

  w.set_position(blue, {0.0, 0.0, 0.35});
  w.set_position(red, {0.6, 0.0, 0.35});
  w.step();
  const double expected = 1.0 / (1.0 + std::exp((w.groups().morale(1) - w.groups().morale(2)) / 10.0));
  EXPECT_GT(expected, 0.9);
  EXPECT_NEAR(share_of(w, blue, red), expected, 1e-6);
}

}  // namespace
}  // namespace throng
