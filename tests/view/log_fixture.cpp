#include "log_fixture.h"

#include <cmath>
#include <vector>

#include "throng/match/match.h"
#include "throng/matchlog/writer.h"
#include "throng/scene/builtin_scenes.h"
#include "throng/scene/scale.h"
#include "throng/world/world.h"

namespace throng::view::testing {

RecordedLog record_log(const std::filesystem::path& path, std::uint64_t ticks, std::uint64_t bodies) {
  const scene::SceneDef scene = scene::scale_scene(scene::builtin_scene("battle"), bodies);
  match::MatchConfig config;
  config.tick_hz = 30;
  config.max_clients = 4;
  match::Match m(scene, config, "view-log-test");
  matchlog::MatchLogWriter writer(path.string());
  matchlog::LogHeader header;
  header.build_id = "view-test";
  header.match_id = "view-log-test";
  header.scene = scene;
  header.config = config;
  writer.begin(header);

  match::Outbox out;
  std::vector<std::uint32_t> entity(3, 0), seq(3, 0);
  for (std::uint64_t t = 1; t <= ticks; ++t) {
    if (t == 2 || t == 3) {
      protocol::JoinRequest j;
      j.client_nonce = 700 + t;
      j.name = "walker" + std::to_string(t);
      m.inputs().push(std::move(j));
    }
    for (std::uint32_t c = 1; c <= 2; ++c) {
      if (entity[c] == 0) continue;
      protocol::Command cmd;  // walk in a slow circle, one way per client
      cmd.client_id = c;
      cmd.entity = entity[c];
      cmd.sequence = ++seq[c];
      cmd.last_seen_tick = t - 1;
      const float a = static_cast<float>(t) * 0.02f * (c == 1 ? 1.0f : -1.0f);
      cmd.move_x = 0.8f * std::cos(a);
      cmd.move_y = 0.8f * std::sin(a);
      cmd.facing_rad = std::remainder(a, 6.2831853f);
      m.inputs().push(std::move(cmd));
    }
    std::uint8_t flags = 0;
    if (t == ticks) {
      m.begin_shutdown();
      flags = matchlog::kTickShutdownBegan;
    }
    const match::TickReport& r = m.tick(out);
    for (const auto& reply : out.join_replies)
      if (reply.result == protocol::JoinResult::accepted && reply.client_id < entity.size()) entity[reply.client_id] = reply.entity;
    writer.append_tick(r.tick, m.last_inputs(), r.state_hash, flags);
  }
  writer.close();
  return RecordedLog{ticks, config.tick_hz, m.world().body_count()};
}

}  // namespace throng::view::testing
