// A match log file as throng-replay / the viewer open it (MatchLogReader: preamble, header record,
// tick blocks, index, gap, keyframe and end records), then every readable tick, a seek, the
// blocks and the keyframes. Input: the file's bytes. Bad input must end in LogError (or a scan
// that says torn / corrupt), never anything else.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "throng/matchlog/reader.h"

using namespace throng;

namespace {

const std::string& log_path() {
  static const std::string p = [] {
    const char* dir = std::getenv("TMPDIR");
    return std::string(dir && *dir ? dir : "/tmp") + "/throng_fuzz_matchlog_" + std::to_string(::getpid()) + ".tlog";
  }();
  return p;
}

void remove_log() { std::remove(log_path().c_str()); }

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  // Registered once the path exists, so it runs before the path's destructor: a fuzz run leaves
  // no file behind in the temporary directory.
  static const bool cleanup_registered = (log_path(), std::atexit(remove_log) == 0);
  (void)cleanup_registered;
  {
    std::FILE* f = std::fopen(log_path().c_str(), "wb");
    if (!f) std::abort();
    if (size > 0 && std::fwrite(data, 1, size, f) != size) std::abort();
    std::fclose(f);
  }
  try {
    matchlog::MatchLogReader reader(log_path());
    const matchlog::LogScan& scan = reader.scan();
    matchlog::TickRecord t;
    std::uint64_t n = 0;
    while (reader.next(t)) ++n;
    if (n != scan.ticks) std::abort();  // documented: scan().ticks complete ticks are readable
    if (scan.ticks > 0) {
      if (!reader.seek(scan.last_tick) || !reader.next(t) || t.tick != scan.last_tick) std::abort();
      matchlog::TickCursor cursor(reader);
      if (!cursor.seek(scan.first_tick) || !cursor.next(t)) std::abort();
    }
    std::vector<std::uint8_t> raw;
    for (std::size_t b = 0; b < scan.blocks.size(); ++b) reader.decode_block(b, raw);
    for (const auto& k : scan.keyframes) {
      try {
        reader.read_keyframe(k, raw);
      } catch (const matchlog::LogError&) {  // documented for a keyframe that does not inflate
      }
    }
  } catch (const matchlog::LogError&) {
  }
  return 0;
}
