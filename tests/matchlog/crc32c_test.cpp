#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "matchlog_test_util.h"
#include "throng/matchlog/crc32c.h"

namespace throng::matchlog {
namespace {

// Bit-at-a-time reference straight from the definition.
std::uint32_t crc32c_bitwise(const std::uint8_t* p, std::size_t n) {
  std::uint32_t c = 0xFFFFFFFFu;
  for (std::size_t i = 0; i < n; ++i) {
    c ^= p[i];
    for (int k = 0; k < 8; ++k) c = (c & 1u) ? (c >> 1) ^ 0x82F63B78u : c >> 1;
  }
  return ~c;
}

TEST(Crc32c, KnownVectors) {
  EXPECT_EQ(crc32c(std::string_view("123456789")), 0xE3069283u);
  EXPECT_EQ(crc32c(std::string_view("")), 0x00000000u);
  EXPECT_EQ(crc32c(std::string_view("a")), 0xC1D04330u);
  // RFC 3720 (iSCSI) appendix B.4.
  std::vector<std::uint8_t> zeros(32, 0x00), ones(32, 0xFF), inc(32), dec(32);
  for (int i = 0; i < 32; ++i) {
    inc[static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(i);
    dec[static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(31 - i);
  }
  EXPECT_EQ(crc32c(zeros), 0x8A9136AAu);
  EXPECT_EQ(crc32c(ones), 0x62A8AB43u);
  EXPECT_EQ(crc32c(inc), 0x46DD794Eu);
  EXPECT_EQ(crc32c(dec), 0x113FDB5Cu);
}

TEST(Crc32c, SlicingMatchesBitwiseAtEveryLengthAndAlignment) {
  std::mt19937_64 rng(3);
  std::vector<std::uint8_t> buf(300);
  for (auto& b : buf) b = static_cast<std::uint8_t>(rng());
  for (std::size_t off = 0; off < 9; ++off) {
    for (std::size_t len = 0; off + len <= buf.size(); len += 1 + len / 8) {
      ASSERT_EQ(crc32c(buf.data() + off, len), crc32c_bitwise(buf.data() + off, len)) << off << "+" << len;
    }
  }
}

// crc32c_update takes SSE4.2's instruction on CPUs that have it: the table it falls back to must
// give the same CRCs.
TEST(Crc32c, TableMatchesBitwiseAtEveryLengthAndAlignment) {
  std::mt19937_64 rng(5);
  std::vector<std::uint8_t> buf(300);
  for (auto& b : buf) b = static_cast<std::uint8_t>(rng());
  for (std::size_t off = 0; off < 9; ++off) {
    for (std::size_t len = 0; off + len <= buf.size(); len += 1 + len / 8) {
      ASSERT_EQ(detail::crc32c_update_table(0, buf.data() + off, len), crc32c_bitwise(buf.data() + off, len)) << off << "+" << len;
      ASSERT_EQ(detail::crc32c_update_table(0x12345678u, buf.data() + off, len), crc32c_update(0x12345678u, buf.data() + off, len));
    }
  }
}

TEST(Crc32c, IncrementalEqualsOneShot) {
  const std::string s = "The quick brown fox jumps over the lazy dog, twice over the lazy dog.";
  for (std::size_t cut = 0; cut <= s.size(); ++cut) {
    const std::uint32_t a = crc32c_update(0, s.data(), cut);
    ASSERT_EQ(crc32c_update(a, s.data() + cut, s.size() - cut), crc32c(s)) << cut;
  }
}

// The suite's temporary files go when the run ends (registered once, here).
const auto* const kCleanup = ::testing::AddGlobalTestEnvironment(new test::CleanupEnvironment);

}  // namespace
}  // namespace throng::matchlog
