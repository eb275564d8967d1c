// throng-replay info: what is in a log, read without re-simulating.
#include <cstdio>
#include <set>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "open_log.h"
#include "throng/matchlog/reader.h"

namespace throng::replay {

int run_info(const InfoOptions& o) {
  const auto reader = open_log<matchlog::MatchLogReader>("info", o.log);
  if (!reader) return kExitBadInput;
  const matchlog::LogHeader& h = reader->header();
  const matchlog::LogScan& s = reader->scan();

  std::uint64_t join_requests = 0, leaves = 0, commands = 0, params = 0, shutdown_tick = 0;
  std::set<std::uint64_t> nonces;
  std::set<std::uint32_t> commanding;
  matchlog::TickRecord t;
  try {
    while (reader->next(t)) {
      for (const auto& j : t.inputs.joins) {
        if (j.leave) ++leaves;
        else {
          ++join_requests;
          nonces.insert(j.client_nonce);
        }
      }
      commands += t.inputs.commands.size();
      for (const auto& c : t.inputs.commands) commanding.insert(c.client_id);
      params += t.inputs.params.size();
      if ((t.flags & matchlog::kTickShutdownBegan) != 0 && shutdown_tick == 0) shutdown_tick = t.tick;
    }
  } catch (const matchlog::LogError& e) {
    fmt::print(stderr, "throng-replay info: {}: {}\n", o.log, e.what());
    return kExitDamaged;
  }

  const double hz = h.config.tick_hz;
  const double seconds = static_cast<double>(s.ticks + s.ticks_missing) / hz;
  const double bytes_per_tick = s.ticks > 0 ? static_cast<double>(s.tick_block_bytes) / static_cast<double>(s.ticks) : 0.0;
  const double raw_per_tick = s.ticks > 0 ? static_cast<double>(s.raw_tick_bytes) / static_cast<double>(s.ticks) : 0.0;
  const bool damaged = s.end == matchlog::LogEnd::corrupt || s.ticks_missing > 0;

  if (o.json) {
    nlohmann::ordered_json j;
    j["log"] = o.log;
    j["file_bytes"] = s.file_bytes;
    j["format_version"] = h.format_version;
    j["build_id"] = h.build_id;
    j["match_id"] = h.match_id;
    j["start_utc"] = h.start_utc;
    j["scene"] = h.scene.name;
    j["bodies"] = h.scene.agent_count();
    j["scene_hash"] = fmt::format("{:016x}", h.scene_hash);
    j["scene_hash_matches"] = s.scene_hash_matches;
    j["tick_hz"] = h.config.tick_hz;
    j["first_tick"] = s.first_tick;
    j["last_tick"] = s.last_tick;
    j["ticks"] = s.ticks;
    j["ticks_missing"] = s.ticks_missing;
    j["duration_s"] = seconds;
    j["join_requests"] = join_requests;
    j["distinct_clients"] = nonces.size();
    j["leaves"] = leaves;
    j["commanding_clients"] = commanding.size();
    j["commands"] = commands;
    j["param_updates"] = params;
    j["shutdown_tick"] = shutdown_tick;
    j["tick_blocks"] = s.blocks.size();
    j["index_records"] = s.index_records;
    j["keyframes"] = s.keyframes.size();
    j["keyframe_interval_ticks"] = h.writer.keyframe_interval_ticks;
    j["keyframe_snapshot_baselines"] = h.writer.keyframe_snapshot_baselines;
    j["keyframe_bytes"] = s.keyframe_bytes;
    j["keyframe_raw_bytes"] = s.keyframe_raw_bytes;
    j["first_keyframe_tick"] = s.keyframes.empty() ? 0 : s.keyframes.front().tick;
    j["last_keyframe_tick"] = s.keyframes.empty() ? 0 : s.keyframes.back().tick;
    j["bytes_per_tick"] = bytes_per_tick;
    j["raw_bytes_per_tick"] = raw_per_tick;
    j["end"] = matchlog::to_string(s.end);
    j["torn_tail"] = s.end == matchlog::LogEnd::torn;
    j["problem"] = s.problem;
    fmt::print("{}\n", j.dump(2));
    return damaged ? kExitDamaged : kExitOk;
  }

  fmt::print("log        {} ({} bytes)\n", o.log, s.file_bytes);
  fmt::print("format     version {}, written by {}\n", h.format_version, h.build_id);
  fmt::print("match      {}, started {}\n", h.match_id, h.start_utc);
  fmt::print("scene      '{}', {} bodies, scene hash {:016x}{}\n", h.scene.name, h.scene.agent_count(), h.scene_hash,
             s.scene_hash_matches ? "" : " (this build re-serialises the scene differently: its scene format changed)");
  fmt::print("config     {} Hz, up to {} clients, {} commands/tick/client, timeout {} s, seed {}\n", h.config.tick_hz,
             h.config.max_clients, h.config.max_commands_per_tick, h.config.client_timeout_s, h.config.seed);
  if (s.ticks == 0) fmt::print("ticks      none\n");
  else
    fmt::print("ticks      {}..{} ({} ticks, {:.1f} s of play){}\n", s.first_tick, s.last_tick, s.ticks, seconds,
               s.ticks_missing > 0 ? fmt::format(", {} ticks MISSING (writer dropped them)", s.ticks_missing) : "");
  fmt::print("clients    {} join requests from {} clients, {} leaves; {} clients sent commands\n", join_requests, nonces.size(),
             leaves, commanding.size());
  fmt::print("inputs     {} commands, {} operator changes{}\n", commands, params,
             shutdown_tick > 0 ? fmt::format(", shutdown began before tick {}", shutdown_tick) : "");
  fmt::print("size       {:.0f} bytes/tick on disk ({:.0f} bytes/tick uncompressed, zstd level {}), {} tick blocks of {} ticks\n",
             bytes_per_tick, raw_per_tick, h.writer.zstd_level, s.blocks.size(), h.writer.block_ticks);
  fmt::print("index      {} index records (every {} ticks)\n", s.index_records, h.writer.index_interval_ticks);
  if (!s.keyframes.empty()) {
    const double n = static_cast<double>(s.keyframes.size());
    fmt::print("keyframes  {} world keyframes, every {} ticks (ticks {}..{}), {} bytes in the file ({:.0f} per keyframe, "
               "{:.0f} uncompressed; {:.1f}% of the file)\n",
               s.keyframes.size(), h.writer.keyframe_interval_ticks, s.keyframes.front().tick, s.keyframes.back().tick,
               s.keyframe_bytes, static_cast<double>(s.keyframe_bytes) / n, static_cast<double>(s.keyframe_raw_bytes) / n,
               s.file_bytes > 0 ? 100.0 * static_cast<double>(s.keyframe_bytes) / static_cast<double>(s.file_bytes) : 0.0);
    fmt::print("           {}\n", h.writer.keyframe_snapshot_baselines
                                     ? "snapshot baselines kept: play publishes what the server sent from any seek on"
                                     : "without snapshot baselines: after a seek, play starts every client's snapshots afresh");
  } else if (h.format_version < 2) {
    fmt::print("keyframes  none (format version 1 has no world keyframes): seeking re-simulates from tick 1\n");
  } else {
    fmt::print("keyframes  none ({}): seeking re-simulates from tick 1\n",
               h.writer.keyframe_interval_ticks == 0 ? "the writer had keyframes off" : "none was written");
  }
  if (const std::uint64_t base = matchlog::start_keyframe_tick(s); base > 0)
    fmt::print("starts     after tick {}, from its keyframe (a hot standby's log, or the log of a match it took over)\n",
               base);
  for (const auto& g : matchlog::holes(s))
    fmt::print("gap        ticks {}..{} dropped by the writer (its backlog exceeded its cap), record at byte {}\n", g.first_tick,
               g.first_tick + g.count - 1, g.offset);
  switch (s.end) {
    case matchlog::LogEnd::closed: fmt::print("end        closed cleanly\n"); break;
    case matchlog::LogEnd::unclosed: fmt::print("end        not closed: {}\n", s.problem); break;
    case matchlog::LogEnd::torn: fmt::print("end        TORN TAIL: {}\n", s.problem); break;
    case matchlog::LogEnd::corrupt: fmt::print("end        CORRUPT: {}\n", s.problem); break;
  }
  return damaged ? kExitDamaged : kExitOk;
}

}  // namespace throng::replay
