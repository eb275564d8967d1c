// SnapshotBuilder: interest radius, quantization round trip, byte budget, priorities (no
// starvation), keepalive, removals, whole-world mode, determinism, view error and bad input.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <random>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "throng/core/object_id.h"
#include "throng/match/snapshot_builder.h"
#include "throng/protocol/codec.h"

namespace throng::match {
namespace {

constexpr double kPi = 3.14159265358979323846;

std::uint32_t oid(std::uint32_t index, std::uint32_t generation = 0) {
  return ObjectId::make(index, generation).value;
}

struct Bodies {
  std::vector<std::uint32_t> id;
  std::vector<double> x, y, z;
  std::vector<float> yaw;

  void add(std::uint32_t i, double px, double py, double pz = 0.0, float pyaw = 0.0f) {
    id.push_back(i);
    x.push_back(px);
    y.push_back(py);
    z.push_back(pz);
    yaw.push_back(pyaw);
  }
  std::size_t find(std::uint32_t i) const {
    return static_cast<std::size_t>(std::find(id.begin(), id.end(), i) - id.begin());
  }
  void erase(std::uint32_t i) {
    const std::size_t k = find(i);
    id.erase(id.begin() + static_cast<std::ptrdiff_t>(k));
    x.erase(x.begin() + static_cast<std::ptrdiff_t>(k));
    y.erase(y.begin() + static_cast<std::ptrdiff_t>(k));
    z.erase(z.begin() + static_cast<std::ptrdiff_t>(k));
    yaw.erase(yaw.begin() + static_cast<std::ptrdiff_t>(k));
  }
  BodyView view() const { return BodyView{id, x, y, z, yaw}; }
};

// What a client holds after applying the snapshots it got.
struct ClientModel {
  std::map<std::uint32_t, protocol::Pose> objects;
  std::map<std::uint32_t, int> removed_count;
  std::vector<protocol::Pose> last;  // poses of the last snapshot

  void apply(const protocol::Snapshot& s) {
    last.clear();
    protocol::decode_poses(s, last);
    for (const std::uint32_t r : s.removed) {
      objects.erase(r);
      ++removed_count[r];
    }
    for (const auto& p : last) objects[p.id] = p;
  }
  bool sent(std::uint32_t id) const {
    return std::any_of(last.begin(), last.end(), [&](const protocol::Pose& p) { return p.id == id; });
  }
};

InterestConfig unlimited(double radius = 30.0) {
  InterestConfig c;
  c.radius_m = radius;
  c.budget_bytes = 0;
  return c;
}

double yaw_diff(double a, double b) {
  double d = std::fmod(std::fabs(a - b), 2.0 * kPi);
  return d > kPi ? 2.0 * kPi - d : d;
}

Bodies random_bodies(std::mt19937_64& rng, std::size_t n, double half, std::uint32_t generation_mod = 1) {
  std::uniform_real_distribution<double> pos(-half, half), height(0.0, 2.0), yaw(-kPi, kPi);
  Bodies b;
  for (std::uint32_t i = 0; i < n; ++i)
    b.add(oid(i * 3 + 1, i % generation_mod), pos(rng), pos(rng), height(rng), static_cast<float>(yaw(rng)));
  return b;
}

// ---------------------------------------------------------------------------------------------

TEST(SnapshotBuilder, SendsExactlyTheBodiesInsideTheRadiusWithinHalfAUnit) {
  std::mt19937_64 rng(7);
  const Bodies b = random_bodies(rng, 3000, 100.0);
  SnapshotBuilder sb(unlimited(30.0));
  sb.add_client(1);
  sb.index(b.view(), 1);
  const double cx = 12.3456, cy = -7.891;
  protocol::Snapshot snap;
  const BuildStats& st = sb.build(1, cx, cy, snap);

  // Distances are taken between the camera and the bodies rounded to a millimetre.
  auto mm = [](double v) { return std::nearbyint(v * 1000.0); };
  std::set<std::uint32_t> inside;
  for (std::size_t i = 0; i < b.id.size(); ++i)
    if (std::pow(mm(b.x[i]) - mm(cx), 2) + std::pow(mm(b.y[i]) - mm(cy), 2) <= 30000.0 * 30000.0)
      inside.insert(b.id[i]);
  ASSERT_GT(inside.size(), 150u);

  std::vector<protocol::Pose> poses;
  protocol::decode_poses(snap, poses);
  std::set<std::uint32_t> got;
  for (const auto& p : poses) got.insert(p.id);
  EXPECT_EQ(got, inside);
  EXPECT_EQ(snap.unit_mm, 1);
  EXPECT_EQ(snap.objects_in_view, inside.size());
  EXPECT_EQ(st.in_view, inside.size());
  EXPECT_EQ(st.sent, inside.size());
  EXPECT_TRUE(snap.removed.empty());
  EXPECT_NEAR(snap.origin_x_mm, cx * 1000.0, 0.5);
  EXPECT_NEAR(snap.origin_y_mm, cy * 1000.0, 0.5);
  for (const auto& p : poses) {
    const std::size_t i = b.find(p.id);
    EXPECT_LE(std::fabs(p.x - b.x[i]), 0.0005 + 1e-9) << p.id;
    EXPECT_LE(std::fabs(p.y - b.y[i]), 0.0005 + 1e-9) << p.id;
    EXPECT_LE(std::fabs(p.z - b.z[i]), 0.0005 + 1e-9) << p.id;
    EXPECT_LE(yaw_diff(p.yaw, b.yaw[i]), kPi / 256.0 + 1e-6) << p.id;
  }
  // Unlimited budget: what the client holds is the truth up to quantization.
  EXPECT_LE(st.view_error_max_m, std::sqrt(3.0) * 0.0005 + 1e-6);
  EXPECT_LE(st.view_error_mean_m, st.view_error_max_m);
}

TEST(SnapshotBuilder, BudgetBoundsTheWireSizeInRandomScenes) {
  std::mt19937_64 rng(11);
  std::uniform_int_distribution<int> count(0, 2500), budget(60, 3000), gens(1, 4);
  std::uniform_real_distribution<double> cam(-60.0, 60.0), step(-0.2, 0.2);
  for (int scene = 0; scene < 40; ++scene) {
    InterestConfig cfg;
    cfg.budget_bytes = static_cast<std::uint32_t>(budget(rng));
    cfg.radius_m = scene % 5 == 0 ? 0.0 : 30.0;
    SnapshotBuilder sb(cfg);
    sb.add_client(3);
    // Mixed generations: ascending ids jump between generations, which costs id escapes.
    Bodies b = random_bodies(rng, static_cast<std::size_t>(count(rng)), 80.0, static_cast<std::uint32_t>(gens(rng)));
    protocol::Snapshot snap;
    std::size_t poses_sent = 0, removed_sent = 0;
    for (std::uint64_t t = 0; t < 12; ++t) {
      for (std::size_t i = 0; i < b.id.size(); ++i) {
        b.x[i] += step(rng);
        b.y[i] += step(rng);
      }
      if (t == 6) {  // destroy a third of the bodies at once: many removals compete for the budget
        Bodies kept;
        for (std::size_t i = 0; i < b.id.size(); ++i)
          if (i % 3 != 0) kept.add(b.id[i], b.x[i], b.y[i], b.z[i], b.yaw[i]);
        b = kept;
      }
      sb.index(b.view(), t);
      sb.build(3, cam(rng) * 0.2, cam(rng) * 0.2, snap);
      EXPECT_LE(protocol::snapshot_wire_bytes(snap), cfg.budget_bytes) << "scene " << scene << " tick " << t;
      poses_sent += snap.x.size();
      removed_sent += snap.removed.size();
      std::vector<protocol::Pose> poses;
      ASSERT_NO_THROW(protocol::decode_poses(snap, poses));
    }
    if (cfg.budget_bytes >= 200 && b.id.size() > 500) {
      EXPECT_GT(poses_sent, 0u) << "scene " << scene;
    }
  }
}

TEST(SnapshotBuilder, TightBudgetSendsTheNearestUnknownObjectsFirst) {
  std::mt19937_64 rng(3);
  const Bodies b = random_bodies(rng, 1500, 40.0);
  InterestConfig cfg;  // default budget: about 100 poses
  SnapshotBuilder sb(cfg);
  sb.add_client(1);
  sb.index(b.view(), 1);
  protocol::Snapshot snap;
  const BuildStats& st = sb.build(1, 0.0, 0.0, snap);
  ASSERT_GT(st.in_view, 500u);
  ASSERT_GT(st.sent, 80u);
  ASSERT_LT(st.sent, st.in_view);
  EXPECT_LE(protocol::snapshot_wire_bytes(snap), cfg.budget_bytes);
  // The budget is nearly used up: less than one more pose (plus an escape) would have fit.
  EXPECT_GT(protocol::snapshot_wire_bytes(snap) + protocol::kPoseWireBytes + 4 + 3, cfg.budget_bytes);
  std::vector<protocol::Pose> poses;
  protocol::decode_poses(snap, poses);
  std::set<std::uint32_t> sent;
  for (const auto& p : poses) sent.insert(p.id);
  double max_sent = 0.0, min_unsent = 1e9;
  for (std::size_t i = 0; i < b.id.size(); ++i) {
    const double d = std::hypot(b.x[i], b.y[i]);
    if (d > 30.0) continue;
    if (sent.count(b.id[i]))
      max_sent = std::max(max_sent, d);
    else
      min_unsent = std::min(min_unsent, d);
  }
  EXPECT_LE(max_sent, min_unsent + 1e-6);
  // View error covers only objects the client knows: all sent ones, at quantization error.
  EXPECT_LE(st.view_error_max_m, std::sqrt(3.0) * 0.0005 + 1e-6);
}

TEST(SnapshotBuilder, NoStarvationAndNearMovingObjectsAreSentMoreOften) {
  // 600 objects in view, about 100 poses per snapshot. Four groups: near/far x moving/static.
  Bodies b;
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> ang(-kPi, kPi), near_d(1.0, 8.0), far_d(22.0, 29.0);
  enum Group { near_moving, far_moving, near_static, far_static };
  std::vector<Group> group;
  std::vector<double> heading;
  for (std::uint32_t i = 0; i < 600; ++i) {
    const auto g = static_cast<Group>(i % 4);
    const double d = (g == near_moving || g == near_static) ? near_d(rng) : far_d(rng);
    const double a = ang(rng);
    b.add(oid(i), d * std::cos(a), d * std::sin(a), 0.9, static_cast<float>(a));
    group.push_back(g);
    heading.push_back(ang(rng));
  }
  InterestConfig cfg;
  SnapshotBuilder sb(cfg);
  sb.add_client(1);
  ClientModel client;
  protocol::Snapshot snap;
  std::vector<std::uint64_t> last_sent(b.id.size(), 0);
  std::vector<int> sends(b.id.size(), 0);
  std::uint64_t max_gap = 0;
  const double dt = 1.0 / 30.0, speed = 1.0;  // 3.3 cm per tick
  const std::uint64_t warmup = 20, ticks = 320;
  for (std::uint64_t t = 1; t <= ticks; ++t) {
    for (std::size_t i = 0; i < b.id.size(); ++i) {
      if (group[i] != near_moving && group[i] != far_moving) continue;
      // Circle around the start point: moving bodies stay in their distance band.
      heading[i] += 0.05;
      b.x[i] += speed * dt * std::cos(heading[i]);
      b.y[i] += speed * dt * std::sin(heading[i]);
    }
    sb.index(b.view(), t);
    sb.build(1, 0.0, 0.0, snap);
    ASSERT_LE(protocol::snapshot_wire_bytes(snap), cfg.budget_bytes);
    client.apply(snap);
    for (std::size_t i = 0; i < b.id.size(); ++i) {
      if (!client.sent(b.id[i])) continue;
      if (t > warmup) {
        ++sends[i];
        max_gap = std::max(max_gap, t - last_sent[i]);
      }
      last_sent[i] = t;
    }
    if (t == 8) {  // 600 unknown objects at ~100 per snapshot: all known within a few ticks
      for (std::size_t i = 0; i < b.id.size(); ++i) EXPECT_GT(last_sent[i], 0u) << i;
    }
  }
  for (std::size_t i = 0; i < b.id.size(); ++i) {
    EXPECT_GT(sends[i], 0) << "object " << i << " starved";
    max_gap = std::max(max_gap, ticks + 1 - last_sent[i]);
  }
  EXPECT_LE(max_gap, 60u);  // every object is refreshed at least every ~2 s
  double per_group[4] = {0, 0, 0, 0};
  for (std::size_t i = 0; i < b.id.size(); ++i) per_group[group[i]] += sends[i];
  EXPECT_GT(per_group[near_moving], 1.3 * per_group[far_moving]);
  EXPECT_GT(per_group[far_moving], 2.0 * per_group[near_static]);
  EXPECT_GT(per_group[far_moving], 2.0 * per_group[far_static]);
  // Static objects only ride on the keepalive: about once per keepalive period.
  const double static_rate = (per_group[near_static] + per_group[far_static]) / 300.0 / (ticks - warmup);
  EXPECT_LE(static_rate, 1.0 / cfg.keepalive_ticks + 0.01);
  EXPECT_GT(static_rate, 0.5 / cfg.keepalive_ticks);
}

TEST(SnapshotBuilder, UnchangedObjectsAreSkippedUntilKeepaliveAndMovedOnesResent) {
  Bodies b;
  for (std::uint32_t i = 0; i < 10; ++i) b.add(oid(i), i * 2.0, 1.0, 0.0, 0.5f);
  InterestConfig cfg = unlimited();
  cfg.keepalive_ticks = 30;
  SnapshotBuilder sb(cfg);
  sb.add_client(1);
  protocol::Snapshot snap;
  sb.index(b.view(), 100);
  EXPECT_EQ(sb.build(1, 0, 0, snap).sent, 10u);
  for (std::uint64_t t = 101; t < 130; ++t) {
    if (t == 110) b.x[3] += 0.0002;  // below a millimetre: the quantized pose does not change
    if (t == 115) b.x[4] += 0.01;    // a centimetre: resent once
    if (t == 120) b.yaw[5] += 0.2f;  // turning is a change too
    sb.index(b.view(), t);
    const BuildStats& st = sb.build(1, 0.5, 0, snap);  // a moving camera does not matter at 1 mm
    std::vector<protocol::Pose> poses;
    protocol::decode_poses(snap, poses);
    std::vector<std::uint32_t> expect;
    if (t == 115) expect = {oid(4)};
    if (t == 120) expect = {oid(5)};
    std::vector<std::uint32_t> got;
    for (const auto& p : poses) got.push_back(p.id);
    EXPECT_EQ(got, expect) << "tick " << t;
    EXPECT_EQ(st.skipped_unchanged, 10u - expect.size()) << "tick " << t;
    EXPECT_EQ(st.in_view, 10u);
  }
  // Tick 130: 30 ticks after the first send, every object not resent since is due.
  sb.index(b.view(), 130);
  const BuildStats& st = sb.build(1, 0, 0, snap);
  EXPECT_EQ(st.sent, 8u);  // all but 4 and 5 (sent at 115 and 120)
  sb.index(b.view(), 145);
  EXPECT_EQ(sb.build(1, 0, 0, snap).sent, 1u);  // 4
}

TEST(SnapshotBuilder, LeavingTheViewIsListedRemovedRepeatTimesAndReentrySendsAgain) {
  InterestConfig cfg = unlimited(30.0);
  cfg.exit_hysteresis = 1.1;
  cfg.removed_repeat = 3;
  SnapshotBuilder sb(cfg);
  sb.add_client(1);
  Bodies b;
  b.add(oid(0), 20.0, 0.0);
  b.add(oid(1), -5.0, 0.0);
  protocol::Snapshot snap;
  ClientModel client;
  std::uint64_t t = 0;
  auto tick = [&] {
    sb.index(b.view(), ++t);
    sb.build(1, 0.0, 0.0, snap);
    client.apply(snap);
  };
  tick();
  ASSERT_TRUE(client.objects.count(oid(0)));
  b.x[0] = 31.0;  // outside the radius, inside the hysteresis: neither sent nor removed
  for (int i = 0; i < 5; ++i) {
    tick();
    EXPECT_FALSE(client.sent(oid(0)));
    EXPECT_TRUE(snap.removed.empty());
    EXPECT_EQ(snap.objects_in_view, 1u);
  }
  b.x[0] = 34.0;  // beyond 33 m
  std::vector<std::size_t> removed_at;
  for (int i = 0; i < 8; ++i) {
    tick();
    if (std::count(snap.removed.begin(), snap.removed.end(), oid(0))) removed_at.push_back(t);
  }
  EXPECT_EQ(removed_at, (std::vector<std::size_t>{7, 8, 9}));
  EXPECT_EQ(client.removed_count[oid(0)], 3);
  EXPECT_FALSE(client.objects.count(oid(0)));
  b.x[0] = 25.0;  // back in view: unknown to the client again, so it is sent at once
  tick();
  EXPECT_TRUE(client.sent(oid(0)));
  EXPECT_TRUE(snap.removed.empty());
}

TEST(SnapshotBuilder, DestroyedAndRecycledIdsAreRemoved) {
  InterestConfig cfg = unlimited(30.0);
  cfg.removed_repeat = 2;
  SnapshotBuilder sb(cfg);
  sb.add_client(1);
  Bodies b;
  for (std::uint32_t i = 0; i < 5; ++i) b.add(oid(i), i * 1.0, 0.0);
  protocol::Snapshot snap;
  ClientModel client;
  std::uint64_t t = 0;
  auto tick = [&] {
    sb.index(b.view(), ++t);
    sb.build(1, 0.0, 0.0, snap);
    client.apply(snap);
  };
  tick();
  ASSERT_EQ(client.objects.size(), 5u);
  b.erase(oid(1));                // destroyed
  b.id[b.find(oid(3))] = oid(3, 1);  // index 3 reused by a new object (next generation)
  b.add(oid(4000), 1.0, 1.0);     // the world grows past the client's table
  tick();
  std::vector<std::uint32_t> removed = snap.removed;
  std::sort(removed.begin(), removed.end());
  EXPECT_EQ(removed, (std::vector<std::uint32_t>{oid(1), oid(3)}));
  EXPECT_TRUE(client.sent(oid(3, 1)));
  EXPECT_TRUE(client.sent(oid(4000)));
  tick();
  removed = snap.removed;
  std::sort(removed.begin(), removed.end());
  EXPECT_EQ(removed, (std::vector<std::uint32_t>{oid(1), oid(3)}));
  for (int i = 0; i < 4; ++i) {
    tick();
    EXPECT_TRUE(snap.removed.empty());
  }
  EXPECT_EQ(client.removed_count[oid(1)], 2);
  EXPECT_EQ(client.removed_count[oid(3)], 2);
  EXPECT_EQ(client.removed_count.count(oid(3, 1)), 0u);
  EXPECT_EQ(client.objects.size(), 5u);  // 0, 2, 3', 4, 4000
}

TEST(SnapshotBuilder, RemovalsBeyondTheBudgetWaitButAreStillListedRepeatTimes) {
  InterestConfig cfg;
  cfg.budget_bytes = 96 + 4 * 10;  // empty header (96 bytes) + 10 removed ids
  cfg.removed_repeat = 3;
  SnapshotBuilder sb(cfg);
  sb.add_client(1);
  Bodies b;
  for (std::uint32_t i = 0; i < 40; ++i) b.add(oid(i), 0.1 * i, 0.0);
  protocol::Snapshot snap;
  ClientModel client;
  std::uint64_t t = 0;
  for (; t < 20; ++t) {  // 40 objects at ~4 poses per snapshot
    sb.index(b.view(), t);
    sb.build(1, 0, 0, snap);
    client.apply(snap);
  }
  ASSERT_EQ(client.objects.size(), 40u);
  const Bodies none;
  for (; t < 40; ++t) {
    sb.index(none.view(), t);
    sb.build(1, 0, 0, snap);
    EXPECT_LE(protocol::snapshot_wire_bytes(snap), cfg.budget_bytes);
    EXPECT_LE(snap.removed.size(), 10u);
    client.apply(snap);
  }
  for (std::uint32_t i = 0; i < 40; ++i) EXPECT_EQ(client.removed_count[oid(i)], 3) << i;
  EXPECT_TRUE(client.objects.empty());
}

TEST(SnapshotBuilder, WholeWorldPicksACoarserUnitAndStillRoundTrips) {
  std::mt19937_64 rng(9);
  Bodies b = random_bodies(rng, 2000, 1000.0);  // 2 km x 2 km
  b.add(oid(99999), 1000.0, 1000.0, 40.0);      // a corner, and too high for 1 mm z
  SnapshotBuilder sb(unlimited(0.0));
  sb.add_client(1);
  sb.index(b.view(), 1);
  protocol::Snapshot snap;
  const BuildStats& st = sb.build(1, 500.0, -300.0, snap);
  EXPECT_GT(snap.unit_mm, 1);
  EXPECT_LE(snap.unit_mm, 40);  // 1 km half extent needs 31 mm
  EXPECT_EQ(st.in_view, b.id.size());
  EXPECT_EQ(st.sent, b.id.size());
  std::vector<protocol::Pose> poses;
  protocol::decode_poses(snap, poses);
  ASSERT_EQ(poses.size(), b.id.size());
  const double half_unit = snap.unit_mm / 2000.0 + 1e-9;
  for (const auto& p : poses) {
    const std::size_t i = b.find(p.id);
    EXPECT_LE(std::fabs(p.x - b.x[i]), half_unit) << p.id;
    EXPECT_LE(std::fabs(p.y - b.y[i]), half_unit) << p.id;
    EXPECT_LE(std::fabs(p.z - b.z[i]), half_unit) << p.id;
  }
  EXPECT_LE(st.view_error_max_m, std::sqrt(3.0) * half_unit + 1e-6);

  // Static world, moving camera: nothing changed, nothing resent (the origin snaps to the unit).
  sb.index(b.view(), 2);
  EXPECT_EQ(sb.build(1, -200.0, 100.0, snap).sent, 0u);

  // A large radius also gets a coarser unit, sized for radius * exit_hysteresis.
  InterestConfig big = unlimited(100.0);
  SnapshotBuilder sb2(big);
  sb2.add_client(1);
  sb2.index(b.view(), 1);
  sb2.build(1, 0.0, 0.0, snap);
  EXPECT_EQ(snap.unit_mm, 4);  // 110 m / 32.766 m -> 4 mm
  poses.clear();
  protocol::decode_poses(snap, poses);
  EXPECT_GT(poses.size(), 10u);
  for (const auto& p : poses) {
    const std::size_t i = b.find(p.id);
    EXPECT_LE(std::fabs(p.x - b.x[i]), 0.002 + 1e-9);
    EXPECT_LE(std::fabs(p.y - b.y[i]), 0.002 + 1e-9);
    EXPECT_LE(std::hypot(b.x[i], b.y[i]), 100.0);
  }
}

TEST(SnapshotBuilder, IdenticalInputsGiveIdenticalSnapshots) {
  InterestConfig cfg;
  SnapshotBuilder a(cfg), b(cfg);
  for (std::uint32_t c : {4u, 2u}) {
    a.add_client(c);
    b.add_client(c);
  }
  std::mt19937_64 rng(21);
  Bodies bodies = random_bodies(rng, 4000, 60.0, 3);
  std::normal_distribution<double> step(0.0, 0.05);
  protocol::Snapshot sa, sbs;
  for (std::uint64_t t = 0; t < 40; ++t) {
    for (std::size_t i = 0; i < bodies.id.size(); ++i) {
      bodies.x[i] += step(rng);
      bodies.y[i] += step(rng);
      bodies.yaw[i] += static_cast<float>(step(rng));
    }
    if (t == 20) bodies.erase(bodies.id[17]);
    a.index(bodies.view(), t);
    b.index(bodies.view(), t);
    for (std::uint32_t c : {2u, 4u}) {
      const double cx = std::sin(t * 0.1) * 20.0 + c, cy = std::cos(t * 0.1) * 20.0;
      const BuildStats sta = a.build(c, cx, cy, sa);
      const BuildStats stb = b.build(c, cx, cy, sbs);
      EXPECT_EQ(sa.origin_x_mm, sbs.origin_x_mm);
      EXPECT_EQ(sa.origin_y_mm, sbs.origin_y_mm);
      EXPECT_EQ(sa.unit_mm, sbs.unit_mm);
      EXPECT_EQ(sa.objects_in_view, sbs.objects_in_view);
      EXPECT_EQ(sa.id_codes, sbs.id_codes);
      EXPECT_EQ(sa.x, sbs.x);
      EXPECT_EQ(sa.y, sbs.y);
      EXPECT_EQ(sa.z, sbs.z);
      EXPECT_EQ(sa.yaw, sbs.yaw);
      EXPECT_EQ(sa.removed, sbs.removed);
      EXPECT_EQ(sta.sent, stb.sent);
      EXPECT_EQ(sta.view_error_max_m, stb.view_error_max_m);
      EXPECT_GT(sta.sent, 0u);
    }
  }
}

TEST(SnapshotBuilder, ViewErrorIsBoundedBySpeedTimesTicksSinceSent) {
  // 400 bodies in view walking at 2 m/s, budget for ~10 poses: the client's copies go stale, but
  // never by more than the distance walked since each was last sent.
  InterestConfig cfg;
  cfg.budget_bytes = 96 + 10 * 9 + 16;
  SnapshotBuilder sb(cfg);
  sb.add_client(1);
  std::mt19937_64 rng(4);
  Bodies b = random_bodies(rng, 400, 12.0);
  std::uniform_real_distribution<double> ang(-kPi, kPi);
  std::vector<double> heading(b.id.size());
  for (auto& h : heading) h = ang(rng);
  const double speed = 2.0, dt = 1.0 / 30.0;
  ClientModel client;
  std::map<std::uint32_t, std::uint64_t> last_sent;
  protocol::Snapshot snap;
  double worst = 0.0;
  for (std::uint64_t t = 1; t <= 150; ++t) {
    for (std::size_t i = 0; i < b.id.size(); ++i) {
      if (t % 20 == 0) heading[i] = ang(rng);
      b.x[i] += speed * dt * std::cos(heading[i]);
      b.y[i] += speed * dt * std::sin(heading[i]);
    }
    sb.index(b.view(), t);
    const BuildStats& st = sb.build(1, 0.0, 0.0, snap);
    client.apply(snap);
    for (const auto& p : client.last) last_sent[p.id] = t;
    double max_err = 0.0;
    for (const auto& [id, p] : client.objects) {
      const std::size_t i = b.find(id);
      if (std::hypot(b.x[i], b.y[i]) > cfg.radius_m) continue;
      const double e = std::sqrt(std::pow(p.x - b.x[i], 2) + std::pow(p.y - b.y[i], 2) + std::pow(p.z - b.z[i], 2));
      EXPECT_LE(e, speed * dt * static_cast<double>(t - last_sent[id]) + 0.001) << id << " tick " << t;
      max_err = std::max(max_err, e);
    }
    EXPECT_NEAR(st.view_error_max_m, max_err, 0.0015) << "tick " << t;  // the builder measures on mm-rounded truth
    worst = std::max(worst, st.view_error_max_m);
  }
  EXPECT_GT(worst, 0.2);  // it does grow with a tiny budget
}

TEST(SnapshotBuilder, RejectsBadInput) {
  SnapshotBuilder sb(InterestConfig{});
  protocol::Snapshot snap;
  sb.add_client(1);
  EXPECT_THROW(sb.build(1, 0, 0, snap), std::logic_error);  // no index() yet
  Bodies b;
  b.add(oid(0), 1, 1);
  sb.index(b.view(), 1);
  EXPECT_THROW(sb.build(2, 0, 0, snap), std::invalid_argument);
  EXPECT_THROW(sb.add_client(1), std::invalid_argument);
  try {
    sb.build(1, std::nan(""), 0, snap);
    FAIL() << "NaN camera accepted";
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("camera_x"), std::string::npos) << what;
    EXPECT_NE(what.find("nan"), std::string::npos) << what;
  }
  try {
    sb.build(1, 0, INFINITY, snap);
    FAIL() << "infinite camera accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("camera_y"), std::string::npos) << e.what();
  }

  Bodies dup = b;
  dup.add(oid(0, 1), 2, 2);  // same index, another generation
  EXPECT_THROW(sb.index(dup.view(), 2), std::invalid_argument);
  Bodies zero;
  zero.add(0, 1, 1);
  EXPECT_THROW(sb.index(zero.view(), 2), std::invalid_argument);
  Bodies ragged = b;
  ragged.yaw.push_back(0.0f);
  EXPECT_THROW(sb.index(ragged.view(), 2), std::invalid_argument);
  // After a refused index() the builder is usable again with good input.
  sb.index(b.view(), 3);
  EXPECT_EQ(sb.build(1, 0, 0, snap).sent, 1u);

  InterestConfig bad;
  bad.radius_m = -1.0;
  EXPECT_THROW(SnapshotBuilder{bad}, std::invalid_argument);
  bad = InterestConfig{};
  bad.exit_hysteresis = 0.5;
  EXPECT_THROW(SnapshotBuilder{bad}, std::invalid_argument);

  // Non-finite bodies are not indexed (and not sent) rather than poisoning the snapshot.
  Bodies nan_body = b;
  nan_body.add(oid(5), std::nan(""), 0.0);
  sb.index(nan_body.view(), 4);
  EXPECT_EQ(sb.build(1, 0, 0, snap).in_view, 1u);
  sb.remove_client(1);
  EXPECT_FALSE(sb.has_client(1));
  EXPECT_THROW(sb.build(1, 0, 0, snap), std::invalid_argument);
}

}  // namespace
}  // namespace throng::match
