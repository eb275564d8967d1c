// "No allocation per tick after warm-up" for the contacts channel: two identical matches get the
// same commands, one with 4 clients watching contacts; counted over the same ticks after warm-up,
// the watched match allocates exactly as often as the other (the channel adds no allocation,
// whatever Match::tick allocates elsewhere).
//
// The counters are the ones tests/support/counting_new.h defines for this binary (included by
// snapshot_alloc_test.cpp, which also replaces operator new). Redeclared here identically, which
// is how inline variables are shared between translation units; only the operators must stay in
// that one file.
#include <gtest/gtest.h>

#include <atomic>
#include <cstddef>
#include <utility>
#include <vector>

#include "match_test_util.h"
#include "throng/match/match.h"

inline std::atomic<bool> g_counting{false};
inline std::atomic<std::size_t> g_allocations{0};

namespace throng::match {
namespace {

TEST(MatchContactsAllocation, WatchingAddsNoAllocationAfterWarmUp) {
  // These must be the counters operator new bumps (a direct call is never elided).
  g_allocations = 0;
  g_counting = true;
  ::operator delete(::operator new(8));
  g_counting = false;
  ASSERT_EQ(g_allocations.load(), 1u) << "not the counters counting_new.h's operator new uses";

  MatchConfig config = test::small_config();
  config.contacts.max_pairs = 16;
  Match watched(test::two_armies(80, 4.0, 3.0), config, "watched");
  Match plain(test::two_armies(80, 4.0, 3.0), config, "plain");
  Outbox out_w, out_p;
  std::vector<protocol::JoinReply> joined;
  for (Match* m : {&watched, &plain})
    for (std::uint64_t n = 1; n <= 4; ++n) m->inputs().push(test::join_request(n));
  watched.tick(out_w);
  plain.tick(out_p);
  joined.assign(out_w.join_replies.begin(), out_w.join_replies.end());
  ASSERT_EQ(joined.size(), 4u);

  std::size_t counted[2] = {0, 0};
  std::size_t pairs = 0;
  for (std::uint32_t t = 1; t <= 90; ++t) {
    const bool measure = t > 60;  // warm-up: buffers grow to their largest tick first
    for (int which = 0; which < 2; ++which) {
      Match& m = which == 0 ? watched : plain;
      Outbox& out = which == 0 ? out_w : out_p;
      for (const auto& r : joined) {
        protocol::Command c = test::command(r.client_id, r.entity, t, 0.2f, 0.0f);
        c.actions = which == 0 ? protocol::kActionContacts : 0u;
        c.camera_x = static_cast<float>(r.client_id) - 2.0f;  // near the clash at x = 0
        m.inputs().push(std::move(c));
      }
      g_allocations = 0;
      g_counting = measure;
      m.tick(out);
      g_counting = false;
      if (measure) counted[which] += g_allocations.load();
      if (which == 0 && measure) {
        ASSERT_EQ(out.contacts_count, 4u);
        for (std::size_t k = 0; k < out.contacts_count; ++k) pairs += out.contacts[k].a.size();
      }
    }
    ASSERT_EQ(watched.state_hash(), plain.state_hash()) << "tick " << t;
  }
  EXPECT_GT(pairs, 0u) << "nothing was sent: the test proves nothing";
  EXPECT_EQ(counted[0], counted[1]) << "allocations over 30 ticks: watched " << counted[0] << ", plain " << counted[1];
  RecordProperty("allocations_over_30_ticks", static_cast<int>(counted[1]));
}

}  // namespace
}  // namespace throng::match
