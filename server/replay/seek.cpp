// throng-replay seek: position a LogPlayer at a tick (through the nearest world keyframe) and check
// the state hash there against the log.
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "open_log.h"
#include "throng/matchlog/log_player.h"

namespace throng::replay {

int run_seek(const SeekOptions& o) {
  // seek reports the world's hash: the cheap settings (PlayerOptions: exact_interest = false)
  // restore keyframes without the snapshot baselines and skip the logged clients' snapshots.
  matchlog::PlayerOptions po;
  po.resim.exact_interest = false;
  const auto player = open_log<matchlog::LogPlayer>("seek", o.log, po);
  if (!player) return kExitBadInput;
  if (o.tick < 1 || o.tick > player->last_tick()) {
    const auto& s = player->scan();
    fmt::print(stderr, "throng-replay seek: --tick {} is outside the ticks that can be re-simulated (1..{}{})\n", o.tick,
               player->last_tick(), s.problem.empty() ? "" : ": " + s.problem);
    return kExitBadInput;
  }
  matchlog::SeekResult r;
  try {
    r = player->seek(o.tick);
  } catch (const std::exception& e) {
    fmt::print(stderr, "throng-replay seek: {}: {}\n", o.log, e.what());
    return kExitBadInput;
  }
  const std::uint64_t actual = player->match().state_hash();
  const std::uint64_t logged = r.logged_hash;
  const bool matched = actual == logged;
  const std::string from = r.keyframe_tick > 0 ? fmt::format("the keyframe of tick {}", r.keyframe_tick) : "the match start";
  if (o.json) {
    nlohmann::ordered_json j;
    j["log"] = o.log;
    j["tick"] = r.tick;
    j["keyframe_tick"] = r.keyframe_tick;
    j["ticks_simulated"] = r.ticks_simulated;
    j["ms"] = r.ms;
    j["state_hash"] = fmt::format("{:016x}", actual);
    j["logged_state_hash"] = fmt::format("{:016x}", logged);
    j["match"] = matched;
    j["hash_mismatches_on_the_way"] = r.hash_mismatches;
    j["keyframe_problem"] = player->keyframe_problem();
    fmt::print("{}\n", j.dump(2));
  } else {
    fmt::print("seeked to tick {} from {} ({} ticks re-simulated) in {:.1f} ms\n", r.tick, from, r.ticks_simulated, r.ms);
    if (!player->keyframe_problem().empty()) fmt::print("note: {}\n", player->keyframe_problem());
    fmt::print("state hash {:016x}, logged {:016x}: {}\n", actual, logged, matched ? "match" : "MISMATCH");
    if (r.hash_mismatches > 0 && matched)
      fmt::print("note: {} ticks on the way did not match (first: tick {}); run verify\n", r.hash_mismatches,
                 r.first_mismatch_tick);
  }
  return matched ? kExitOk : kExitMismatch;
}

}  // namespace throng::replay
