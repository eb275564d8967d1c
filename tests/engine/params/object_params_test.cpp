#include "throng/params/object_params.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

namespace throng::params {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

Param param_at(std::size_t i) { return static_cast<Param>(i); }

std::string what_of_set(ObjectParams& o, Param p, double v) {
  try {
    o.set(p, v);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(ParamsObjectParams, EveryParamNameRoundTrips) {
  for (std::size_t i = 0; i < kParamCount; ++i) {
    const Param p = param_at(i);
    EXPECT_EQ(parse_param(param_name(p)), p) << param_name(p);
  }
  EXPECT_EQ(parse_param("weight"), Param::weight_kg);  // the designer-facing alias
  EXPECT_FALSE(try_parse_param("wieght").has_value());
}

TEST(ParamsObjectParams, UnknownFieldNameIsNamedInTheError) {
  ObjectParams o;
  try {
    o.set("wieght", 1.0);
    FAIL() << "expected an exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("'wieght'"), std::string::npos) << e.what();
  }
}

TEST(ParamsObjectParams, SettersRejectNaNAndInfAndKeepTheOldValue) {
  for (std::size_t i = 0; i < kParamCount; ++i) {
    const Param p = param_at(i);
    for (double bad : {kNaN, kInf, -kInf}) {
      ObjectParams o;
      const double before = o.get(p);
      const std::string what = what_of_set(o, p, bad);
      ASSERT_FALSE(what.empty()) << param_name(p) << " accepted " << bad;
      EXPECT_EQ(what.rfind(std::string(param_name(p)) + ": ", 0), 0u) << what;
      EXPECT_EQ(o.get(p), before) << param_name(p);
    }
  }
}

TEST(ParamsObjectParams, SettersRejectOutOfRangeJustOutsideEachBound) {
  for (std::size_t i = 0; i < kParamCount; ++i) {
    const Param p = param_at(i);
    const ParamRange r = param_range(p);
    ObjectParams o;
    const double step = r.integral ? 1.0 : 1e-6 * std::max(1.0, std::fabs(r.max));
    EXPECT_FALSE(what_of_set(o, p, r.max + step).empty()) << param_name(p);
    EXPECT_FALSE(what_of_set(o, p, r.min - std::max(step, 1e-6 * std::fabs(r.min))).empty()) << param_name(p);
    EXPECT_TRUE(what_of_set(o, p, r.min).empty()) << param_name(p);
    EXPECT_TRUE(what_of_set(o, p, r.max).empty()) << param_name(p);
  }
  ObjectParams o;
  EXPECT_EQ(what_of_set(o, Param::importance, 11.0), "importance: 11 is out of range [0, 10]");
  EXPECT_EQ(what_of_set(o, Param::faction, 1.5), "faction: 1.5 is not a whole number");
}

TEST(ParamsObjectParams, TextSetterTakesCategoriesAndNumbers) {
  ObjectParams o;
  o.set("weight", std::string_view("heavy"));
  EXPECT_EQ(o.weight_kg, weight_class_kg(WeightClass::heavy));
  o.set("weight_kg", std::string_view("123.5"));
  EXPECT_EQ(o.weight_kg, 123.5);
  o.set("kind", std::string_view("giant"));
  EXPECT_EQ(o.kind, Kind::giant);
  o.set("character_type", std::string_view("player"));
  EXPECT_EQ(o.character_type, CharacterType::player);
  o.set("fixed", std::string_view("true"));
  EXPECT_TRUE(o.fixed);
  o.set("hp", std::string_view("12.5"));
  EXPECT_EQ(o.hp, 12.5);
  try {
    o.set("weight", std::string_view("hevy"));
    FAIL();
  } catch (const std::invalid_argument& e) {
    const std::string w = e.what();
    EXPECT_EQ(w.rfind("weight_kg: ", 0), 0u) << w;
    EXPECT_NE(w.find("'hevy'"), std::string::npos) << w;
  }
  EXPECT_THROW(o.set("hp", std::string_view("12x")), std::invalid_argument);
  EXPECT_THROW(o.set("hp", std::string_view("nan")), std::invalid_argument);
}

TEST(ParamsObjectParams, WeightCategoriesMapToDocumentedMasses) {
  EXPECT_EQ(weight_class_kg(WeightClass::light), 50.0);
  EXPECT_EQ(weight_class_kg(WeightClass::medium), 80.0);
  EXPECT_EQ(weight_class_kg(WeightClass::heavy), 200.0);
  EXPECT_EQ(weight_class_kg(WeightClass::very_heavy), 600.0);
  for (auto c : {WeightClass::light, WeightClass::medium, WeightClass::heavy, WeightClass::very_heavy}) {
    EXPECT_EQ(weight_class_of(weight_class_kg(c)), c);
    EXPECT_EQ(parse_weight_class(weight_class_name(c)), c);
  }
  EXPECT_EQ(weight_class_of(weight_class_kg(WeightClass::heavy) - 1.0), WeightClass::medium);
}

TEST(ParamsObjectParams, FactionRelationIsRelativeToHomeFaction) {
  ObjectParams o;
  o.faction = 3;
  EXPECT_EQ(o.relation(3), FactionRelation::ally);
  EXPECT_EQ(o.relation(1), FactionRelation::enemy);
  o.faction = static_cast<std::uint8_t>(kNeutralFaction);
  EXPECT_EQ(o.relation(3), FactionRelation::neutral);
}

TEST(ParamsObjectParams, FacingIsStoredAsUnitVector) {
  ObjectParams o;
  const double quarter = std::acos(0.0);  // pi / 2
  o.set(Param::facing_yaw_rad, quarter);
  EXPECT_NEAR(o.facing_x, 0.0, 1e-15);
  EXPECT_NEAR(o.facing_y, 1.0, 1e-15);
  EXPECT_NEAR(o.get(Param::facing_yaw_rad), quarter, 1e-15);
  o.set_facing(3.0, 4.0);
  EXPECT_DOUBLE_EQ(o.facing_x, 0.6);
  EXPECT_DOUBLE_EQ(o.facing_y, 0.8);
  EXPECT_THROW(o.set_facing(0.0, 0.0), std::invalid_argument);
  EXPECT_THROW(o.set_facing(kNaN, 1.0), std::invalid_argument);
}

TEST(ParamsObjectParams, ValidateCatchesDirectWrites) {
  ObjectParams o;
  EXPECT_NO_THROW(o.validate());
  o.importance = kNaN;
  try {
    o.validate();
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()).rfind("importance: ", 0), 0u) << e.what();
  }
  ObjectParams f;
  f.facing_x = 2.0;
  EXPECT_THROW(f.validate(), std::invalid_argument);
}

TEST(ParamsObjectParams, CollisionFilterNeedsBothDirections) {
  ObjectParams a;
  ObjectParams b;
  a.collision_group = 0b01;
  b.collision_group = 0b10;
  a.collision_mask = 0b10;
  b.collision_mask = 0b01;
  EXPECT_TRUE(should_collide(a, b));
  b.collision_mask = 0b10;  // b no longer accepts a's group
  EXPECT_FALSE(should_collide(a, b));
  EXPECT_FALSE(should_collide(b, a));
}

}  // namespace
}  // namespace throng::params
