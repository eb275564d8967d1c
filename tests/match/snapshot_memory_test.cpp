// What a snapshot client costs in memory, and when: a joining client's per-object table is
// resident at the join (so a server's memory is a function of the clients present, not of how
// much of the world each has seen yet), a departing one's is returned, and a restore stays lazy
// (it creates every client at once, inside a seek).
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <fstream>
#include <vector>

#include "throng/core/byte_io.h"
#include "throng/core/object_id.h"
#include "throng/match/snapshot_builder.h"

namespace throng::match {
namespace {

constexpr std::uint32_t kBodies = 200000;  // a table of 200,000 records of 32 bytes: 6.4 MB
constexpr std::size_t kTableBytes = std::size_t{kBodies} * 32;

std::size_t resident_bytes() {
  std::ifstream statm("/proc/self/statm");
  std::size_t size_pages = 0, resident_pages = 0;
  statm >> size_pages >> resident_pages;
  return resident_pages * static_cast<std::size_t>(sysconf(_SC_PAGESIZE));
}

struct Line {
  std::vector<std::uint32_t> id;
  std::vector<double> x, y, z;
  std::vector<float> yaw;
  Line() {
    for (std::uint32_t i = 0; i < kBodies; ++i) {
      id.push_back(ObjectId::make(i, 0).value);
      x.push_back(0.5 * i);
      y.push_back(0.0);
      z.push_back(0.0);
      yaw.push_back(0.0f);
    }
  }
  BodyView view() const { return BodyView{id, x, y, z, yaw}; }
};

TEST(SnapshotMemory, AJoinedClientsTableIsResidentAtOnceAndReturnedWhenItLeaves) {
  const Line line;
  InterestConfig config;
  config.radius_m = 30.0;
  SnapshotBuilder builder(config);
  builder.index(line.view(), 1);
  const std::size_t before = resident_bytes();
  builder.add_client(7);
  const std::size_t joined = resident_bytes();
  // The whole table, though the client has not been sent a single object.
  EXPECT_GE(joined, before + kTableBytes * 9 / 10) << "before " << before << ", joined " << joined;
  builder.remove_client(7);
  EXPECT_LE(resident_bytes(), joined - kTableBytes * 9 / 10) << "the table's mapping is returned";
}

TEST(SnapshotMemory, ARestoredClientsTableStaysLazy) {
  const Line line;
  InterestConfig config;
  config.radius_m = 30.0;
  std::vector<std::uint8_t> bytes;
  {
    SnapshotBuilder saved(config);
    saved.index(line.view(), 1);
    saved.add_client(7);
    protocol::Snapshot out;
    saved.build(7, 0.0, 0.0, out);  // a few objects near the origin become known
    ByteWriter w(bytes);
    saved.save_state(w);
  }
  SnapshotBuilder restored(config);
  const std::size_t before = resident_bytes();
  ByteReader r(bytes);
  restored.restore_state(r, 2 * std::size_t{kBodies});  // the saved table may be larger than the bodies
  ASSERT_TRUE(restored.has_client(7));
  // Only the pages of the records it holds (a handful near the origin), not the table.
  EXPECT_LT(resident_bytes(), before + kTableBytes / 4) << "before " << before << ", restored " << resident_bytes();
}

// A restore without baselines adds its clients before the first index (lazily), and the index's
// growth of the tables must keep them lazy; a joined client's grows resident.
TEST(SnapshotMemory, TablesGrownByTheIndexStayAsTheirClientWasAdded) {
  const Line line;
  InterestConfig config;
  config.radius_m = 30.0;
  SnapshotBuilder lazy(config), resident(config);
  lazy.add_client(7, SnapshotBuilder::Residency::kLazy);
  resident.add_client(7);
  const std::size_t before = resident_bytes();
  lazy.index(line.view(), 1);  // capacity 0 -> every body's index
  const std::size_t lazy_indexed = resident_bytes();
  resident.index(line.view(), 1);
  const std::size_t resident_indexed = resident_bytes();
  // Each index also builds its own grid and scratch (the same for both builders): the resident
  // client's index costs its table more than the lazy one's.
  const std::size_t lazy_cost = lazy_indexed - before, resident_cost = resident_indexed - lazy_indexed;
  EXPECT_GE(resident_cost, lazy_cost + kTableBytes * 9 / 10) << "lazy " << lazy_cost << ", resident " << resident_cost;
}

}  // namespace
}  // namespace throng::match
