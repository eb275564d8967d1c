#pragma once
// Contact pairs near a camera: what the debug overlay (protocol kActionContacts, the ContactPairs
// topic) is sent, chosen from World::push_events() after a step. The live server (Match, for the
// clients it granted the channel) and throng-view's log mode (straight from a re-simulated World)
// choose the same way:
//  - body-body pairs only: a body against fixed scenery has no partner position to place a
//    contact plane between, and its share is 1 (or the soft share) by definition;
//  - a pair is near when its midpoint is within radius_m of the camera (x, y; metres);
//  - nearest first, ties by a then b (object id values): deterministic, whatever the threads;
//  - at most max_pairs; pairs_near says how many were near before the cap.
// Reading only: the world, and so the state hash, never depends on whether anyone looks.
// No allocation once warm (the buffers grow to the largest tick's push-event count).
#include <cstdint>
#include <vector>

#include "throng/protocol/messages.h"

namespace throng {
class World;
}

namespace throng::match {

class ContactSelector {
 public:
  // Once per step: the body-body push events with their midpoints.
  void prepare(const World& world);
  // Fills out.pairs_near/camera/radius and the pair arrays (cleared first); client_id and tick
  // are the caller's. radius_m <= 0 selects nothing.
  void select(double camera_x, double camera_y, double radius_m, std::uint32_t max_pairs, protocol::ContactPairs& out);
  // Body-body pairs prepared this step.
  std::size_t prepared() const { return pairs_.size(); }

 private:
  struct Pair {
    double mx, my;  // midpoint of the two centres
    std::uint32_t a, b;
    float share_a, depth_m, push_m;
  };
  struct Near {
    double d2;
    std::uint32_t pair;
  };
  std::vector<Pair> pairs_;
  std::vector<Near> near_;
};

}  // namespace throng::match
