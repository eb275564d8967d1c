// The contact-pairs debug channel (protocol/README.md, "Contact pairs"): a ContactPairs sample
// crosses DDS unchanged, in the client's own partition only, its size is what
// contact_pairs_wire_bytes() says, and the quantization keeps a push ratio to 1/65535.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>

#include "message_equality.h"
#include "throng/protocol/contacts.h"
#include "throng/protocol/dds_transport.h"
#include "transport_test_util.h"

namespace throng::protocol {
namespace {

using test::Inbox;
using test::loopback;

ContactPairs pairs_for(std::uint32_t client, std::uint64_t tick, std::size_t n) {
  ContactPairs c;
  c.client_id = client;
  c.tick = tick;
  c.pairs_near = static_cast<std::uint32_t>(n + 5);
  c.camera_x = 12.25f;
  c.camera_y = -3.5f;
  c.radius_m = 12.0f;
  for (std::size_t i = 0; i < n; ++i)
    push_contact(c, 100 + static_cast<std::uint32_t>(i), 70'000 + static_cast<std::uint32_t>(i), 0.05 + 0.09 * i,
                 0.001 * i, 0.0007 * i);
  return c;
}

TEST(ContactPairs, QuantizationKeepsTheRatioAndSaturates) {
  for (double s : {1e-6, 0.3, 0.5, 0.7, 0.999}) EXPECT_NEAR(dequantize_share(quantize_share(s)), s, 0.5 / kShareScale);
  EXPECT_EQ(quantize_share(-1.0), 0u);
  EXPECT_EQ(quantize_share(2.0), 65535u);
  EXPECT_EQ(quantize_share(std::numeric_limits<double>::quiet_NaN()), 0u);
  EXPECT_NEAR(dequantize_contact_m(quantize_contact_m(0.01234)), 0.01234, 0.5 * kContactUnitM);
  EXPECT_EQ(quantize_contact_m(100.0), 65535u);
  EXPECT_EQ(quantize_contact_m(-0.1), 0u);
}

TEST(ContactPairs, CheckRejectsMalformedMessages) {
  EXPECT_FALSE(check_contact_pairs(pairs_for(1, 1, 3)).has_value());
  ContactPairs c = pairs_for(1, 1, 3);
  c.push.pop_back();
  EXPECT_TRUE(check_contact_pairs(c).has_value());
  c = pairs_for(1, 1, 3);
  c.pairs_near = 2;
  EXPECT_TRUE(check_contact_pairs(c).has_value());
  c = pairs_for(1, 1, 3);
  c.b[1] = 0;
  EXPECT_TRUE(check_contact_pairs(c).has_value());
  c = pairs_for(1, 1, 3);
  c.camera_x = std::numeric_limits<float>::infinity();
  EXPECT_TRUE(check_contact_pairs(c).has_value());
}

TEST(DdsContacts, RoundTripInTheClientsPartitionWithTheComputedWireSize) {
  ServerTransport server(loopback(122, "server"));
  server.start({});
  EXPECT_EQ(server.publish_contacts(pairs_for(1, 1, 2)), 0u) << "no channel open for client 1 yet";
  server.open_client_channel(1, "c1");
  server.open_client_channel(2, "c2");

  Inbox<std::pair<ContactPairs, std::size_t>> got1, got2, snapshots1;
  ClientTransport client(loopback(122, "viewer"));
  client.start({});
  client.subscribe_contacts(1, "c1", [&](ContactPairs&& c, std::size_t bytes) { got1.push({std::move(c), bytes}); });
  client.subscribe_contacts(2, "c2", [&](ContactPairs&& c, std::size_t bytes) { got2.push({std::move(c), bytes}); });
  client.subscribe_snapshots(1, "c1", [&](Snapshot&&, std::size_t) { snapshots1.push({}); });

  std::uint64_t tick = 0;
  std::uint64_t sent_bytes = 0, sent = 0;
  ASSERT_TRUE(test::send_until(
      [&] {
        ++tick;
        const ContactPairs c = pairs_for(1, tick, tick % 4);  // odd and even counts: padding
        const std::size_t bytes = server.publish_contacts(c);
        EXPECT_EQ(bytes, contact_pairs_wire_bytes(c)) << tick % 4 << " pairs";
        sent_bytes += bytes;
        ++sent;
      },
      [&](std::chrono::milliseconds t) { return got1.wait_until([](const auto& v) { return v.size() >= 4; }, t); }));
  for (const auto& [c, bytes] : got1.items()) {
    test::expect_same(c, pairs_for(1, c.tick, c.tick % 4));
    // The reader's payload is padded to a multiple of 4 (RTPS); the writer counts the serialized size.
    EXPECT_EQ(bytes, (contact_pairs_wire_bytes(c) + 3) / 4 * 4);
    EXPECT_FALSE(check_contact_pairs(c).has_value());
  }
  EXPECT_EQ(got2.size(), 0u) << "client 2 never asked: nothing on its partition";
  EXPECT_EQ(snapshots1.size(), 0u) << "contacts are their own topic, not snapshots";
  const TransportCounters counters = server.counters();
  EXPECT_EQ(counters.contacts_samples, sent);
  EXPECT_EQ(counters.contacts_bytes, sent_bytes);
  EXPECT_EQ(counters.snapshot_samples, 0u);

  // The sizes protocol/README.md quotes: 56 bytes empty, 14 a pair, 4 of padding for an odd count.
  EXPECT_EQ(contact_pairs_wire_bytes(pairs_for(1, 1, 0)), 56u);
  EXPECT_EQ(contact_pairs_wire_bytes(pairs_for(1, 1, 32)), 56u + 14u * 32u);
  EXPECT_EQ(contact_pairs_wire_bytes(pairs_for(1, 1, 1)), 56u + 14u + 4u);

  // Closing the channel stops the contacts too.
  server.close_client_channel(1);
  EXPECT_EQ(server.publish_contacts(pairs_for(1, 999, 1)), 0u);
}

}  // namespace
}  // namespace throng::protocol
