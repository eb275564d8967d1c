// SnapshotBuilder::build() from several threads (distinct clients, one Scratch per thread) gives
// the same bytes as building the clients one after the other; and the pose arrays it writes are
// exactly what protocol::encode_poses writes for the decoded poses.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <thread>
#include <vector>

#include "throng/core/object_id.h"
#include "throng/match/snapshot_builder.h"
#include "throng/protocol/codec.h"

namespace throng::match {
namespace {

constexpr double kPi = 3.14159265358979323846;

struct Crowd {
  std::vector<std::uint32_t> id;
  std::vector<double> x, y, z, heading;
  std::vector<float> yaw;

  BodyView view() const { return BodyView{id, x, y, z, yaw}; }

  // n bodies in a square of side `side` around the origin, ids of mixed generations (so some
  // snapshots need id escapes), walking at up to 1.5 m/s.
  static Crowd make(std::mt19937_64& rng, std::size_t n, double side, std::uint32_t generations) {
    std::uniform_real_distribution<double> pos(-side / 2, side / 2), ang(-kPi, kPi), height(0.0, 2.0);
    Crowd c;
    for (std::uint32_t i = 0; i < n; ++i) {
      c.id.push_back(ObjectId::make(i, i % generations).value);
      c.x.push_back(pos(rng));
      c.y.push_back(pos(rng));
      c.z.push_back(height(rng));
      c.heading.push_back(ang(rng));
      c.yaw.push_back(static_cast<float>(c.heading.back()));
    }
    return c;
  }
  void step(std::mt19937_64& rng, double dt) {
    std::uniform_real_distribution<double> turn(-0.3, 0.3), speed(0.0, 1.5);
    for (std::size_t i = 0; i < id.size(); ++i) {
      heading[i] += turn(rng);
      const double v = speed(rng);
      x[i] += v * dt * std::cos(heading[i]);
      y[i] += v * dt * std::sin(heading[i]);
      yaw[i] = static_cast<float>(heading[i]);
    }
  }
};

void expect_same(const protocol::Snapshot& a, const protocol::Snapshot& b, std::uint64_t tick, std::uint32_t client) {
  EXPECT_EQ(a.origin_x_mm, b.origin_x_mm) << "tick " << tick << " client " << client;
  EXPECT_EQ(a.origin_y_mm, b.origin_y_mm) << "tick " << tick << " client " << client;
  EXPECT_EQ(a.unit_mm, b.unit_mm) << "tick " << tick << " client " << client;
  EXPECT_EQ(a.objects_in_view, b.objects_in_view) << "tick " << tick << " client " << client;
  EXPECT_EQ(a.id_codes, b.id_codes) << "tick " << tick << " client " << client;
  EXPECT_EQ(a.x, b.x) << "tick " << tick << " client " << client;
  EXPECT_EQ(a.y, b.y) << "tick " << tick << " client " << client;
  EXPECT_EQ(a.z, b.z) << "tick " << tick << " client " << client;
  EXPECT_EQ(a.yaw, b.yaw) << "tick " << tick << " client " << client;
  EXPECT_EQ(a.removed, b.removed) << "tick " << tick << " client " << client;
}

TEST(SnapshotBuilderThreads, EightClientsFromFourThreadsMatchASequentialBuild) {
  constexpr std::uint32_t kClients = 8, kThreads = 4;
  std::mt19937_64 rng(17);
  Crowd crowd = Crowd::make(rng, 5000, 110.0, 3);
  InterestConfig cfg;  // default budget: the priorities decide what is sent
  SnapshotBuilder sequential(cfg), parallel(cfg);
  for (std::uint32_t c = 1; c <= kClients; ++c) {
    sequential.add_client(c * 7);
    parallel.add_client(c * 7);
  }
  std::vector<SnapshotBuilder::Scratch> scratch(kThreads);
  std::vector<protocol::Snapshot> seq_out(kClients), par_out(kClients);
  std::vector<BuildStats> seq_stats(kClients), par_stats(kClients);
  auto camera = [](std::uint32_t c, std::uint64_t t) {
    const double a = 0.05 * static_cast<double>(t) + c;  // cameras circling at about 4 m/s
    return std::pair{30.0 * std::cos(a) + 3.0 * c, 30.0 * std::sin(a) - 2.0 * c};
  };
  for (std::uint64_t t = 1; t <= 60; ++t) {
    crowd.step(rng, 1.0 / 30.0);
    if (t == 30) {  // destroy some bodies and recycle an index: removals in every client's list
      for (std::size_t i = 0; i < 40; ++i) crowd.x[i * 97] = std::nan("");
      crowd.id[5] = ObjectId::make(5, 7).value;
    }
    sequential.index(crowd.view(), t);
    parallel.index(crowd.view(), t);
    for (std::uint32_t c = 0; c < kClients; ++c) {
      const auto [cx, cy] = camera(c, t);
      seq_stats[c] = sequential.build((c + 1) * 7, cx, cy, seq_out[c]);
    }
    // Each thread takes every kThreads-th client, in an order that changes from tick to tick.
    std::vector<std::thread> threads;
    for (std::uint32_t th = 0; th < kThreads; ++th) {
      threads.emplace_back([&, th] {
        for (std::uint32_t j = 0; j < kClients / kThreads; ++j) {
          const std::uint32_t c = ((j + t) % (kClients / kThreads)) * kThreads + th;
          const auto [cx, cy] = camera(c, t);
          par_stats[c] = parallel.build((c + 1) * 7, cx, cy, par_out[c], scratch[th]);
        }
      });
    }
    for (auto& th : threads) th.join();
    for (std::uint32_t c = 0; c < kClients; ++c) {
      expect_same(seq_out[c], par_out[c], t, c);
      EXPECT_EQ(seq_stats[c].in_view, par_stats[c].in_view);
      EXPECT_EQ(seq_stats[c].sent, par_stats[c].sent);
      EXPECT_EQ(seq_stats[c].skipped_unchanged, par_stats[c].skipped_unchanged);
      EXPECT_EQ(seq_stats[c].view_error_max_m, par_stats[c].view_error_max_m);
      EXPECT_EQ(seq_stats[c].view_error_mean_m, par_stats[c].view_error_mean_m);
      EXPECT_GT(seq_stats[c].in_view, 200u);
      EXPECT_GT(seq_stats[c].sent, 30u);  // mixed generations: many id escapes
    }
  }
}

TEST(SnapshotBuilderThreads, ScratchIsReusableAcrossBuildersAndClients) {
  std::mt19937_64 rng(3);
  const Crowd crowd = Crowd::make(rng, 800, 60.0, 1);
  SnapshotBuilder a(InterestConfig{}), b(InterestConfig{});
  a.add_client(1);
  b.add_client(1);
  b.add_client(2);
  a.index(crowd.view(), 1);
  b.index(crowd.view(), 1);
  SnapshotBuilder::Scratch shared;
  protocol::Snapshot sa, sb, sb2;
  const BuildStats st = a.build(1, 0.0, 0.0, sa, shared);
  b.build(2, 5.0, 5.0, sb2, shared);
  b.build(1, 0.0, 0.0, sb);  // the builder's own scratch
  expect_same(sa, sb, 1, 1);
  EXPECT_EQ(st.sent, static_cast<std::uint32_t>(sa.x.size()));
}

// The builder writes the pose arrays itself; they must be what encode_poses makes of the poses a
// client decodes from them, at 1 mm and at coarser units, with id escapes.
TEST(SnapshotBuilderWire, PoseArraysAreWhatEncodePosesWrites) {
  std::mt19937_64 rng(23);
  for (const double radius : {30.0, 120.0, 0.0}) {
    InterestConfig cfg;
    cfg.radius_m = radius;
    cfg.budget_bytes = radius == 30.0 ? 1066 : 0;
    SnapshotBuilder sb(cfg);
    sb.add_client(1);
    Crowd crowd = Crowd::make(rng, 3000, radius == 0.0 ? 900.0 : 200.0, 4);
    crowd.z[3] = 40.0;  // above the 1 mm height range: clamped on the wire
    protocol::Snapshot snap, again;
    std::size_t poses = 0;
    for (std::uint64_t t = 1; t <= 20; ++t) {
      crowd.step(rng, 1.0 / 30.0);
      sb.index(crowd.view(), t);
      sb.build(1, 3.0 * static_cast<double>(t) * 0.1, -1.0, snap);
      std::vector<protocol::Pose> decoded;
      protocol::decode_poses(snap, decoded);
      ASSERT_TRUE(protocol::encode_poses(decoded, snap.origin_x_mm, snap.origin_y_mm, snap.unit_mm, again));
      EXPECT_EQ(snap.id_codes, again.id_codes) << "radius " << radius << " tick " << t;
      EXPECT_EQ(snap.x, again.x) << "radius " << radius << " tick " << t;
      EXPECT_EQ(snap.y, again.y) << "radius " << radius << " tick " << t;
      EXPECT_EQ(snap.z, again.z) << "radius " << radius << " tick " << t;
      EXPECT_EQ(snap.yaw, again.yaw) << "radius " << radius << " tick " << t;
      poses += decoded.size();
    }
    EXPECT_GT(poses, 500u) << "radius " << radius;
  }
}

}  // namespace
}  // namespace throng::match
