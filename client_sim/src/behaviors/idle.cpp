// idle: stands still (keeps its facing); still sends one command per tick so the server keeps
// the client alive and its camera current.
#include "steer.h"

namespace throng::client_sim::detail {
namespace {

class Idle final : public Mover {
 public:
  std::string_view name() const override { return "idle"; }
  Intent intent(const BehaviorContext& ctx) override {
    return Intent{0, 0, facing_of(0, 0, ctx.self.yaw), 0};
  }
};

}  // namespace

std::unique_ptr<Behavior> make_idle() { return std::make_unique<Idle>(); }

}  // namespace throng::client_sim::detail
