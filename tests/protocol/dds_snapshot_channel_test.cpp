// Per-client snapshot channels: each client's snapshots travel in its own DDS partition, so a
// subscription only ever sees its own client's samples; closing a channel stops delivery.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

#include "message_equality.h"
#include "throng/protocol/codec.h"
#include "throng/protocol/dds_transport.h"
#include "transport_test_util.h"

namespace throng::protocol {
namespace {

using test::Inbox;
using test::loopback;

struct Received {
  Snapshot snapshot;
  std::size_t wire_bytes = 0;
};

// A snapshot for one client whose content depends on the client and the tick.
Snapshot snapshot_for(std::uint32_t client_id, std::uint64_t tick) {
  Snapshot s;
  s.client_id = client_id;
  s.tick = tick;
  s.last_applied_sequence = static_cast<std::uint32_t>(tick * 2);
  s.last_applied_tick = tick - 1;
  s.entity = 500 + client_id;
  s.entity_x = 1.5f * client_id, s.entity_y = -2.25f, s.entity_z = 0.125f, s.entity_yaw = 3.0f;
  s.objects_in_view = 40 + client_id;
  std::vector<Pose> poses;
  for (std::uint32_t i = 0; i < 10 + client_id; ++i)
    poses.push_back(Pose{client_id * 1000 + i * 7, 0.001 * i, -0.002 * i, 1.0, 0.1 * i});
  EXPECT_TRUE(encode_poses(poses, 1000 * static_cast<std::int32_t>(client_id), -2000, 1, s));
  s.removed = {client_id, client_id + 1};
  return s;
}

std::function<void(Snapshot&&, std::size_t)> into(Inbox<Received>& inbox) {
  return [&inbox](Snapshot&& s, std::size_t bytes) { inbox.push(Received{std::move(s), bytes}); };
}

TEST(DdsSnapshotChannel, EachClientReceivesOnlyItsOwnPartition) {
  ServerTransport server(loopback(115, "server"));
  server.start({});
  server.open_client_channel(1, "c1");
  server.open_client_channel(2, "c2");
  server.open_client_channel(2, "c-other");  // already open: no-op

  // Two clients multiplexed on one participant, a third client on its own participant, and a
  // subscription to a partition nobody writes.
  Inbox<Received> got1, got2, got2_viewer, got3;
  ClientTransport bots(loopback(115, "bots"));
  ClientTransport viewer(loopback(115, "viewer"));
  bots.start({});
  viewer.start({});
  bots.subscribe_snapshots(1, "c1", into(got1));
  bots.subscribe_snapshots(2, "c2", into(got2));
  bots.subscribe_snapshots(3, "c3", into(got3));
  viewer.subscribe_snapshots(2, "c2", into(got2_viewer));

  std::uint64_t tick = 0;
  std::vector<std::size_t> sent_bytes;
  auto publish_round = [&] {
    ++tick;
    for (std::uint32_t client : {1u, 2u}) {
      const Snapshot s = snapshot_for(client, tick);
      const std::size_t bytes = server.publish_snapshot(s);
      EXPECT_EQ(bytes, snapshot_wire_bytes(s));
      sent_bytes.push_back(bytes);
    }
    EXPECT_EQ(server.publish_snapshot(snapshot_for(3, tick)), 0u) << "client 3 has no channel";
  };
  ASSERT_TRUE(test::send_until(publish_round, [&](std::chrono::milliseconds t) {
    return got1.wait_for_count(3, t) && got2.wait_for_count(3, t) && got2_viewer.wait_for_count(3, t);
  }));

  for (const auto& [inbox, client] : {std::pair{&got1, 1u}, std::pair{&got2, 2u}, std::pair{&got2_viewer, 2u}}) {
    SCOPED_TRACE("client " + std::to_string(client));
    for (const Received& r : inbox->items()) {
      ASSERT_EQ(r.snapshot.client_id, client);
      test::expect_same(r.snapshot, snapshot_for(client, r.snapshot.tick));
      EXPECT_EQ(r.wire_bytes, snapshot_wire_bytes(r.snapshot));
      std::vector<Pose> poses;
      decode_poses(r.snapshot, poses);
      EXPECT_EQ(poses.size(), 10u + client);
    }
  }
  EXPECT_EQ(got3.size(), 0u);

  const TransportCounters c = server.counters();
  EXPECT_EQ(c.snapshot_samples, sent_bytes.size());
  std::uint64_t total = 0;
  for (std::size_t b : sent_bytes) total += b;
  EXPECT_EQ(c.snapshot_bytes, total);
  EXPECT_EQ(c.other_samples, 0u);
}

TEST(DdsSnapshotChannel, CloseStopsDeliveryAndReopenResumesIt) {
  ServerTransport server(loopback(116, "server"));
  server.start({});
  server.open_client_channel(4, "c4");
  Inbox<Received> got;
  ClientTransport client(loopback(116, "client"));
  client.start({});
  client.subscribe_snapshots(4, "c4", into(got));

  std::uint64_t tick = 0;
  ASSERT_TRUE(test::send_until([&] { server.publish_snapshot(snapshot_for(4, ++tick)); },
                               [&](std::chrono::milliseconds t) { return got.wait_for_count(1, t); }));

  server.close_client_channel(4);
  server.close_client_channel(4);   // unknown now: no-op
  server.close_client_channel(99);  // never opened: no-op
  const std::uint64_t last_tick_before_close = tick;
  const TransportCounters before = server.counters();
  for (int i = 0; i < 20; ++i) EXPECT_EQ(server.publish_snapshot(snapshot_for(4, ++tick)), 0u);
  EXPECT_EQ(server.counters().snapshot_samples, before.snapshot_samples);
  // Nothing written after the close may arrive; give a stray sample time to show up.
  EXPECT_FALSE(got.wait_until(
      [&](const std::vector<Received>& items) {
        for (const Received& r : items)
          if (r.snapshot.tick > last_tick_before_close) return true;
        return false;
      },
      std::chrono::milliseconds(500)));

  server.open_client_channel(4, "c4");
  const std::uint64_t reopened_after = tick;
  ASSERT_TRUE(test::send_until([&] { server.publish_snapshot(snapshot_for(4, ++tick)); },
                               [&](std::chrono::milliseconds t) {
                                 return got.wait_until(
                                     [&](const std::vector<Received>& items) {
                                       return items.back().snapshot.tick > reopened_after;
                                     },
                                     t);
                               }));
}

TEST(DdsSnapshotChannel, UnsubscribeStopsAndResubscribeReplacesTheHandler) {
  ServerTransport server(loopback(117, "server"));
  server.start({});
  server.open_client_channel(5, "c5");
  server.open_client_channel(6, "c6");
  Inbox<Received> first, second, moved;
  ClientTransport client(loopback(117, "client"));
  client.start({});
  client.subscribe_snapshots(5, "c5", into(first));

  std::uint64_t tick = 0;
  auto publish_both = [&] {
    ++tick;
    server.publish_snapshot(snapshot_for(5, tick));
    server.publish_snapshot(snapshot_for(6, tick));
  };
  ASSERT_TRUE(test::send_until(publish_both, [&](std::chrono::milliseconds t) { return first.wait_for_count(1, t); }));

  // Same client, same partition: only the handler changes.
  client.subscribe_snapshots(5, "c5", into(second));
  const std::size_t first_count = first.size();
  ASSERT_TRUE(test::send_until(publish_both, [&](std::chrono::milliseconds t) { return second.wait_for_count(1, t); }));
  EXPECT_LE(first.size(), first_count + 1) << "at most one sample already in the old handler";

  // Same client, another partition: the subscription follows it.
  client.subscribe_snapshots(5, "c6", into(moved));
  ASSERT_TRUE(test::send_until(publish_both, [&](std::chrono::milliseconds t) {
    return moved.wait_until(
        [](const std::vector<Received>& items) { return !items.empty() && items.back().snapshot.client_id == 6; }, t);
  }));

  client.unsubscribe_snapshots(5);
  client.unsubscribe_snapshots(5);  // no longer subscribed: no-op
  const std::size_t after = moved.size();
  for (int i = 0; i < 10; ++i) publish_both();
  EXPECT_FALSE(moved.wait_for_count(after + 1, std::chrono::milliseconds(300)));
}

}  // namespace
}  // namespace throng::protocol
