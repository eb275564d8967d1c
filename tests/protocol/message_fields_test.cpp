// The field lists' guard: aggregate_field_count must count every kind of field the messages hold,
// or a field added to a message but not to its list would slip past the static_asserts in
// message_fields.h.
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

TEST(MessageFields, EachListNamesEveryFieldOfItsMessage) {
  // The same checks as the static_asserts, here so a failing count shows its numbers.
#define ONE(f) +1
  EXPECT_EQ(detail::aggregate_field_count<Snapshot>(), 0u THRONG_SNAPSHOT_FIELDS(ONE));
  EXPECT_EQ(detail::aggregate_field_count<MatchInfo>(), 0u THRONG_MATCH_INFO_FIELDS(ONE));
  EXPECT_EQ(detail::aggregate_field_count<Command>(), 0u THRONG_COMMAND_FIELDS(ONE) THRONG_COMMAND_LOCAL_FIELDS(ONE));
#undef ONE
  EXPECT_EQ(detail::aggregate_field_count<Command>(), 12u);  // 11 on the wire, the sender local
}

}  // namespace
}  // namespace throng::protocol
