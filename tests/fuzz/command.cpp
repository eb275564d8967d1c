// Commands as the server receives them: the field checks (check_command_fields, clamped_move) and
// then the match applying them (Match::tick) for a joined client. Each input starts from the same
// checkpoint, so a crash reproduces from its input alone. Input: a flag byte then a Command (in
// fuzz_bytes.h's layout), repeated; flag bit 0 = send as the joined client with its entity.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <vector>

#include "command_validation.h"
#include "fuzz_bytes.h"
#include "match_test_util.h"

using namespace throng;

namespace {

struct State {
  match::MatchConfig config;
  std::unique_ptr<match::Match> match;
  match::Outbox out;
  std::uint32_t client_id = 0, entity = 0;
  std::vector<std::uint8_t> start;  // checkpoint after the join
};

State& state() {
  static State* s = [] {
    auto* st = new State;
    st->config = match::test::small_config();
    st->config.worker_threads = 1;
    st->match = std::make_unique<match::Match>(match::test::two_armies(4), st->config, "fuzz");
    st->match->inputs().push(match::test::join_request(1));
    st->match->tick(st->out);
    if (st->out.join_replies.empty() || st->out.join_replies[0].result != protocol::JoinResult::accepted) std::abort();
    st->client_id = st->out.join_replies[0].client_id;
    st->entity = st->out.join_replies[0].entity;
    st->match->save_checkpoint(st->start);
    return st;
  }();
  return *s;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  State& s = state();
  s.match->restore_checkpoint(s.start);
  fuzz::In in(data, size);
  for (int i = 0; i < 8 && !in.empty(); ++i) {
    const auto flags = in.get<std::uint8_t>();
    protocol::Command c = fuzz::read_command(in);
    if (flags & 1) {
      c.client_id = s.client_id;
      c.entity = s.entity;
    }
    if (!match::check_command_fields(c, s.config)) {
      const match::MoveVector m = match::clamped_move(c);
      if (!std::isfinite(m.x) || !std::isfinite(m.y) || std::hypot(m.x, m.y) > 1.0 + 1e-9) std::abort();
    }
    s.match->inputs().push(std::move(c));
  }
  s.match->tick(s.out);
  return 0;
}
