// The keyframe saver: checkpoints taken on its thread are the bytes Match::save_checkpoint gives
// on the caller's thread, it is reusable tick after tick, and misuse is refused.
#include "throng/server/keyframe_saver.h"

#include <stdexcept>

#include <gtest/gtest.h>

#include "match/match_test_util.h"
#include "throng/match/match.h"

namespace throng::server {
namespace {

using match::Match;
using match::Outbox;

class KeyframeSaverModes : public ::testing::TestWithParam<bool> {};

TEST_P(KeyframeSaverModes, SavesTheSameBytesAsSaveCheckpointTickAfterTick) {
  const bool baselines = GetParam();
  Match m(match::test::two_armies(), match::test::small_config(), "kf-saver");
  Outbox out;
  KeyframeSaver saver{baselines};
  std::vector<std::uint8_t> expected;
  for (int round = 0; round < 3; ++round) {
    for (int i = 0; i < 7; ++i) m.tick(out);
    saver.start(m, m.tick_index());
    EXPECT_TRUE(saver.pending());
    // const readers side by side, as publish_outbox does
    m.save_checkpoint(expected, match::SaveOptions{.snapshot_baselines = baselines});
    KeyframeSaver::Finished k;
    ASSERT_TRUE(saver.finish(k));
    EXPECT_FALSE(saver.pending());
    EXPECT_EQ(k.tick, m.tick_index());
    ASSERT_NE(k.bytes, nullptr);
    EXPECT_EQ(*k.bytes, expected) << "round " << round;
    EXPECT_EQ(match::checkpoint_sections(*k.bytes).snapshot_baselines.empty(), !baselines);
    // The saved bytes restore into a fresh match with the same state hash.
    Match copy(match::test::two_armies(), match::test::small_config(), "kf-copy");
    copy.restore_checkpoint(*k.bytes);
    EXPECT_EQ(copy.state_hash(), m.state_hash());
  }
}
INSTANTIATE_TEST_SUITE_P(WithAndWithoutSnapshotBaselines, KeyframeSaverModes, ::testing::Bool());

TEST(KeyframeSaver, FinishWithNothingPendingReturnsFalseAndStartTwiceIsRefused) {
  Match m(match::test::two_armies(), match::test::small_config(), "kf-misuse");
  KeyframeSaver saver{false};
  KeyframeSaver::Finished k;
  EXPECT_FALSE(saver.finish(k));
  EXPECT_EQ(k.bytes, nullptr);
  saver.start(m, 0);
  EXPECT_THROW(saver.start(m, 0), std::logic_error);
  EXPECT_TRUE(saver.finish(k));
  EXPECT_FALSE(k.bytes->empty());
}

TEST(KeyframeSaver, DestroyingWithASavePendingWaitsForIt) {
  Match m(match::test::two_armies(), match::test::small_config(), "kf-dtor");
  {
    KeyframeSaver saver{false};
    saver.start(m, 0);
  }  // must not crash or leave the thread reading a destroyed buffer (ASan checks the latter)
}

}  // namespace
}  // namespace throng::server
