// The snapshot clients' per-object records (server/match/src/lazy_zero_array.h): zero until
// written, kept across growth, each array its own mapping, resident on commit.
#include <gtest/gtest.h>
#include <sys/mman.h>
#include <unistd.h>

#include <cstdint>
#include <cstring>
#include <utility>
#include <vector>

#include "../../server/match/src/lazy_zero_array.h"

namespace throng::match::detail {
namespace {

struct Record {
  std::uint64_t a;
  std::uint32_t b, c;
  double d, e;
};

bool all_zero(const Record& r) {
  Record zero;
  std::memset(&zero, 0, sizeof zero);
  return std::memcmp(&r, &zero, sizeof r) == 0;
}

TEST(LazyZeroArray, StartsEmptyAndGrowsToZeroRecords) {
  LazyZeroArray<Record> records;
  EXPECT_EQ(records.size(), 0u);
  EXPECT_EQ(records.data(), nullptr);
  records.grow_to(6001);
  ASSERT_EQ(records.size(), 6001u);
  for (const Record& r : records) EXPECT_TRUE(all_zero(r));
}

TEST(LazyZeroArray, GrowingKeepsTheRecordsAndZeroesTheNewOnes) {
  LazyZeroArray<Record> records;
  // Sizes that end inside a page, on one, and far past the first mapping (the mapping moves).
  records.grow_to(3);
  for (std::size_t i = 0; i < 3; ++i) records[i] = {i + 1, 7, 8, 0.5, -1.0};
  for (const std::size_t n : {4u, 128u, 129u, 6000u, 250000u}) {
    records.grow_to(n);
    ASSERT_EQ(records.size(), n);
    for (std::size_t i = 0; i < 3; ++i) {
      EXPECT_EQ(records[i].a, i + 1);
      EXPECT_EQ(records[i].d, 0.5);
    }
    for (std::size_t i = 3; i < n; ++i) ASSERT_TRUE(all_zero(records[i])) << "record " << i << " of " << n;
    records[n - 1] = Record{};  // written (all zero again, so the next size's check holds)
  }
  records.grow_to(10);  // never shrinks
  EXPECT_EQ(records.size(), 250000u);
}

TEST(LazyZeroArray, MovesOwnTheirMapping) {
  LazyZeroArray<Record> a;
  a.grow_to(1000);
  a[999].b = 5;
  LazyZeroArray<Record> b(std::move(a));
  EXPECT_EQ(a.size(), 0u);
  EXPECT_EQ(a.data(), nullptr);
  ASSERT_EQ(b.size(), 1000u);
  EXPECT_EQ(b[999].b, 5u);
  LazyZeroArray<Record> c;
  c.grow_to(5);
  c = std::move(b);  // c's own mapping is released, b's taken
  ASSERT_EQ(c.size(), 1000u);
  EXPECT_EQ(c[999].b, 5u);
  a.grow_to(2);  // a moved-from array is usable again
  EXPECT_TRUE(all_zero(a[1]));
}

TEST(LazyZeroArray, RefusesACountBeyondAnyMapping) {
  LazyZeroArray<Record> records;
  records.grow_to(4);
  records[0].a = 1;
  EXPECT_THROW(records.grow_to(std::size_t{1} << 60), std::bad_alloc);
  ASSERT_EQ(records.size(), 4u);  // unchanged
  EXPECT_EQ(records[0].a, 1u);
}


// Pages of the array's mapping the kernel holds in memory (mincore).
std::size_t resident_pages(const LazyZeroArray<Record>& records) {
  const auto page = static_cast<std::size_t>(sysconf(_SC_PAGESIZE));
  const std::size_t pages = (records.size() * sizeof(Record) + page - 1) / page;
  std::vector<unsigned char> in_core(pages);
  if (mincore(const_cast<Record*>(records.data()), pages * page, in_core.data()) != 0) return ~std::size_t{0};
  std::size_t n = 0;
  for (const unsigned char c : in_core) n += c & 1u;
  return n;
}

TEST(LazyZeroArray, CommitMakesEveryPageResidentAndKeepsTheRecords) {
  const auto page = static_cast<std::size_t>(sysconf(_SC_PAGESIZE));
  LazyZeroArray<Record> records;
  records.grow_to(100000);  // 3.2 MB
  const std::size_t pages = (records.size() * sizeof(Record) + page - 1) / page;
  records[5] = {1, 2, 3, 4.5, -6.0};
  records[99999].b = 9;
  // Lazily, only what was written is resident: the two pages written.
  EXPECT_EQ(resident_pages(records), 2u);
  records.commit();
  EXPECT_EQ(resident_pages(records), pages);
  EXPECT_EQ(records[5].a, 1u);
  EXPECT_EQ(records[5].e, -6.0);
  EXPECT_EQ(records[99999].b, 9u);
  for (std::size_t i = 0; i < records.size(); ++i) {
    if (i == 5 || i == 99999) continue;
    ASSERT_TRUE(all_zero(records[i])) << "record " << i;
  }
  // After a growth, commit makes the new pages resident; the lazy part stays lazy until then.
  records.grow_to(200000);
  const std::size_t grown = (records.size() * sizeof(Record) + page - 1) / page;
  EXPECT_EQ(resident_pages(records), pages);
  records.commit();
  EXPECT_EQ(resident_pages(records), grown);
  EXPECT_EQ(records[99999].b, 9u);
  LazyZeroArray<Record> empty;
  empty.commit();  // nothing mapped: nothing to do
  EXPECT_EQ(empty.data(), nullptr);
}

}  // namespace
}  // namespace throng::match::detail
