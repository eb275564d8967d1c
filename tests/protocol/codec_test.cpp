// The snapshot codec (protocol/wire/codec.h): quantization error bounds, id escape coding,
// rejection of malformed or unencodable input, and the wire-size formula against the real
// serialized size of the generated DDS type.
#include "throng/protocol/codec.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include "throng/protocol/dds_transport.h"
#include "transport_test_util.h"

namespace throng::protocol {
namespace {

// Angular distance in [0, pi].
double yaw_error(double a, double b) {
  const double d = std::remainder(a - b, 2.0 * kPi);
  return std::abs(d);
}

std::vector<Pose> decode(const Snapshot& s) {
  std::vector<Pose> out;
  decode_poses(s, out);
  return out;
}

Snapshot encoded(const std::vector<Pose>& poses, std::int32_t ox = 0, std::int32_t oy = 0, std::uint16_t unit = 1) {
  Snapshot s;
  EXPECT_TRUE(encode_poses(poses, ox, oy, unit, s));
  return s;
}

TEST(Codec, RandomPosesRoundTripWithinHalfAUnitAndPiOver256) {
  std::mt19937_64 rng(20240611);
  const std::uint16_t units[] = {1, 2, 5, 37, 1000};
  // Floating-point slack on the bounds: far below a millimetre, far below a yaw step.
  const double kSlack = 1e-9;
  for (const std::uint16_t unit : units) {
    std::uniform_int_distribution<std::int32_t> origin(-5'000'000, 5'000'000);
    const std::int32_t ox = origin(rng), oy = origin(rng);
    const double range = offset_range_m(unit);
    std::uniform_real_distribution<double> offset(-range, range);
    std::uniform_real_distribution<double> yaw(-4.0 * kPi, 4.0 * kPi);
    std::vector<Pose> poses;
    std::uint32_t id = 0;
    for (int i = 0; i < 2000; ++i) {
      id += 1 + static_cast<std::uint32_t>(rng() % 3);
      poses.push_back(Pose{id, ox / 1000.0 + offset(rng), oy / 1000.0 + offset(rng), offset(rng), yaw(rng)});
    }
    // Range edges: the last representable offset on each side, and yaw at the seam.
    const double edge = 32767.0 * unit / 1000.0;
    poses.push_back(Pose{++id, ox / 1000.0 + edge, oy / 1000.0 - edge, edge, kPi});
    poses.push_back(Pose{++id, ox / 1000.0 - edge, oy / 1000.0 + edge, -edge, -kPi});
    poses.push_back(Pose{++id, ox / 1000.0, oy / 1000.0, 0.0, 2.0 * kPi - 1e-12});

    Snapshot s;
    ASSERT_TRUE(encode_poses(poses, ox, oy, unit, s)) << "unit " << unit;
    const std::vector<Pose> back = decode(s);
    ASSERT_EQ(back.size(), poses.size());
    const double bound_m = unit / 2000.0 + kSlack;
    for (std::size_t i = 0; i < poses.size(); ++i) {
      EXPECT_EQ(back[i].id, poses[i].id);
      EXPECT_LE(std::abs(back[i].x - poses[i].x), bound_m) << "unit " << unit << " pose " << i;
      EXPECT_LE(std::abs(back[i].y - poses[i].y), bound_m) << "unit " << unit << " pose " << i;
      EXPECT_LE(std::abs(back[i].z - poses[i].z), bound_m) << "unit " << unit << " pose " << i;
      EXPECT_LE(yaw_error(back[i].yaw, poses[i].yaw), kPi / 256.0 + kSlack) << "unit " << unit << " pose " << i;
      EXPECT_GT(back[i].yaw, -kPi);
      EXPECT_LE(back[i].yaw, kPi);
    }
  }
}

TEST(Codec, OffsetJustInsideAndJustOutsideTheRange) {
  // 32767.4 units rounds to 32767 (fits); 32767.6 rounds to 32768 (does not).
  EXPECT_EQ(quantize_offset(32.7674, 0, 1), std::optional<std::int16_t>(32767));
  EXPECT_EQ(quantize_offset(-32.7674, 0, 1), std::optional<std::int16_t>(-32767));
  EXPECT_FALSE(quantize_offset(32.7676, 0, 1).has_value());
  EXPECT_FALSE(quantize_offset(-32.7676, 0, 1).has_value());
  EXPECT_EQ(quantize_offset(1.0 + 32.7674 * 5, 1000, 5), std::optional<std::int16_t>(32767));
  EXPECT_FALSE(quantize_offset(0.0, 0, 0).has_value());
}

TEST(Codec, IdsAreDeltaCodedWithEscapesForLargeDeltasAndHighBits) {
  const std::uint32_t generation_bit = 0x8000'0000u;
  const std::vector<Pose> poses = {
      {1}, {2}, {65537},             // delta 65535: still one code
      {131073},                      // delta 65536: escape
      {131074},
      {generation_bit | 5u},         // generation bits set: escape
      {generation_bit | 6u},
      {0xFFFF'FFFFu},                // largest id
  };
  const Snapshot s = encoded(poses);
  const std::vector<std::uint16_t> expected_codes = {
      1, 1, 65535, 0, 0x0002, 0x0001, 1, 0, 0x8000, 0x0005, 1, 0, 0xFFFF, 0xFFFF};
  EXPECT_EQ(s.id_codes, expected_codes);
  const std::vector<Pose> back = decode(s);
  ASSERT_EQ(back.size(), poses.size());
  for (std::size_t i = 0; i < poses.size(); ++i) EXPECT_EQ(back[i].id, poses[i].id) << "pose " << i;
}

TEST(Codec, FirstIdZeroIsEscaped) {
  const Snapshot s = encoded({{0}, {3}});
  EXPECT_EQ(s.id_codes, (std::vector<std::uint16_t>{0, 0, 0, 3}));
  const std::vector<Pose> back = decode(s);
  ASSERT_EQ(back.size(), 2u);
  EXPECT_EQ(back[0].id, 0u);
  EXPECT_EQ(back[1].id, 3u);
}

TEST(Codec, EqualHeightsTravelAsOneSharedValue) {
  // Two or more poses at one quantized height: z holds it once, and every pose decodes to it.
  const std::vector<Pose> flat = {{3, 1.0, 2.0, 0.9004, 0.0}, {9, -1.0, 0.5, 0.9, 1.0}, {12, 0.0, 0.0, 0.8996, -1.0}};
  Snapshot s;
  ASSERT_TRUE(encode_poses(flat, 0, 0, 1, s));
  ASSERT_EQ(s.z.size(), 1u);
  EXPECT_EQ(s.z[0], 900);
  std::vector<Pose> back;
  decode_poses(s, back);
  ASSERT_EQ(back.size(), 3u);
  for (const Pose& p : back) EXPECT_DOUBLE_EQ(p.z, 0.9) << p.id;
  EXPECT_DOUBLE_EQ(back[1].x, -1.0);

  // One height differs: one z per pose, as before.
  std::vector<Pose> mixed = flat;
  mixed[2].z = 1.6;
  ASSERT_TRUE(encode_poses(mixed, 0, 0, 1, s));
  EXPECT_EQ(s.z.size(), 3u);
  back.clear();
  decode_poses(s, back);
  EXPECT_DOUBLE_EQ(back[2].z, 1.6);

  // A single pose has one z either way; no poses, no z.
  ASSERT_TRUE(encode_poses(std::span<const Pose>(flat.data(), 1), 0, 0, 1, s));
  EXPECT_EQ(s.z.size(), 1u);
  ASSERT_TRUE(encode_poses({}, 0, 0, 1, s));
  EXPECT_TRUE(s.z.empty());

  // share_equal_heights is what encode_poses ends with.
  Snapshot manual;
  manual.z = {5, 5, 5, 5};
  share_equal_heights(manual);
  EXPECT_EQ(manual.z, std::vector<std::int16_t>{5});
  manual.z = {5, 5, 6};
  share_equal_heights(manual);
  EXPECT_EQ(manual.z.size(), 3u);
}

TEST(Codec, DecodeRejectsMalformedSnapshots) {
  const Snapshot good = encoded({{10}, {20}, {30}});
  std::vector<Pose> out;

  Snapshot lengths = good;
  lengths.yaw.pop_back();
  EXPECT_THROW(decode_poses(lengths, out), DecodeError);

  Snapshot z_long = good;  // three poses at one height: z is the one shared value
  ASSERT_EQ(z_long.z.size(), 1u);
  z_long.z.push_back(0);      // two heights for three poses
  EXPECT_THROW(decode_poses(z_long, out), DecodeError);
  Snapshot z_four = good;
  z_four.z.assign(4, 0);      // more heights than poses
  EXPECT_THROW(decode_poses(z_four, out), DecodeError);
  Snapshot z_none = good;
  z_none.z.clear();           // no height for three poses
  EXPECT_THROW(decode_poses(z_none, out), DecodeError);
  Snapshot z_without_poses;   // a height with no poses
  z_without_poses.unit_mm = 1;
  z_without_poses.z = {0};
  EXPECT_THROW(decode_poses(z_without_poses, out), DecodeError);

  Snapshot truncated_escape = good;
  truncated_escape.id_codes = {10, 10, 0, 1};  // the third pose's escape lacks its low half
  EXPECT_THROW(decode_poses(truncated_escape, out), DecodeError);

  Snapshot extra_codes = good;
  extra_codes.id_codes.push_back(7);
  EXPECT_THROW(decode_poses(extra_codes, out), DecodeError);

  Snapshot too_few_codes = good;
  too_few_codes.id_codes.pop_back();
  EXPECT_THROW(decode_poses(too_few_codes, out), DecodeError);

  Snapshot not_ascending = good;
  not_ascending.id_codes = {10, 10, 0, 0, 15};  // escape back to id 15 after 20
  EXPECT_THROW(decode_poses(not_ascending, out), DecodeError);

  Snapshot repeated = good;
  repeated.id_codes = {10, 10, 0, 0, 20};  // escape to the same id again
  EXPECT_THROW(decode_poses(repeated, out), DecodeError);

  Snapshot overflow;
  ASSERT_TRUE(encode_poses(std::vector<Pose>{{0xFFFF'FFF0u}, {0xFFFF'FFFFu}}, 0, 0, 1, overflow));
  overflow.id_codes = {0, 0xFFFF, 0xFFF0, 0xFFFF};  // 0xFFFFFFF0 + 65535 wraps past 2^32
  EXPECT_THROW(decode_poses(overflow, out), DecodeError);

  Snapshot unit_zero = good;
  unit_zero.unit_mm = 0;
  EXPECT_THROW(decode_poses(unit_zero, out), DecodeError);

  // A well-formed snapshot still decodes after all that.
  EXPECT_NO_THROW(decode_poses(good, out));
}

TEST(Codec, EncodeRefusesOutOfRangeAndNonFiniteAndLeavesArraysEmpty) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const std::vector<std::vector<Pose>> refused = {
      {{1, 40.0, 0, 0, 0}},             // x beyond +-32.767 m at 1 mm
      {{1, 0, -40.0, 0, 0}},            // y
      {{1, 0, 0, 33.0, 0}},             // z (absolute)
      {{1, 0, 0, 0, 0}, {2, nan, 0, 0, 0}},
      {{1, 0, 0, inf, 0}},
      {{1, 0, 0, 0, nan}},              // yaw
      {{1, 0, 0, 0, -inf}},
  };
  for (std::size_t i = 0; i < refused.size(); ++i) {
    Snapshot s;
    s.id_codes = {9};  // stale content must be cleared
    s.x = {9};
    EXPECT_FALSE(encode_poses(refused[i], 0, 0, 1, s)) << "case " << i;
    EXPECT_TRUE(s.id_codes.empty() && s.x.empty() && s.y.empty() && s.z.empty() && s.yaw.empty()) << "case " << i;
  }
  // The same x fits once the origin moves next to it.
  Snapshot s;
  EXPECT_TRUE(encode_poses(std::vector<Pose>{{1, 40.0, 0, 0, 0}}, 40'000, 0, 1, s));
  EXPECT_EQ(s.x, (std::vector<std::int16_t>{0}));
}

TEST(Codec, EncodeRejectsUnsortedOrDuplicateIds) {
  Snapshot s;
  EXPECT_THROW(encode_poses(std::vector<Pose>{{5}, {4}}, 0, 0, 1, s), std::invalid_argument);
  EXPECT_THROW(encode_poses(std::vector<Pose>{{5}, {5}}, 0, 0, 1, s), std::invalid_argument);
}

// snapshot_wire_bytes() must equal what DDS really serializes: publish_snapshot returns the
// payload length measured inside the type's serialize().
TEST(Codec, WireBytesEqualsSerializedSizeOfTheDdsType) {
  ServerTransport server(test::loopback(110, "codec-wire-size"));
  server.open_client_channel(7, "c7");

  std::mt19937_64 rng(7);
  for (const std::size_t n : {0u, 1u, 2u, 3u, 100u, 1001u}) {
    std::vector<Pose> poses;
    std::uint32_t id = 0;
    for (std::size_t i = 0; i < n; ++i) {
      id += (i % 17 == 3) ? 70'000u : 1u + static_cast<std::uint32_t>(rng() % 4);  // some escapes
      poses.push_back(Pose{id, (rng() % 20000) / 1000.0, (rng() % 20000) / 1000.0, 1.0, 0.5});
    }
    Snapshot s;
    s.client_id = 7;
    s.tick = 1000 + n;
    ASSERT_TRUE(encode_poses(poses, 0, 0, 1, s));
    for (std::size_t r = 0; r < n % 5; ++r) s.removed.push_back(static_cast<std::uint32_t>(r * 3 + 1));
    const std::size_t wire = server.publish_snapshot(s);
    EXPECT_EQ(wire, snapshot_wire_bytes(s)) << n << " poses, " << s.id_codes.size() << " codes, "
                                            << s.removed.size() << " removed";
    if (n == 0) {
      EXPECT_EQ(wire, 96u) << "header: 68 bytes of fields + 6 sequence lengths + 4 encapsulation";
    }
  }

  // The figures protocol/README.md quotes: 100 poses with ascending ids at different heights cost
  // 96 + 9 * 100 bytes; on flat ground (one shared height) 96 + 7 * 100 + 4 (the shared z and the
  // padding before yaw).
  std::vector<Pose> hundred;
  for (std::uint32_t id = 1; id <= 100; ++id) hundred.push_back(Pose{id * 5, 0.5, -0.5, 0.001 * id, 1.0});
  Snapshot s;
  s.client_id = 7;
  ASSERT_TRUE(encode_poses(hundred, 0, 0, 1, s));
  ASSERT_EQ(s.z.size(), 100u);
  const std::size_t wire = server.publish_snapshot(s);
  EXPECT_EQ(wire, 996u);
  ::testing::Test::RecordProperty("snapshot_100_poses_bytes", static_cast<int>(wire));
  for (Pose& p : hundred) p.z = 0.9;
  ASSERT_TRUE(encode_poses(hundred, 0, 0, 1, s));
  ASSERT_EQ(s.z.size(), 1u);
  const std::size_t flat = server.publish_snapshot(s);
  EXPECT_EQ(flat, 800u);
  EXPECT_EQ(flat, snapshot_wire_bytes(s));
  ::testing::Test::RecordProperty("snapshot_100_flat_poses_bytes", static_cast<int>(flat));
}

}  // namespace
}  // namespace throng::protocol
