#pragma once
// The header record: everything needed to rebuild the match before its first tick.
#include <cstdint>
#include <string>

#include <nlohmann/json.hpp>

#include "throng/match/match_config.h"
#include "throng/scene/scene_def.h"

namespace throng::matchlog {

// How the writer was configured (stored for info; the reader does not need it).
struct WriterSettingsRecord {
  std::uint32_t block_ticks = 0;
  std::uint32_t index_interval_ticks = 0;
  std::uint32_t fsync_interval_ms = 0;
  int zstd_level = 0;  // 0 = tick blocks stored raw
  std::uint32_t keyframe_interval_ticks = 0;  // v2; 0 = no keyframes (and every v1 log)
  // Keyframes hold the snapshot baselines (absent in logs written before they could be left out,
  // which always held them).
  bool keyframe_snapshot_baselines = true;
};

struct LogHeader {
  // --- given by the caller ---------------------------------------------------------------------
  std::string build_id;      // empty: default_build_id()
  std::string match_id;      // the id the Match was constructed with
  scene::SceneDef scene;     // exactly the SceneDef passed to Match (already scaled)
  match::MatchConfig config; // exactly the MatchConfig passed to Match
  // --- filled by the writer ---------------------------------------------------------------------
  std::uint32_t format_version = 0;
  std::int64_t start_unix_ms = 0;  // wall clock when begin() was called
  std::string start_utc;           // the same as "YYYY-MM-DDTHH:MM:SS.mmmZ" (fixed width)
  std::uint64_t scene_hash = 0;    // XXH3-64 of the scene JSON text as stored
  WriterSettingsRecord writer;
};

// The scene as stored: parameter-table / push-policy files are read and inlined, so the log
// replays on a machine without the files. Throws LogError if a file cannot be read or parsed.
scene::SceneDef self_contained_scene(const scene::SceneDef& scene);

nlohmann::ordered_json config_to_json(const match::MatchConfig& c);
match::MatchConfig config_from_json(const nlohmann::json& j);  // throws LogError

// Header <-> JSON text of the header record. header_from_json throws LogError naming the field.
std::string header_to_json_text(const LogHeader& h);
LogHeader header_from_json_text(const std::string& text);

// The header as this build writes it (the writer's begin() and a primary's answer to a standby):
// this format version, the build id when empty, the scene made self-contained, the start time now.
// `writer` is left as given. Throws LogError as self_contained_scene does.
LogHeader stamp_header(LogHeader header);

// Wall-clock time as the header stores it (fixed width, so two logs of the same inputs differ
// only in these bytes and the header's CRC).
std::string format_utc_ms(std::int64_t unix_ms);

}  // namespace throng::matchlog
