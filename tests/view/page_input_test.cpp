// Page input validation: only a fully valid `input` message becomes a PageInput.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "throng/view/page_input.h"

namespace throng::view {
namespace {

PageInput ok(const std::string& text) {
  auto r = parse_page_message(text);
  EXPECT_TRUE(std::holds_alternative<PageInput>(r)) << text << " -> " << to_string(std::get<InputError>(r));
  return std::holds_alternative<PageInput>(r) ? std::get<PageInput>(r) : PageInput{};
}

InputError bad(const std::string& text) {
  auto r = parse_page_message(text);
  EXPECT_TRUE(std::holds_alternative<InputError>(r)) << text;
  return std::holds_alternative<InputError>(r) ? std::get<InputError>(r) : InputError::count_;
}

TEST(PageInput, AcceptsAFullMessage) {
  const PageInput in =
      ok(R"({"type":"input","move_x":0.6,"move_y":-0.8,"facing":1.5,"actions":3,"camera_x":12.5,"camera_y":-4})");
  EXPECT_FLOAT_EQ(in.move_x, 0.6f);
  EXPECT_FLOAT_EQ(in.move_y, -0.8f);
  EXPECT_FLOAT_EQ(in.facing_rad, 1.5f);
  EXPECT_EQ(in.actions, 3u);
  // The contacts overlay request (protocol::kActionContacts) is a known bit.
  EXPECT_EQ(ok(R"({"type":"input","actions":7})").actions, 7u);
  ASSERT_TRUE(in.panned());
  EXPECT_FLOAT_EQ(*in.camera_x, 12.5f);
  EXPECT_FLOAT_EQ(*in.camera_y, -4.0f);
}

TEST(PageInput, MissingFieldsDefaultToStandingStillAndFollowing) {
  const PageInput in = ok(R"({"type":"input","extra":"ignored"})");
  EXPECT_EQ(in.move_x, 0.0f);
  EXPECT_EQ(in.move_y, 0.0f);
  EXPECT_EQ(in.actions, 0u);
  EXPECT_FALSE(in.panned());
}

TEST(PageInput, WrapsFacingIntoPlusMinusPi) {
  const PageInput in = ok(R"({"type":"input","facing":7.0})");
  EXPECT_NEAR(in.facing_rad, 7.0 - 2 * std::numbers::pi, 1e-6);
  EXPECT_LE(std::abs(in.facing_rad), std::numbers::pi + 1e-6);
}

TEST(PageInput, RejectsWhatIsNotAnInputMessage) {
  EXPECT_EQ(bad("hello"), InputError::not_json);
  EXPECT_EQ(bad(R"({"type":"input","move_x":NaN})"), InputError::not_json);  // JSON has no NaN
  EXPECT_EQ(bad(R"({"type":"input","move_x":1e400})"), InputError::not_json);  // overflows a double
  EXPECT_EQ(bad("[1,2]"), InputError::not_object);
  EXPECT_EQ(bad(R"({"move_x":0})"), InputError::unknown_type);
  EXPECT_EQ(bad(R"({"type":"teleport"})"), InputError::unknown_type);
  EXPECT_EQ(bad(std::string(5000, ' ') + "{}"), InputError::too_large);
}

TEST(PageInput, RejectsWrongTypesAndRanges) {
  EXPECT_EQ(bad(R"({"type":"input","move_x":"1"})"), InputError::bad_type);
  EXPECT_EQ(bad(R"({"type":"input","move_x":null})"), InputError::bad_type);
  EXPECT_EQ(bad(R"({"type":"input","move_x":1e300})"), InputError::out_of_range);
  EXPECT_EQ(bad(R"({"type":"input","move_x":1,"move_y":1})"), InputError::out_of_range);  // |move| > 1
  EXPECT_EQ(bad(R"({"type":"input","move_y":-1.5})"), InputError::out_of_range);
  EXPECT_EQ(bad(R"({"type":"input","facing":100})"), InputError::out_of_range);
  EXPECT_EQ(bad(R"({"type":"input","camera_x":1})"), InputError::out_of_range);  // only one coordinate
  EXPECT_EQ(bad(R"({"type":"input","camera_x":1e6,"camera_y":0})"), InputError::out_of_range);
  EXPECT_EQ(bad(R"({"type":"input","actions":8})"), InputError::bad_actions);
  EXPECT_EQ(bad(R"({"type":"input","actions":12})"), InputError::bad_actions);  // contacts + an unknown bit
  EXPECT_EQ(bad(R"({"type":"input","actions":-1})"), InputError::bad_actions);
  EXPECT_EQ(bad(R"({"type":"input","actions":1.5})"), InputError::bad_actions);
  EXPECT_EQ(bad(R"({"type":"input","actions":"1"})"), InputError::bad_type);
}

TEST(PageInput, EveryErrorHasAName) {
  for (std::size_t i = 0; i < kInputErrorCount; ++i)
    EXPECT_STRNE(to_string(static_cast<InputError>(i)), "unknown") << i;
}

}  // namespace
}  // namespace throng::view
