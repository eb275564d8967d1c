// The header record's JSON, and the scene made self-contained before it is stored.
#include "throng/matchlog/log_header.h"

#include <chrono>
#include <ctime>
#include <fstream>
#include <sstream>

#include <fmt/format.h>
#include <xxhash.h>

#include "throng/matchlog/format.h"
#include "throng/protocol/messages.h"
#include "throng/scene/scene_error.h"
#include "throng/scene/scene_json.h"

namespace throng::matchlog {
namespace {

using OJson = nlohmann::ordered_json;
using Json = nlohmann::json;

nlohmann::json read_document(const std::string& file, const char* what) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw LogError(fmt::format("cannot inline the scene's {} file '{}': cannot open it", what, file));
  std::ostringstream buf;
  buf << in.rdbuf();
  try {
    return nlohmann::json::parse(buf.str());
  } catch (const nlohmann::json::exception& e) {
    throw LogError(fmt::format("cannot inline the scene's {} file '{}': {}", what, file, e.what()));
  }
}

const Json& field(const Json& j, const char* key, const char* where) {
  if (!j.is_object() || !j.contains(key)) throw LogError(fmt::format("log header: {}{} is missing", where, key));
  return j.at(key);
}

template <class T>
T get(const Json& j, const char* key, const char* where = "") {
  const Json& v = field(j, key, where);
  try {
    return v.get<T>();
  } catch (const nlohmann::json::exception&) {
    throw LogError(fmt::format("log header: {}{} has the wrong type ({})", where, key, v.type_name()));
  }
}

std::uint64_t parse_hex64(const std::string& s, const char* key) {
  try {
    std::size_t used = 0;
    const std::uint64_t v = std::stoull(s, &used, 16);
    if (used != s.size()) throw std::invalid_argument(s);
    return v;
  } catch (const std::exception&) {
    throw LogError(fmt::format("log header: {} '{}' is not a hexadecimal number", key, s));
  }
}

}  // namespace

scene::SceneDef self_contained_scene(const scene::SceneDef& scene) {
  scene::SceneDef s = scene;
  if (!s.params.file.empty()) {
    s.params.inline_json = read_document(s.params.file, "parameter table").dump();
    s.params.file.clear();
  }
  if (!s.policy.file.empty()) {
    s.policy.inline_json = read_document(s.policy.file, "push policy").dump();
    s.policy.file.clear();
  }
  return s;
}

OJson config_to_json(const match::MatchConfig& c) {
  OJson j;
  j["tick_hz"] = c.tick_hz;
  j["max_clients"] = c.max_clients;
  j["client_timeout_s"] = c.client_timeout_s;
  j["max_commands_per_tick"] = c.max_commands_per_tick;
  j["player_speed_mps"] = c.player_speed_mps;
  j["npc_speed_mps"] = c.npc_speed_mps;
  j["camera_limit_m"] = c.camera_limit_m;
  j["seed"] = c.seed;
  OJson i;
  i["radius_m"] = c.interest.radius_m;
  i["exit_hysteresis"] = c.interest.exit_hysteresis;
  i["budget_bytes"] = c.interest.budget_bytes;
  i["keepalive_ticks"] = c.interest.keepalive_ticks;
  i["removed_repeat"] = c.interest.removed_repeat;
  j["interest"] = i;
  return j;
}

match::MatchConfig config_from_json(const Json& j) {
  match::MatchConfig c;
  const char* w = "config.";
  c.tick_hz = get<std::uint32_t>(j, "tick_hz", w);
  c.max_clients = get<std::uint32_t>(j, "max_clients", w);
  c.client_timeout_s = get<double>(j, "client_timeout_s", w);
  c.max_commands_per_tick = get<std::uint32_t>(j, "max_commands_per_tick", w);
  c.player_speed_mps = get<double>(j, "player_speed_mps", w);
  c.npc_speed_mps = get<double>(j, "npc_speed_mps", w);
  c.camera_limit_m = get<double>(j, "camera_limit_m", w);
  c.seed = get<std::uint64_t>(j, "seed", w);
  const Json& i = field(j, "interest", w);
  const char* wi = "config.interest.";
  c.interest.radius_m = get<double>(i, "radius_m", wi);
  c.interest.exit_hysteresis = get<double>(i, "exit_hysteresis", wi);
  c.interest.budget_bytes = get<std::uint32_t>(i, "budget_bytes", wi);
  c.interest.keepalive_ticks = get<std::uint32_t>(i, "keepalive_ticks", wi);
  c.interest.removed_repeat = get<std::uint32_t>(i, "removed_repeat", wi);
  return c;
}

LogHeader stamp_header(LogHeader header) {
  header.format_version = kFormatVersion;
  if (header.build_id.empty()) header.build_id = default_build_id();
  header.scene = self_contained_scene(header.scene);
  header.start_unix_ms = std::chrono::duration_cast<std::chrono::milliseconds>(
                             std::chrono::system_clock::now().time_since_epoch()).count();
  header.start_utc = format_utc_ms(header.start_unix_ms);
  return header;
}

std::string format_utc_ms(std::int64_t unix_ms) {
  const std::time_t secs = static_cast<std::time_t>(unix_ms / 1000);
  std::tm tm{};
  gmtime_r(&secs, &tm);
  return fmt::format("{:04}-{:02}-{:02}T{:02}:{:02}:{:02}.{:03}Z", tm.tm_year + 1900, tm.tm_mon + 1, tm.tm_mday,
                     tm.tm_hour, tm.tm_min, tm.tm_sec, static_cast<int>(unix_ms % 1000));
}

std::string header_to_json_text(const LogHeader& h) {
  const OJson scene_json = scene::scene_to_json(h.scene);
  const std::string scene_text = scene_json.dump();
  OJson j;
  j["format"] = "throng-match-log";
  j["format_version"] = h.format_version;
  j["build_id"] = h.build_id;
  j["match_id"] = h.match_id;
  j["start_utc"] = h.start_utc;
  j["start_unix_ms"] = h.start_unix_ms;
  j["tick_hz"] = h.config.tick_hz;
  j["first_tick"] = 1;
  j["protocol_version"] = protocol::kProtocolVersion;
  j["scene_hash"] = fmt::format("{:016x}", XXH3_64bits(scene_text.data(), scene_text.size()));
  OJson w;
  w["block_ticks"] = h.writer.block_ticks;
  w["index_interval_ticks"] = h.writer.index_interval_ticks;
  w["fsync_interval_ms"] = h.writer.fsync_interval_ms;
  w["zstd_level"] = h.writer.zstd_level;
  w["keyframe_interval_ticks"] = h.writer.keyframe_interval_ticks;
  w["keyframe_snapshot_baselines"] = h.writer.keyframe_snapshot_baselines;
  j["writer"] = w;
  j["config"] = config_to_json(h.config);
  j["scene"] = scene_json;
  return j.dump();
}

LogHeader header_from_json_text(const std::string& text) {
  Json j;
  try {
    j = Json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    throw LogError(std::string("log header: malformed JSON: ") + e.what());
  }
  if (!j.is_object()) throw LogError("log header: not a JSON object");
  if (get<std::string>(j, "format") != "throng-match-log") throw LogError("log header: 'format' is not throng-match-log");
  LogHeader h;
  h.format_version = get<std::uint32_t>(j, "format_version");
  h.build_id = get<std::string>(j, "build_id");
  h.match_id = get<std::string>(j, "match_id");
  h.start_utc = get<std::string>(j, "start_utc");
  h.start_unix_ms = get<std::int64_t>(j, "start_unix_ms");
  if (get<std::uint64_t>(j, "first_tick") != 1) throw LogError("log header: first_tick must be 1 (logs start with the match)");
  const Json& w = field(j, "writer", "");
  h.writer.block_ticks = get<std::uint32_t>(w, "block_ticks", "writer.");
  h.writer.index_interval_ticks = get<std::uint32_t>(w, "index_interval_ticks", "writer.");
  h.writer.fsync_interval_ms = get<std::uint32_t>(w, "fsync_interval_ms", "writer.");
  h.writer.zstd_level = get<int>(w, "zstd_level", "writer.");
  if (w.contains("keyframe_interval_ticks"))  // absent in format version 1
    h.writer.keyframe_interval_ticks = get<std::uint32_t>(w, "keyframe_interval_ticks", "writer.");
  if (w.contains("keyframe_snapshot_baselines"))  // absent before keyframes could leave them out
    h.writer.keyframe_snapshot_baselines = get<bool>(w, "keyframe_snapshot_baselines", "writer.");
  h.config = config_from_json(field(j, "config", ""));
  if (get<std::uint32_t>(j, "tick_hz") != h.config.tick_hz) throw LogError("log header: tick_hz disagrees with config.tick_hz");
  h.scene_hash = parse_hex64(get<std::string>(j, "scene_hash"), "scene_hash");
  try {
    h.scene = scene::scene_from_json(field(j, "scene", ""));
  } catch (const scene::SceneError& e) {
    throw LogError(std::string("log header: the scene does not load in this build: ") + e.what());
  }
  return h;
}

}  // namespace throng::matchlog
