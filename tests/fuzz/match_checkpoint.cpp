// Match::restore_checkpoint: a whole match checkpoint (world, clients, NPC AI, snapshot baselines),
// as keyframes of a match log bring it to throng-replay and the viewer. A match that accepts the
// bytes must then tick. Input: one byte of options (bit 0: reset the snapshot baselines), then the
// checkpoint. Bad input throws CheckpointError and leaves the match unchanged.
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <span>
#include <vector>

#include "match_test_util.h"

using namespace throng;

namespace {

struct State {
  std::unique_ptr<match::Match> match;
  match::Outbox out;
  std::vector<std::uint8_t> start;
};

State& state() {
  static State* s = [] {
    auto* st = new State;
    match::MatchConfig config = match::test::small_config();
    config.worker_threads = 1;
    st->match = std::make_unique<match::Match>(match::test::two_armies(4), config, "fuzz");
    st->match->inputs().push(match::test::join_request(1));
    st->match->tick(st->out);
    st->match->save_checkpoint(st->start);
    return st;
  }();
  return *s;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  State& s = state();
  s.match->restore_checkpoint(s.start);
  match::RestoreOptions options;
  options.snapshot_baselines = (data[0] & 1) ? match::SnapshotBaselines::reset : match::SnapshotBaselines::restore;
  const std::span<const std::uint8_t> bytes(data + 1, size - 1);
  try {
    (void)match::checkpoint_sections(bytes);
  } catch (const match::CheckpointError&) {
  }
  try {
    s.match->restore_checkpoint(bytes, options);
  } catch (const match::CheckpointError&) {
    return 0;
  }
  s.match->tick(s.out);
  return 0;
}
