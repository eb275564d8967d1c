// Damaged logs: truncation anywhere (torn tail), flipped bytes in the middle (corruption at the
// right record), and header problems (clear errors).
#include <gtest/gtest.h>

#include <random>
#include <set>

#include "matchlog_test_util.h"
#include "throng/matchlog/crc32c.h"
#include "throng/matchlog/format.h"
#include "throng/matchlog/reader.h"

namespace throng::matchlog {
namespace {

struct Rec {
  std::size_t start, end;
  std::uint8_t type;
  std::uint64_t first_tick = 0;  // tick blocks
  std::uint32_t ticks = 0;
};

// The records of an intact log, walked independently of the reader.
std::vector<Rec> walk(const std::vector<std::uint8_t>& f) {
  std::vector<Rec> out;
  std::size_t pos = kFilePreambleBytes;
  auto u32 = [&](std::size_t p) {
    return static_cast<std::uint32_t>(f[p]) | static_cast<std::uint32_t>(f[p + 1]) << 8 |
           static_cast<std::uint32_t>(f[p + 2]) << 16 | static_cast<std::uint32_t>(f[p + 3]) << 24;
  };
  while (pos < f.size()) {
    Rec r{pos, pos + 9 + u32(pos), f[pos + 4]};
    if (r.type == static_cast<std::uint8_t>(RecordType::tick_block)) {
      r.first_tick = u32(pos + 5) | static_cast<std::uint64_t>(u32(pos + 9)) << 32;
      r.ticks = u32(pos + 13);
    }
    out.push_back(r);
    pos = r.end;
  }
  return out;
}

std::string open_error(const std::filesystem::path& p) {
  try {
    MatchLogReader r(p.string());
  } catch (const LogError& e) {
    return e.what();
  }
  return "";
}

class Truncation : public ::testing::TestWithParam<int> {};

TEST_P(Truncation, ReaderKeepsEveryCompleteTickAndReportsTheTornTail) {
  const auto dir = test::test_dir();
  const auto full = dir / "full.tlog";
  WriterOptions o;
  o.zstd_level = GetParam();
  const auto written = test::write_random_log(full, 300, o, 21);
  const auto bytes = test::read_bytes(full);
  const auto recs = walk(bytes);
  ASSERT_EQ(recs.back().end, bytes.size());
  const std::size_t header_end = recs.front().end;

  std::mt19937_64 rng(99);
  std::set<std::size_t> cuts;
  while (cuts.size() < 240) cuts.insert(rng() % bytes.size());
  for (const Rec& r : recs) {  // every boundary and its neighbours too
    cuts.insert(r.start);
    if (r.start + 1 < bytes.size()) cuts.insert(r.start + 1);
    cuts.insert(r.end - 1);
  }
  for (std::size_t x : {0, 1, 7, 8, 11, 12, 13}) cuts.insert(x);
  cuts.insert(bytes.size());

  const auto cut_path = dir / "cut.tlog";
  std::size_t torn = 0;
  for (std::size_t x : cuts) {
    SCOPED_TRACE("cut at byte " + std::to_string(x) + " of " + std::to_string(bytes.size()));
    test::write_bytes(cut_path, bytes, x);
    if (x < header_end) {
      const std::string e = open_error(cut_path);
      if (x == 0) EXPECT_NE(e.find("empty file"), std::string::npos) << e;
      else EXPECT_NE(e.find("truncated header"), std::string::npos) << e;
      continue;
    }
    std::uint64_t expect_ticks = 0;
    std::size_t damaged_at = 0;
    bool boundary = false;
    for (const Rec& r : recs) {
      if (r.end <= x) expect_ticks += r.ticks;
      if (r.end == x) boundary = true;
      if (r.start < x && x < r.end) damaged_at = r.start;
    }
    MatchLogReader reader(cut_path.string());
    const LogScan& s = reader.scan();
    ASSERT_EQ(s.ticks, expect_ticks);
    if (x == bytes.size()) {
      EXPECT_EQ(s.end, LogEnd::closed);
    } else if (boundary) {
      EXPECT_EQ(s.end, LogEnd::unclosed) << s.problem;
      EXPECT_NE(s.problem.find("without an end record"), std::string::npos) << s.problem;
    } else {
      ++torn;
      EXPECT_EQ(s.end, LogEnd::torn) << s.problem;
      EXPECT_EQ(s.damage_offset, damaged_at);
      const std::string want = "log ends mid-record at byte " + std::to_string(damaged_at) + " after tick " + std::to_string(expect_ticks);
      EXPECT_NE(s.problem.find(want), std::string::npos) << s.problem;
      EXPECT_NE(s.problem.find("torn tail"), std::string::npos) << s.problem;
    }
    // Every kept tick is the one written.
    TickRecord t;
    std::uint64_t n = 0;
    while (reader.next(t)) {
      ASSERT_EQ(t.tick, n + 1);
      ASSERT_EQ(t.state_hash, written[n].state_hash);
      if (n % 37 == 0) test::expect_same_inputs(t.inputs, written[n].inputs, t.tick);
      ++n;
    }
    ASSERT_EQ(n, expect_ticks);
  }
  EXPECT_GE(torn, 200u);
}

INSTANTIATE_TEST_SUITE_P(Codecs, Truncation, ::testing::Values(3, 0),
                         [](const ::testing::TestParamInfo<int>& i) { return "zstd" + std::to_string(i.param); });

TEST(Damage, ZeroFilledTailIsATornTail) {
  // A power loss can leave the file extended with zeros after the last good write.
  const auto dir = test::test_dir();
  test::write_random_log(dir / "full.tlog", 100, {}, 3);
  auto bytes = test::read_bytes(dir / "full.tlog");
  const auto recs = walk(bytes);
  const Rec& mid = recs[recs.size() / 2];
  bytes.resize(mid.start + 7);
  bytes.resize(bytes.size() + 4096, 0);
  test::write_bytes(dir / "zero.tlog", bytes, bytes.size());
  MatchLogReader r((dir / "zero.tlog").string());
  EXPECT_EQ(r.scan().end, LogEnd::torn) << r.scan().problem;
  EXPECT_EQ(r.scan().damage_offset, mid.start);
}

TEST(Damage, FlippedByteInTheMiddleIsCorruptionAtThatRecord) {
  const auto dir = test::test_dir();
  test::write_random_log(dir / "full.tlog", 300, {}, 8);
  const auto bytes = test::read_bytes(dir / "full.tlog");
  const auto recs = walk(bytes);
  std::mt19937_64 rng(5);
  int checked = 0;
  for (std::size_t i = 1; i + 2 < recs.size(); ++i) {  // every record but the header, final index and end
    const Rec& r = recs[i];
    std::uint64_t ticks_before = 0;
    for (std::size_t k = 0; k < i; ++k) ticks_before += recs[k].ticks;
    for (int trial = 0; trial < 4; ++trial) {
      auto damaged = bytes;
      // Trial 0 hits the length field, 1 the type, the others anywhere in the record.
      const std::size_t at = trial == 0 ? r.start + rng() % 4 : trial == 1 ? r.start + 4 : r.start + rng() % (r.end - r.start);
      damaged[at] ^= static_cast<std::uint8_t>(1u << (rng() % 8));
      test::write_bytes(dir / "flip.tlog", damaged, damaged.size());
      SCOPED_TRACE("record " + std::to_string(i) + " at byte " + std::to_string(r.start) + ", flipped byte " + std::to_string(at));
      MatchLogReader reader((dir / "flip.tlog").string());
      const LogScan& s = reader.scan();
      ASSERT_EQ(s.end, LogEnd::corrupt) << s.problem;
      EXPECT_EQ(s.damage_offset, r.start);
      EXPECT_EQ(s.ticks, ticks_before);
      EXPECT_NE(s.problem.find("at byte " + std::to_string(r.start) + " after tick " + std::to_string(ticks_before)),
                std::string::npos) << s.problem;
      if (s.resumes_at != 0) {
        EXPECT_EQ(s.resumes_at, r.end);
      }
      TickRecord t;
      std::uint64_t n = 0;
      while (reader.next(t)) ++n;
      EXPECT_EQ(n, ticks_before);  // never reads past the damage
      ++checked;
    }
  }
  EXPECT_GT(checked, 80);
}

TEST(Damage, FlippedByteInTheLastRecordIsATornTail) {
  const auto dir = test::test_dir();
  test::write_random_log(dir / "full.tlog", 50, {}, 8);
  auto bytes = test::read_bytes(dir / "full.tlog");
  bytes[bytes.size() - 10] ^= 0x10;  // inside the end record
  test::write_bytes(dir / "flip.tlog", bytes, bytes.size());
  MatchLogReader r((dir / "flip.tlog").string());
  EXPECT_EQ(r.scan().end, LogEnd::torn) << r.scan().problem;
  EXPECT_EQ(r.scan().ticks, 50u);
}

TEST(Damage, HeaderProblemsAreClearErrors) {
  const auto dir = test::test_dir();
  test::write_random_log(dir / "good.tlog", 20, {}, 1);
  const auto good = test::read_bytes(dir / "good.tlog");
  const auto p = dir / "bad.tlog";

  auto bytes = good;
  bytes[1] = 'X';
  test::write_bytes(p, bytes, bytes.size());
  EXPECT_NE(open_error(p).find("not a Throng match log"), std::string::npos) << open_error(p);

  bytes = good;
  bytes[8] = 4;  // format version 4
  test::write_bytes(p, bytes, bytes.size());
  EXPECT_NE(open_error(p).find("format version 4 is not supported (this build reads format versions 1..3)"), std::string::npos)
      << open_error(p);
  bytes[8] = 0;
  test::write_bytes(p, bytes, bytes.size());
  EXPECT_NE(open_error(p).find("format version 0 is not supported"), std::string::npos) << open_error(p);
  bytes[8] = 1;  // a v3 header in a v1 preamble
  test::write_bytes(p, bytes, bytes.size());
  EXPECT_NE(open_error(p).find("format version 1 in the preamble, 3 in the header"), std::string::npos) << open_error(p);

  const auto recs = walk(good);
  test::write_bytes(p, good, recs.front().end - 10);
  EXPECT_NE(open_error(p).find("truncated header"), std::string::npos) << open_error(p);

  bytes = good;
  bytes[40] ^= 0x01;  // inside the header's JSON
  test::write_bytes(p, bytes, bytes.size());
  EXPECT_NE(open_error(p).find("corrupt header record at byte 12"), std::string::npos) << open_error(p);

  const std::string text = "{\"this\": \"is JSON, not a match log\"}\n";
  test::write_bytes(p, std::vector<std::uint8_t>(text.begin(), text.end()), text.size());
  EXPECT_NE(open_error(p).find("not a Throng match log"), std::string::npos) << open_error(p);

  EXPECT_NE(open_error(dir / "missing.tlog").find("cannot open"), std::string::npos);
}

// Frames a record as the writer does (length, type, payload, CRC-32C over the three).
std::vector<std::uint8_t> framed(std::uint8_t type, const std::vector<std::uint8_t>& payload) {
  std::vector<std::uint8_t> r;
  const auto n = static_cast<std::uint32_t>(payload.size());
  for (int k = 0; k < 4; ++k) r.push_back(static_cast<std::uint8_t>(n >> (8 * k)));
  r.push_back(type);
  r.insert(r.end(), payload.begin(), payload.end());
  const std::uint32_t c = crc32c(r.data(), r.size());
  for (int k = 0; k < 4; ++k) r.push_back(static_cast<std::uint8_t>(c >> (8 * k)));
  return r;
}

TEST(Damage, FormatVersionOneLogsAreStillRead) {
  // A version 1 file: preamble and header say 1, tick blocks as today, index records without the
  // keyframe part, no keyframes. Ticks carry parameter changes only: their layout is the same in
  // every version (joins and commands gained senders in version 3).
  const auto dir = test::test_dir();
  const auto ticks = test::write_random_log(dir / "v2.tlog", 40, {}, 5, /*params_only=*/true);
  const auto v2 = test::read_bytes(dir / "v2.tlog");
  const auto recs = walk(v2);
  std::string text(v2.begin() + static_cast<std::ptrdiff_t>(recs.front().start + 5),
                   v2.begin() + static_cast<std::ptrdiff_t>(recs.front().end - 4));
  const auto at = text.find("\"format_version\":3");
  ASSERT_NE(at, std::string::npos);
  text[at + 17] = '1';
  const std::string kf_field = ",\"keyframe_interval_ticks\":60";  // v1 writers did not know it
  const auto kat = text.find(kf_field);
  ASSERT_NE(kat, std::string::npos) << text.substr(0, 400);
  text.erase(kat, kf_field.size());
  std::vector<std::uint8_t> v1(v2.begin(), v2.begin() + 8);
  for (std::uint8_t b : {1, 0, 0, 0}) v1.push_back(b);
  const auto h = framed(1, std::vector<std::uint8_t>(text.begin(), text.end()));
  v1.insert(v1.end(), h.begin(), h.end());
  for (const Rec& r : recs)
    if (r.type == static_cast<std::uint8_t>(RecordType::tick_block))
      v1.insert(v1.end(), v2.begin() + static_cast<std::ptrdiff_t>(r.start), v2.begin() + static_cast<std::ptrdiff_t>(r.end));
  const std::vector<std::uint8_t> empty_index(13, 0);  // prev 0, periodic, 0 entries (v1 layout)
  const auto idx = framed(3, empty_index);
  v1.insert(v1.end(), idx.begin(), idx.end());
  const auto p = dir / "v1.tlog";
  test::write_bytes(p, v1, v1.size());
  {
    MatchLogReader r(p.string());
    EXPECT_EQ(r.scan().format_version, 1u);
    EXPECT_EQ(r.header().format_version, 1u);
    EXPECT_EQ(r.scan().end, LogEnd::unclosed) << r.scan().problem;
    EXPECT_EQ(r.scan().ticks, 40u);
    EXPECT_EQ(r.scan().index_records, 1u);
    EXPECT_TRUE(r.scan().keyframes.empty());
    EXPECT_EQ(r.header().writer.keyframe_interval_ticks, 0u);
    TickRecord t;
    for (std::size_t i = 0; r.next(t); ++i) {
      ASSERT_EQ(t.state_hash, ticks[i].state_hash);
      test::expect_same_inputs(t.inputs, ticks[i].inputs, t.tick);
    }
  }
  // A keyframe record has no place in a version 1 log.
  std::vector<std::uint8_t> kf_payload(13, 0);
  kf_payload[0] = 40;  // tick 40, codec raw, size 0
  const auto kf = framed(6, kf_payload);
  auto bad = v1;
  bad.insert(bad.end(), kf.begin(), kf.end());
  test::write_bytes(p, bad, bad.size());
  MatchLogReader r(p.string());
  EXPECT_EQ(r.scan().end, LogEnd::corrupt);
  EXPECT_NE(r.scan().problem.find("a keyframe record in a format version 1 log"), std::string::npos) << r.scan().problem;
}

}  // namespace
}  // namespace throng::matchlog
