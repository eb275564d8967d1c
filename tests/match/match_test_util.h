#pragma once
// Small scenes and message builders shared by the match tests.
#include <cstdint>
#include <string>
#include <utility>

#include "throng/match/match.h"
#include "throng/protocol/messages.h"
#include "throng/scene/scene_def.h"

namespace throng::match::test {

// Two small armies facing each other along x: faction 1 / group 1 on the left, faction 2 /
// group 2 on the right, a wall to the north and a bush to the south.
inline scene::SceneDef two_armies(std::uint32_t per_side = 20, double gap_m = 30.0, double half_m = 5.0) {
  scene::SceneDef s;
  s.name = "two_armies";
  s.seed = 7;
  scene::Scenery wall;
  wall.kind = scene::SceneryKind::box;
  wall.archetype = "wall";
  wall.centre = {0.0, 30.0, 1.0};
  wall.half_extents_m = {5.0, 0.4, 1.0};
  wall.yaw_deg = 30.0;
  s.scenery.push_back(wall);
  scene::Scenery bush;
  bush.kind = scene::SceneryKind::cylinder;
  bush.archetype = "bush";
  bush.centre = {0.0, -30.0, 0.6};
  bush.radius_m = 1.5;
  bush.half_height_m = 0.6;
  s.scenery.push_back(bush);
  for (int side = 0; side < 2; ++side) {
    scene::SpawnGroup g;
    g.name = side == 0 ? "red" : "blue";
    g.count = per_side;
    g.shape.kind = scene::SpawnAreaKind::rect;
    g.shape.centre = {side == 0 ? -gap_m / 2 : gap_m / 2, 0.0};
    g.shape.half_extents_m = {half_m, half_m};
    g.archetype = "infantry";
    g.faction = side == 0 ? 1u : 2u;
    g.group = side == 0 ? 1u : 2u;
    s.spawns.push_back(g);
  }
  return s;
}

inline MatchConfig small_config() {
  MatchConfig c;
  c.tick_hz = 30;
  c.max_clients = 8;
  c.client_timeout_s = 5.0;
  c.max_commands_per_tick = 4;
  return c;
}

inline protocol::JoinRequest join_request(std::uint64_t nonce, std::string name = "bot") {
  protocol::JoinRequest r;
  r.client_nonce = nonce;
  r.name = std::move(name);
  return r;
}

inline protocol::JoinRequest leave_request(std::uint64_t nonce, std::uint32_t client_id) {
  protocol::JoinRequest r;
  r.client_nonce = nonce;
  r.leave = true;
  r.client_id = client_id;
  return r;
}

inline protocol::Command command(std::uint32_t client, std::uint32_t entity, std::uint32_t seq, float mx = 0.0f,
                                 float my = 0.0f) {
  protocol::Command c;
  c.client_id = client;
  c.entity = entity;
  c.sequence = seq;
  c.move_x = mx;
  c.move_y = my;
  return c;
}

// Joins one client and runs the tick; returns its accepted reply.
inline protocol::JoinReply join_one(Match& m, Outbox& out, std::uint64_t nonce, std::string name = "bot") {
  m.inputs().push(join_request(nonce, std::move(name)));
  m.tick(out);
  for (const auto& r : out.join_replies) {
    if (r.client_nonce == nonce) return r;
  }
  return {};
}

}  // namespace throng::match::test
