// World::restore_state: the engine's section of a checkpoint (keyframes in match logs, seeking in
// the viewer and throng-replay). A world that accepts the bytes must then step (so state it took
// in but cannot use shows up here, not a tick later in production). Input: one world section.
// Bad input throws CheckpointError and leaves the world unchanged.
#include <cstdint>
#include <cstdlib>
#include <span>
#include <vector>

#include "match_test_util.h"
#include "throng/core/byte_io.h"
#include "throng/scene/build_scene.h"

using namespace throng;

namespace {

struct State {
  scene::BuiltScene built;
  std::vector<std::uint8_t> start;
};

State& state() {
  static State* s = [] {
    auto* st = new State{scene::build_scene(match::test::two_armies(4)), {}};
    scene::step_scene(st->built);
    st->built.world.save_state(st->start);
    return st;
  }();
  return *s;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  State& s = state();
  s.built.world.restore_state(s.start);
  try {
    s.built.world.restore_state(std::span<const std::uint8_t>(data, size));
  } catch (const CheckpointError&) {
    return 0;
  }
  s.built.world.step();
  return 0;
}
