#pragma once
// Field-by-field expectations for the protocol structs, expanding each message's one field list
// (message_fields.h). messages.h has no operator==, on purpose: a test names the field that
// differs, and the transport must not change a single bit. The fields the server's transport fills
// in (sender, identity) are not sent, so they are not compared.
#include <gtest/gtest.h>

#include <cstddef>
#include <type_traits>
#include <vector>

#include "throng/protocol/message_fields.h"
#include "throng/protocol/messages.h"

namespace throng::protocol::test {

inline void expect_same(const SceneryShape& a, const SceneryShape& b);
inline void expect_same(const Roster& a, const Roster& b);

// A field's values: nested messages field by field, lists of them element by element, the rest
// with EXPECT_EQ.
template <class T>
void expect_same_field(const char* field, const T& a, const T& b) {
  SCOPED_TRACE(field);
  if constexpr (std::is_same_v<T, Roster>) {
    expect_same(a, b);
  } else if constexpr (std::is_same_v<T, std::vector<SceneryShape>>) {
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t i = 0; i < a.size(); ++i) expect_same(a[i], b[i]);
  } else {
    EXPECT_EQ(a, b);
  }
}

#define THRONG_EXPECT_SAME_FIELD(f) expect_same_field(#f, a.f, b.f);
#define THRONG_EXPECT_SAME(Message, FIELDS) \
  inline void expect_same(const Message& a, const Message& b) { FIELDS(THRONG_EXPECT_SAME_FIELD) }

THRONG_EXPECT_SAME(SceneryShape, THRONG_SCENERY_SHAPE_FIELDS)
THRONG_EXPECT_SAME(Roster, THRONG_ROSTER_FIELDS)
THRONG_EXPECT_SAME(JoinRequest, THRONG_JOIN_REQUEST_FIELDS)
THRONG_EXPECT_SAME(JoinReply, THRONG_JOIN_REPLY_FIELDS)
THRONG_EXPECT_SAME(Command, THRONG_COMMAND_FIELDS)
THRONG_EXPECT_SAME(Snapshot, THRONG_SNAPSHOT_FIELDS)
THRONG_EXPECT_SAME(MatchInfo, THRONG_MATCH_INFO_FIELDS)
THRONG_EXPECT_SAME(ParamUpdate, THRONG_PARAM_UPDATE_FIELDS)
THRONG_EXPECT_SAME(ParamReply, THRONG_PARAM_REPLY_FIELDS)
THRONG_EXPECT_SAME(ServerStats, THRONG_SERVER_STATS_FIELDS)
THRONG_EXPECT_SAME(ContactPairs, THRONG_CONTACT_PAIRS_FIELDS)

#undef THRONG_EXPECT_SAME
#undef THRONG_EXPECT_SAME_FIELD

}  // namespace throng::protocol::test
