// The field lists' guard: aggregate_field_count must count every kind of field the messages hold,
// or a field added to a message but not to its list would slip past the static_asserts in
// message_fields.h (which check every list at compile time).
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "throng/protocol/message_fields.h"

namespace throng::protocol {
namespace {

struct EveryKindOfField {
  std::uint64_t id = 7;
  float x = 0, y = 0;
  bool flag = false;
  MatchState state = MatchState::running;
  std::string text;
  std::vector<std::uint16_t> codes;
  std::vector<std::string> names;
  ParticipantKey key;
  Roster nested;
  std::vector<SceneryShape> shapes;
};

TEST(MessageFields, CountsEveryKindOfFieldOnce) {
  EXPECT_EQ(detail::aggregate_field_count<EveryKindOfField>(), 11u);
  EXPECT_EQ(detail::aggregate_field_count<ParticipantKey>(), 1u);
}

}  // namespace
}  // namespace throng::protocol
