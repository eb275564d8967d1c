// Client side of the snapshot channel: the pose codec (decode_poses) and the bots' / viewer's world
// model (ClientWorld::apply), fed a few snapshots in a row (so baselines, removals, interpolation
// and expiry see fuzzed history). Input: snapshots in fuzz_bytes.h's layout, back to back.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <vector>

#include "fuzz_bytes.h"
#include "throng/client_sim/client_world.h"
#include "throng/protocol/codec.h"

using namespace throng;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  fuzz::In in(data, size);
  client_sim::ClientWorld world;
  std::vector<protocol::Pose> poses;
  for (int i = 0; i < 6 && !in.empty(); ++i) {
    const protocol::Snapshot snap = fuzz::read_snapshot(in);
    poses.clear();
    try {
      protocol::decode_poses(snap, poses);
      for (std::size_t k = 1; k < poses.size(); ++k)
        if (poses[k].id <= poses[k - 1].id) std::abort();  // documented: ids strictly ascending
    } catch (const protocol::DecodeError&) {
    }
    world.apply(snap);  // counts a malformed snapshot; must never throw
    world.for_each([](const client_sim::ObjectState& o) {
      if (!std::isfinite(o.x) || !std::isfinite(o.y) || !std::isfinite(o.z)) std::abort();
    });
    for (const auto& p : poses) (void)world.object(p.id);
    (void)world.own_pose();
  }
  return 0;
}
