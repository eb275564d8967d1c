// Writer -> reader round trips: random inputs come back bit for bit under every writer setting;
// seeking; the same inputs give the same file apart from the header's wall-clock time.
#include <nlohmann/json.hpp>
#include <gtest/gtest.h>

#include <algorithm>

#include "matchlog_test_util.h"
#include "throng/matchlog/crc32c.h"
#include "throng/matchlog/log_header.h"
#include "throng/matchlog/reader.h"
#include "throng/matchlog/tick_record.h"

namespace throng::matchlog {
namespace {

struct Setting {
  std::uint32_t block_ticks;
  int zstd_level;
  std::uint32_t index_interval;
};
void PrintTo(const Setting& s, std::ostream* os) {
  *os << "block " << s.block_ticks << ", zstd " << s.zstd_level << ", index " << s.index_interval;
}

class RoundTrip : public ::testing::TestWithParam<Setting> {};

TEST_P(RoundTrip, RandomInputsComeBackBitExact) {
  const Setting s = GetParam();
  const auto path = test::test_dir() / "random.tlog";
  WriterOptions o;
  o.block_ticks = s.block_ticks;
  o.zstd_level = s.zstd_level;
  o.index_interval_ticks = s.index_interval;
  const auto written = test::write_random_log(path, 307, o, 11);

  MatchLogReader r(path.string());
  EXPECT_EQ(r.header().match_id, "random");
  EXPECT_EQ(r.header().build_id, "test-build");
  EXPECT_EQ(r.header().format_version, kFormatVersion);
  EXPECT_TRUE(r.header().scene == test::small_battle(50));
  EXPECT_EQ(r.header().config.tick_hz, 30u);
  EXPECT_EQ(r.header().writer.block_ticks, s.block_ticks);
  EXPECT_TRUE(r.scan().scene_hash_matches);
  EXPECT_EQ(r.scan().end, LogEnd::closed) << r.scan().problem;
  EXPECT_TRUE(r.scan().problem.empty());
  EXPECT_EQ(r.scan().ticks, 307u);
  EXPECT_EQ(r.scan().first_tick, 1u);
  EXPECT_EQ(r.scan().last_tick, 307u);
  EXPECT_EQ(r.scan().end_last_tick, 307u);
  EXPECT_EQ(r.scan().end_ticks_written, 307u);
  EXPECT_EQ(r.scan().blocks.size(), (307 + s.block_ticks - 1) / s.block_ticks);
  // Periodic index records plus the final one.
  const std::uint32_t interval = (s.index_interval + s.block_ticks - 1) / s.block_ticks * s.block_ticks;
  EXPECT_EQ(r.scan().index_records, (interval == 0 ? 0 : 307 / interval) + 1);

  TickRecord t;
  std::size_t n = 0;
  while (r.next(t)) {
    ASSERT_LT(n, written.size());
    const TickRecord& w = written[n];
    ASSERT_EQ(t.tick, w.tick);
    ASSERT_EQ(t.state_hash, w.state_hash);
    ASSERT_EQ(t.flags, w.flags);
    test::expect_same_inputs(t.inputs, w.inputs, w.tick);
    ++n;
  }
  EXPECT_EQ(n, written.size());

  // Seek to every tick (and past the end).
  for (std::uint64_t tick : {1ull, 2ull, 15ull, 16ull, 59ull, 60ull, 61ull, 200ull, 306ull, 307ull}) {
    ASSERT_TRUE(r.seek(tick));
    ASSERT_TRUE(r.next(t));
    EXPECT_EQ(t.tick, tick);
    test::expect_same_inputs(t.inputs, written[tick - 1].inputs, tick);
    const BlockInfo* b = r.find_block(tick);
    ASSERT_NE(b, nullptr);
    EXPECT_LE(b->first_tick, tick);
    EXPECT_LT(tick, b->first_tick + b->tick_count);
  }
  EXPECT_FALSE(r.seek(308));
  EXPECT_FALSE(r.next(t));
  EXPECT_EQ(r.find_block(308), nullptr);
  EXPECT_EQ(r.find_block(0), nullptr);
}

INSTANTIATE_TEST_SUITE_P(Settings, RoundTrip,
                         ::testing::Values(Setting{15, 3, 60}, Setting{1, 0, 10}, Setting{7, 1, 30}, Setting{64, 9, 64},
                                           Setting{15, 0, 0}),
                         [](const ::testing::TestParamInfo<Setting>& i) {
                           return "block" + std::to_string(i.param.block_ticks) + "_zstd" + std::to_string(i.param.zstd_level) +
                                  "_index" + std::to_string(i.param.index_interval);
                         });

TEST(RoundTrip, EmptyTicksAndEmptyLog) {
  const auto dir = test::test_dir();
  {
    MatchLogWriter w((dir / "none.tlog").string());
    LogHeader h;
    h.match_id = "none";
    h.scene = test::small_battle(20);
    h.config = test::small_config();
    w.begin(h);
    w.close();
  }
  MatchLogReader r((dir / "none.tlog").string());
  EXPECT_EQ(r.scan().ticks, 0u);
  EXPECT_EQ(r.scan().end, LogEnd::closed);
  EXPECT_FALSE(r.header().build_id.empty());  // default build id
  TickRecord t;
  EXPECT_FALSE(r.next(t));
  EXPECT_FALSE(r.seek(1));
}

// The header record's payload as JSON, without its wall-clock fields.
nlohmann::json header_without_time(const std::vector<std::uint8_t>& file) {
  const std::uint32_t len = static_cast<std::uint32_t>(file[12]) | static_cast<std::uint32_t>(file[13]) << 8 |
                            static_cast<std::uint32_t>(file[14]) << 16 | static_cast<std::uint32_t>(file[15]) << 24;
  auto j = nlohmann::json::parse(std::string(file.begin() + 17, file.begin() + 17 + len));
  j.erase("start_utc");
  j.erase("start_unix_ms");
  return j;
}

TEST(RoundTrip, SameInputsTwiceGiveTheSameFileApartFromTheHeaderTime) {
  const auto dir = test::test_dir();
  test::write_random_log(dir / "a.tlog", 200, {}, 5);
  std::this_thread::sleep_for(std::chrono::milliseconds(5));  // a different start time
  test::write_random_log(dir / "b.tlog", 200, {}, 5);
  const auto a = test::read_bytes(dir / "a.tlog");
  const auto b = test::read_bytes(dir / "b.tlog");
  ASSERT_EQ(a.size(), b.size());  // the time fields have a fixed width
  MatchLogReader ra((dir / "a.tlog").string());
  const std::size_t header = ra.scan().header_bytes;
  EXPECT_NE(ra.header().start_unix_ms, MatchLogReader((dir / "b.tlog").string()).header().start_unix_ms);
  // Everything after the header record is byte-identical...
  EXPECT_TRUE(std::equal(a.begin() + static_cast<std::ptrdiff_t>(header), a.end(), b.begin() + static_cast<std::ptrdiff_t>(header)));
  // ...and the headers differ only in the start time.
  EXPECT_EQ(header_without_time(a), header_without_time(b));
  std::size_t differing = 0;
  for (std::size_t i = 0; i < header; ++i) differing += a[i] != b[i];
  EXPECT_GT(differing, 0u);
  EXPECT_LE(differing, 4u + 25u);  // the CRC and some digits of the two time fields
}

TEST(RoundTrip, FileBasedParamsArePutInlineAndSimulateTheSame) {
  const std::string data = std::string(THRONG_SOURCE_DIR) + "/server/engine/data/";
  scene::SceneDef s = test::small_battle(60);
  for (auto& g : s.spawns) g.archetype = "infantry";  // archetypes the designers' file defines
  for (auto& sc : s.scenery) sc.archetype = sc.archetype == "bush" ? "bush" : "wall";
  s.params.file = data + "default_params.json";
  s.params.inline_json.clear();
  s.policy.file = data + "default_policy.json";
  s.policy.inline_json.clear();
  const scene::SceneDef inlined = self_contained_scene(s);
  EXPECT_TRUE(inlined.params.file.empty());
  EXPECT_TRUE(nlohmann::json::parse(inlined.params.inline_json).is_object());
  EXPECT_TRUE(inlined.policy.file.empty());
  EXPECT_TRUE(nlohmann::json::parse(inlined.policy.inline_json).is_object());
  match::Match a(s, test::small_config(), "m"), b(inlined, test::small_config(), "m");
  match::Outbox out;
  for (int t = 0; t < 20; ++t) ASSERT_EQ(a.tick(out).state_hash, b.tick(out).state_hash) << t;

  scene::SceneDef missing = s;
  missing.params.file = data + "no_such_file.json";
  EXPECT_THROW(self_contained_scene(missing), LogError);
}

// A tick entry as format version 2 wrote it (no senders): version 2 reads it with zero senders and
// an empty identity; read as version 3 it runs past its end (the layouts really differ).
TEST(RoundTrip, VersionTwoTickEntriesDecodeWithoutSenders) {
  std::vector<std::uint8_t> b;
  auto u8 = [&](std::uint8_t v) { b.push_back(v); };
  auto u32 = [&](std::uint32_t v) { for (int k = 0; k < 4; ++k) u8(static_cast<std::uint8_t>(v >> (8 * k))); };
  auto u64 = [&](std::uint64_t v) { u32(static_cast<std::uint32_t>(v)); u32(static_cast<std::uint32_t>(v >> 32)); };
  u64(7); u64(0xABCDull); u8(0); u32(1); u32(1); u32(0);      // tick 7, hash, flags, 1 join, 1 command
  u64(99); u32(1); u8(0); u32(0); u32(3); b.insert(b.end(), {'b', 'o', 't'});  // join: nonce 99 "bot"
  u32(1); u32(1234); u32(5); u64(6);                          // command: client 1, entity 1234, seq 5
  for (int k = 0; k < 7; ++k) u32(0);                         // move, facing, actions, camera
  TickRecord t;
  std::size_t pos = 0;
  decode_tick(b, pos, t, 2);
  EXPECT_EQ(pos, b.size());
  ASSERT_EQ(t.inputs.joins.size(), 1u);
  ASSERT_EQ(t.inputs.commands.size(), 1u);
  EXPECT_EQ(t.inputs.joins[0].name, "bot");
  EXPECT_EQ(t.inputs.joins[0].sender, protocol::ParticipantKey{});
  EXPECT_TRUE(t.inputs.joins[0].identity.empty());
  EXPECT_EQ(t.inputs.commands[0].entity, 1234u);
  EXPECT_EQ(t.inputs.commands[0].sender, protocol::ParticipantKey{});
  pos = 0;
  EXPECT_THROW(decode_tick(b, pos, t, 3), LogError);
}

// The encoder writes FORMAT.md's little-endian layout (built here byte by byte with shifts, not
// with the codec under test), and a truncated entry names the field it ran out in.
TEST(RoundTrip, EncodedTickEntryHasTheDocumentedLayoutAndTruncationNamesTheField) {
  match::TickInputs in;
  in.commands.resize(1);
  auto& c = in.commands[0];
  c.client_id = 1;
  c.entity = 1234;
  c.sequence = 5;
  c.last_seen_tick = 6;
  c.move_x = 1.5f;
  for (std::size_t k = 0; k < c.sender.bytes.size(); ++k) c.sender.bytes[k] = static_cast<std::uint8_t>(k + 1);
  std::vector<std::uint8_t> got;
  encode_tick(7, in, 0xABCDull, 0, got);

  std::vector<std::uint8_t> want;
  auto u8 = [&](std::uint8_t v) { want.push_back(v); };
  auto u32 = [&](std::uint32_t v) { for (int k = 0; k < 4; ++k) u8(static_cast<std::uint8_t>(v >> (8 * k))); };
  auto u64 = [&](std::uint64_t v) { u32(static_cast<std::uint32_t>(v)); u32(static_cast<std::uint32_t>(v >> 32)); };
  u64(7); u64(0xABCDull); u8(0); u32(0); u32(1); u32(0);    // tick, hash, flags, 0 joins, 1 command, 0 params
  u32(1); u32(1234); u32(5); u64(6);                        // client, entity, sequence, last seen tick
  u32(0x3FC00000u);                                         // move x = 1.5f
  for (int k = 0; k < 6; ++k) u32(0);                       // move y, facing, actions, camera
  for (std::uint8_t k = 1; k <= 12; ++k) u8(k);             // sender
  EXPECT_EQ(got, want);

  TickRecord t;
  std::size_t pos = 0;
  decode_tick(got, pos, t, kFormatVersion);
  EXPECT_EQ(pos, got.size());
  ASSERT_EQ(t.inputs.commands.size(), 1u);
  EXPECT_EQ(t.inputs.commands[0].move_x, 1.5f);
  EXPECT_EQ(t.inputs.commands[0].sender, c.sender);

  got.pop_back();
  pos = 0;
  try {
    decode_tick(got, pos, t, kFormatVersion);
    ADD_FAILURE() << "a truncated entry decoded";
  } catch (const LogError& e) {
    EXPECT_NE(std::string(e.what()).find("tick entry truncated: command sender needs 12 bytes"), std::string::npos)
        << e.what();
  }
}

TEST(RoundTrip, UtcFormatIsFixedWidth) {
  EXPECT_EQ(format_utc_ms(0), "1970-01-01T00:00:00.000Z");
  EXPECT_EQ(format_utc_ms(1714567890123), "2024-05-01T12:51:30.123Z");
}

}  // namespace
}  // namespace throng::matchlog
