// The contact-pairs debug channel (match.h, contacts.h): an opted-in client gets the body pairs the
// solver pushed apart nearest its camera with the world's own shares; a client that did not ask
// gets nothing; the number of served clients is capped (refusals counted); a bad request is
// rejected and counted; and whoever watches, the state hash is the same as without the overlay.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <tuple>
#include <utility>
#include <vector>

#include "match_test_util.h"
#include "throng/match/contacts.h"
#include "throng/match/match.h"
#include "throng/protocol/contacts.h"
#include "throng/scene/builtin_scenes.h"
#include "throng/scene/scale.h"
#include "throng/world/world.h"

namespace throng::match {
namespace {

using test::command;
using test::join_request;
using test::small_config;
using test::two_armies;

// Two armies spawned into each other: pushing from the first tick.
scene::SceneDef clash() { return two_armies(60, 4.0, 3.0); }

MatchConfig contacts_config(std::uint32_t max_clients, std::uint32_t max_pairs = 8, double radius_m = 5.0) {
  MatchConfig c = small_config();
  c.contacts.max_clients = max_clients;
  c.contacts.max_pairs = max_pairs;
  c.contacts.radius_m = radius_m;
  return c;
}

protocol::Command cmd(std::uint32_t client, std::uint32_t entity, std::uint32_t seq, bool contacts, float cx = 0.0f,
                      float cy = 0.0f) {
  protocol::Command c = command(client, entity, seq);
  c.actions = contacts ? protocol::kActionContacts : 0u;
  c.camera_x = cx;
  c.camera_y = cy;
  return c;
}

const protocol::ContactPairs* contacts_of(const Outbox& out, std::uint32_t client) {
  for (std::size_t i = 0; i < out.contacts_count; ++i)
    if (out.contacts[i].client_id == client) return &out.contacts[i];
  return nullptr;
}

struct Expected {
  double d2;
  std::uint32_t a, b;
  float share_a, depth_m, push_m;
};

// The pairs contacts.h promises, computed here from the world's push events independently.
std::vector<Expected> expected_near(const World& w, double cx, double cy, double radius) {
  std::vector<Expected> e;
  for (const PushEvent& p : w.push_events()) {
    if (!w.is_body(p.a) || !w.is_body(p.b)) continue;
    const Vec3 a = w.position(p.a), b = w.position(p.b);
    const double mx = (a.x + b.x) / 2 - cx, my = (a.y + b.y) / 2 - cy;
    const double d2 = mx * mx + my * my;
    if (d2 <= radius * radius) e.push_back(Expected{d2, p.a.value, p.b.value, p.share_a, p.depth_m, p.push_m});
  }
  std::sort(e.begin(), e.end(), [](const Expected& l, const Expected& r) {
    return std::tie(l.d2, l.a, l.b) < std::tie(r.d2, r.a, r.b);
  });
  return e;
}

TEST(MatchContacts, OptedInClientGetsThePairsNearItsCameraWithTheWorldsShares) {
  Match m(clash(), contacts_config(2, 8, 5.0), "contacts");
  Outbox out;
  m.inputs().push(join_request(1));
  m.inputs().push(join_request(2));
  m.tick(out);
  ASSERT_EQ(out.join_replies.size(), 2u);
  const auto r1 = out.join_replies[0], r2 = out.join_replies[1];
  EXPECT_EQ(out.contacts_count, 0u) << "nobody asked yet";

  std::size_t pairs_seen = 0, capped_ticks = 0;
  for (std::uint32_t t = 1; t <= 40; ++t) {
    m.inputs().push(cmd(r1.client_id, r1.entity, t, true, 0.5f, -1.0f));  // opted in, camera at the clash
    m.inputs().push(cmd(r2.client_id, r2.entity, t, false, 0.5f, -1.0f));
    const TickReport& rep = m.tick(out);
    ASSERT_EQ(out.contacts_count, 1u) << "tick " << rep.tick;
    EXPECT_EQ(contacts_of(out, r2.client_id), nullptr) << "a client that did not ask gets no contacts";
    const protocol::ContactPairs* cp = contacts_of(out, r1.client_id);
    ASSERT_NE(cp, nullptr);
    EXPECT_EQ(cp->tick, rep.tick);
    EXPECT_FALSE(protocol::check_contact_pairs(*cp).has_value()) << *protocol::check_contact_pairs(*cp);
    EXPECT_FLOAT_EQ(cp->camera_x, 0.5f);
    EXPECT_FLOAT_EQ(cp->camera_y, -1.0f);

    const std::vector<Expected> want = expected_near(m.world(), 0.5, -1.0, 5.0);
    EXPECT_EQ(cp->pairs_near, want.size()) << "tick " << rep.tick;
    ASSERT_EQ(cp->a.size(), std::min<std::size_t>(8, want.size())) << "the cap is max_pairs";
    for (std::size_t i = 0; i < cp->a.size(); ++i) {
      SCOPED_TRACE("tick " + std::to_string(rep.tick) + " pair " + std::to_string(i));
      EXPECT_EQ(cp->a[i], want[i].a);
      EXPECT_EQ(cp->b[i], want[i].b);
      const double share = protocol::dequantize_share(cp->share_a[i]);
      EXPECT_NEAR(share, want[i].share_a, 0.5 / protocol::kShareScale);
      EXPECT_GT(share, 0.0);  // the ratio policy's shares lie strictly inside (0, 1)
      EXPECT_LT(share, 1.0);
      EXPECT_NEAR(protocol::dequantize_contact_m(cp->depth[i]), want[i].depth_m, 0.5 * protocol::kContactUnitM);
      EXPECT_NEAR(protocol::dequantize_contact_m(cp->push[i]), want[i].push_m, 0.5 * protocol::kContactUnitM);
    }
    EXPECT_EQ(rep.contact_pairs, cp->a.size());
    pairs_seen += cp->a.size();
    if (want.size() > 8) ++capped_ticks;
  }
  EXPECT_GT(pairs_seen, 40u) << "the armies never pushed near the camera: the test proves nothing";
  EXPECT_GT(capped_ticks, 0u) << "the pair cap was never reached";

  // A command without the bit gives the place back: no contacts from the next tick on.
  m.inputs().push(cmd(r1.client_id, r1.entity, 41, false));
  m.tick(out);
  EXPECT_EQ(out.contacts_count, 0u);
  EXPECT_TRUE(m.contacts_clients().empty());
}

TEST(MatchContacts, TheCapHoldsRefusalsAreCountedAndLeavingFreesThePlace) {
  Match m(clash(), contacts_config(1), "cap");
  Outbox out;
  for (std::uint64_t n = 1; n <= 3; ++n) m.inputs().push(join_request(n));
  m.tick(out);
  ASSERT_EQ(out.join_replies.size(), 3u);
  std::vector<protocol::JoinReply> r(out.join_replies.begin(), out.join_replies.end());
  std::uint32_t seq = 0;
  auto all_ask = [&](bool third_asks) {
    ++seq;
    for (std::size_t k = 0; k < r.size(); ++k)
      if (r[k].client_id != 0) m.inputs().push(cmd(r[k].client_id, r[k].entity, seq, k < 2 || third_asks));
    return m.tick(out);
  };
  const TickReport& first = all_ask(false);
  ASSERT_EQ(m.contacts_clients().size(), 1u) << "max_clients = 1";
  EXPECT_EQ(first.contacts_refused, 1u);
  EXPECT_EQ(out.contacts_count, 1u);
  const std::uint32_t served = m.contacts_clients()[0];
  for (int i = 0; i < 5; ++i) {
    all_ask(true);
    ASSERT_EQ(m.contacts_clients().size(), 1u);
    EXPECT_EQ(m.contacts_clients()[0], served) << "first come keeps its place while it asks";
    EXPECT_EQ(out.contacts_count, 1u);
    EXPECT_EQ(out.contacts[0].client_id, served);
  }
  EXPECT_EQ(m.contacts_refused_total(), 1u + 5u * 2u);

  // The served client leaves: the next request takes its place.
  std::uint64_t served_nonce = 0;
  for (auto& x : r)
    if (x.client_id == served) {
      served_nonce = x.client_nonce;
      m.inputs().push(test::leave_request(x.client_nonce, x.client_id));
      x.client_id = 0;
    }
  ASSERT_NE(served_nonce, 0u);
  m.tick(out);
  EXPECT_TRUE(m.contacts_clients().empty()) << "a departed client gives its place back";
  all_ask(true);
  ASSERT_EQ(m.contacts_clients().size(), 1u);
  EXPECT_NE(m.contacts_clients()[0], served);
  EXPECT_EQ(out.contacts_count, 1u);
}

TEST(MatchContacts, ChannelOffRefusesEveryRequest) {
  Match m(clash(), contacts_config(0), "off");
  Outbox out;
  const auto r = test::join_one(m, out, 1);
  for (std::uint32_t t = 1; t <= 3; ++t) {
    m.inputs().push(cmd(r.client_id, r.entity, t, true));
    EXPECT_EQ(m.tick(out).contacts_refused, 1u);
    EXPECT_EQ(out.contacts_count, 0u);
  }
  EXPECT_EQ(m.contacts_refused_total(), 3u);
  EXPECT_EQ(m.rejected_by_reason()[static_cast<std::size_t>(RejectReason::bad_actions)], 0u)
      << "the command itself still applies";
}

// Match A: one client watches contacts and sends a bad request; match B gets the same commands
// without the contacts bit and without the bad one. Every tick's state hash must agree.
TEST(MatchContacts, WatchingAndBadRequestsNeverChangeTheStateHash) {
  Match a(clash(), contacts_config(2), "watched");
  Match b(clash(), contacts_config(2), "unwatched");
  Outbox out_a, out_b;
  for (Match* m : {&a, &b}) {
    m->inputs().push(join_request(1));
    m->inputs().push(join_request(2));
  }
  a.tick(out_a);
  b.tick(out_b);
  ASSERT_EQ(out_a.join_replies.size(), 2u);
  const auto r1 = out_a.join_replies[0], r2 = out_a.join_replies[1];
  ASSERT_EQ(r1.entity, out_b.join_replies[0].entity);
  std::size_t pairs = 0;
  for (std::uint32_t t = 1; t <= 60; ++t) {
    const float mx = (t % 20 < 10) ? 0.8f : -0.6f;
    for (Match* m : {&a, &b}) {
      const bool watched = m == &a;
      protocol::Command c1 = cmd(r1.client_id, r1.entity, 2 * t, watched && t % 15 != 0, 1.0f, 0.0f);
      c1.move_x = mx;
      c1.actions |= (t % 7 == 0) ? protocol::kActionBrace : 0u;
      m->inputs().push(std::move(c1));
      m->inputs().push(cmd(r2.client_id, r2.entity, t, watched, -2.0f, 1.0f));
      if (watched && t == 20) {
        protocol::Command bad = cmd(r1.client_id, r1.entity, 2 * t + 1, true);
        bad.actions |= 1u << 5;  // an unknown bit beside the contacts request: bad_actions
        bad.move_x = -1.0f;
        m->inputs().push(std::move(bad));
      }
    }
    const std::uint64_t ha = a.tick(out_a).state_hash;
    const std::uint64_t hb = b.tick(out_b).state_hash;
    ASSERT_EQ(ha, hb) << "tick " << t << ": watching contacts changed the simulation";
    for (std::size_t i = 0; i < out_a.contacts_count; ++i) pairs += out_a.contacts[i].a.size();
    EXPECT_EQ(out_b.contacts_count, 0u);
  }
  EXPECT_GT(pairs, 0u);
  EXPECT_EQ(a.rejected_by_reason()[static_cast<std::size_t>(RejectReason::bad_actions)], 1u);
  EXPECT_EQ(b.rejected_by_reason()[static_cast<std::size_t>(RejectReason::bad_actions)], 0u);
  EXPECT_EQ(a.commands_accepted_total(), b.commands_accepted_total());
  EXPECT_EQ(a.state_hash(), b.state_hash());
}

TEST(MatchContacts, ConfigIsValidated) {
  MatchConfig c = small_config();
  c.contacts.max_pairs = 0;
  EXPECT_THROW(validate_config(c), std::invalid_argument);
  c = small_config();
  c.contacts.max_clients = 257;
  EXPECT_THROW(validate_config(c), std::invalid_argument);
  c = small_config();
  c.contacts.radius_m = 0.0;
  EXPECT_THROW(validate_config(c), std::invalid_argument);
  c.contacts.radius_m = std::nan("");
  EXPECT_THROW(validate_config(c), std::invalid_argument);
  EXPECT_NO_THROW(validate_config(small_config()));
}

TEST(MatchContacts, FacingAccessorReturnsTheCommandedYaw) {
  Match m(clash(), small_config(), "facing");
  Outbox out;
  const auto r = test::join_one(m, out, 1);
  protocol::Command c = command(r.client_id, r.entity, 1);
  c.facing_rad = 1.25f;
  m.inputs().push(std::move(c));
  m.tick(out);
  ASSERT_TRUE(m.facing_rad(ObjectId{r.entity}).has_value());
  EXPECT_FLOAT_EQ(*m.facing_rad(ObjectId{r.entity}), 1.25f);
  ASSERT_EQ(out.snapshot_count, 1u);
  EXPECT_FLOAT_EQ(out.snapshots[0].entity_yaw, 1.25f) << "the same yaw the snapshot carries";
  EXPECT_FALSE(m.facing_rad(ObjectId{}).has_value());
}

// Measurement (not run by default): step time with push events recorded or not, and the contacts
// phase with 4 served clients, at THRONG_MEASURE_BODIES (5,000) bodies of the battle scene.
//   throng_match_tests --gtest_also_run_disabled_tests --gtest_filter='MeasureContacts*'
TEST(MeasureContacts, DISABLED_StepTimeWithAndWithoutPushEvents) {
  const char* env = std::getenv("THRONG_MEASURE_BODIES");
  const std::uint64_t bodies = env ? std::strtoull(env, nullptr, 10) : 5000;
  const int ticks = 300;
  auto median = [](std::vector<double> v) {
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
    return v[v.size() / 2];
  };
  for (int round = 0; round < 2; ++round) {
    for (bool record : {true, false}) {
      for (bool watch : {false, true}) {
        if (watch && !record) continue;
        scene::SceneDef s = scene::scale_scene(scene::load_scene("battle"), bodies);
        s.settings.record_push_events = record;
        MatchConfig c;
        Match m(s, c, "measure");
        Outbox out;
        std::vector<protocol::JoinReply> joined;
        for (std::uint64_t n = 1; n <= 4; ++n) m.inputs().push(join_request(n));
        m.tick(out);
        joined.assign(out.join_replies.begin(), out.join_replies.end());
        std::vector<double> step, snap;
        std::size_t events = 0, pairs = 0;
        for (int t = 1; t <= ticks; ++t) {
          for (const auto& r : joined) {
            protocol::Command cc = command(r.client_id, r.entity, static_cast<std::uint32_t>(t), 0.3f, 0.0f);
            cc.actions = watch ? protocol::kActionContacts : 0u;
            for (std::size_t k = 0; k < out.snapshot_count; ++k)  // the camera on the own character
              if (out.snapshots[k].client_id == r.client_id) {
                cc.camera_x = out.snapshots[k].entity_x;
                cc.camera_y = out.snapshots[k].entity_y;
              }
            m.inputs().push(std::move(cc));
          }
          const TickReport& rep = m.tick(out);
          if (t > 30) {
            step.push_back(rep.step_us);
            snap.push_back(rep.snapshots_us);
          }
          events += rep.push_events;
          pairs += rep.contact_pairs;
        }
        std::printf("round %d  %llu bodies  record_push_events %-5s contacts clients %d: step median %.0f us, "
                    "snapshots+contacts median %.0f us, push events/tick %.0f, contact pairs sent/tick %.1f\n",
                    round, static_cast<unsigned long long>(m.world().body_count()), record ? "on" : "off", watch ? 4 : 0,
                    median(step), median(snap), static_cast<double>(events) / ticks, static_cast<double>(pairs) / ticks);
      }
    }
  }
}

}  // namespace
}  // namespace throng::match
