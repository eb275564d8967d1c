#include "gateway_loop.h"

#include <array>
#include <condition_variable>
#include <cstdio>
#include <deque>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

#include <fmt/format.h>

#include "display_host.h"
#include "page_server.h"
#include "throng/protocol/dds_transport.h"
#include "throng/protocol/security.h"
#include "throng/view/gateway.h"
#include "throng/view/page_input.h"
#include "throng/view/web_server.h"

namespace throng::view {

namespace {

using namespace std::chrono_literals;

// Filled by DDS threads, drained by the loop.
struct Inbox {
  static constexpr std::size_t kMaxSnapshots = 64;  // the loop is far behind: drop the oldest

  std::mutex mutex;
  std::condition_variable wake;
  std::optional<protocol::MatchInfo> match;
  std::vector<protocol::JoinReply> replies;
  struct Arrived {
    protocol::Snapshot snapshot;
    std::size_t bytes;
    TimePoint at;
  };
  std::deque<Arrived> snapshots;
  std::uint64_t dropped = 0;
  struct ArrivedContacts {
    protocol::ContactPairs contacts;
    std::size_t bytes;
    TimePoint at;
  };
  std::vector<ArrivedContacts> contacts;  // the loop keeps the newest; at most kMaxSnapshots held

  void notify() { wake.notify_one(); }
};

// Written by the web thread, read by the loop.
class InputSlot {
 public:
  void accept(const PageInput& in) {
    std::lock_guard lock(mutex_);
    latest_ = in;
    received_ = Clock::now();
  }
  void reject(InputError e) {
    std::lock_guard lock(mutex_);
    ++errors_[static_cast<std::size_t>(e)];
  }
  void read(std::optional<PageInput>& in, std::optional<TimePoint>& at,
            std::array<std::uint64_t, kInputErrorCount>& errors) const {
    std::lock_guard lock(mutex_);
    in = latest_;
    at = received_;
    errors = errors_;
  }

 private:
  mutable std::mutex mutex_;
  std::optional<PageInput> latest_;
  std::optional<TimePoint> received_;
  std::array<std::uint64_t, kInputErrorCount> errors_{};
};

// One viewer session: the DDS client it joins as, what arrived since the last turn, and what the
// page is shown. run() is the loop; each step of a turn is a method.
class GatewayLoop {
 public:
  GatewayLoop(const ViewOptions& o, WebServer& web, InputSlot& input) : o_(o), web_(web), input_(input), gateway_(options(o)) {}

  int run(const std::atomic<bool>& stop) {
    protocol::ClientTransport transport(transport_options());
    transport_ = &transport;
    start_transport();
    const auto server_wait = std::chrono::milliseconds(static_cast<long>(o_.server_wait_s * 1000));
    if (!transport.wait_for_server(server_wait)) {
      fmt::print(stderr, "throng-view: no server on domain {} within {:g} s\n", o_.domain, o_.server_wait_s);
      return 2;
    }
    transport.send_join(gateway_.join_request(Clock::now()));
    next_command_ = Clock::now();
    next_status_ = Clock::now() + 10s;
    int exit_code = 0;
    while (!stop.load()) {
      const Arrivals a = wait_for_arrivals();
      const TimePoint now = Clock::now();
      if (a.match) on_match_info(*a.match);
      for (const auto& r : a.replies) on_join_reply(r, now);
      if ((exit_code = check_join(now)) != 0) break;
      const bool applied = apply(a, now);
      std::optional<PageInput> in;
      std::optional<TimePoint> in_at;
      std::array<std::uint64_t, kInputErrorCount> errors{};
      input_.read(in, in_at, errors);
      if (applied) show_frame(now, errors);
      send_command(now, in, in_at);
      report(now, errors);
    }
    leave();
    return exit_code;
  }

 private:
  struct Arrivals {
    std::optional<protocol::MatchInfo> match;
    std::vector<protocol::JoinReply> replies;
    std::deque<Inbox::Arrived> snapshots;
    std::vector<Inbox::ArrivedContacts> contacts;
  };

  static GatewayOptions options(const ViewOptions& o) {
    GatewayOptions go;
    go.name = o.name;
    return go;
  }

  protocol::TransportOptions transport_options() const {
    protocol::TransportOptions t;
    t.domain_id = o_.domain;
    t.loopback_only = o_.loopback;
    if (!o_.server.empty()) t.server_endpoint = protocol::parse_endpoint(o_.server);
    t.participant_name = o_.name;
    if (!o_.security_dir.empty()) t.security = protocol::security_files(o_.security_dir, o_.identity);
    return t;
  }

  // DDS threads only fill the inbox; the loop drains it.
  void start_transport() {
    protocol::ClientTransport::Handlers h;
    h.on_match_info = [this](protocol::MatchInfo&& info) {
      {
        std::lock_guard lock(inbox_.mutex);
        inbox_.match = std::move(info);
      }
      inbox_.notify();
    };
    h.on_join_reply = [this, nonce = gateway_.nonce()](protocol::JoinReply&& reply) {
      if (reply.client_nonce != nonce) return;  // other clients' replies
      {
        std::lock_guard lock(inbox_.mutex);
        inbox_.replies.push_back(std::move(reply));
      }
      inbox_.notify();
    };
    h.on_param_reply = [](protocol::ParamReply&&) {};
    h.on_stats = [](protocol::ServerStats&&) {};
    transport_->start(std::move(h));
  }

  // Wakes for the next command, an arrival, or at least every 100 ms to check the stop flag.
  Arrivals wait_for_arrivals() {
    const TimePoint now = Clock::now();
    const TimePoint wake_at = std::min(now + 100ms, gateway_.state() == Gateway::State::joined ? next_command_ : now + 100ms);
    Arrivals a;
    std::unique_lock lock(inbox_.mutex);
    inbox_.wake.wait_until(lock, wake_at, [&] {
      return inbox_.match || !inbox_.replies.empty() || !inbox_.snapshots.empty() || !inbox_.contacts.empty();
    });
    a.match.swap(inbox_.match);
    a.replies.swap(inbox_.replies);
    a.snapshots.swap(inbox_.snapshots);
    a.contacts.swap(inbox_.contacts);
    return a;
  }

  void on_match_info(const protocol::MatchInfo& match) {
    gateway_.on_match_info(match);
    web_.set_greeting(gateway_.match_json());
    if (gateway_.match_ended() && !warned_ended_) {
      warned_ended_ = true;
      fmt::print(stderr, "throng-view: the match ended\n");
    }
  }

  // Accepted: subscribe to the client's snapshots and contacts (the overlay: nothing arrives until
  // the page asks and the server grants it).
  void on_join_reply(const protocol::JoinReply& r, TimePoint now) {
    if (!gateway_.on_join_reply(r)) return;
    fmt::print(stderr, "throng-view: joined as client {}, controlling entity {} (faction {})\n", r.client_id, r.entity,
               static_cast<unsigned>(r.faction));
    transport_->subscribe_snapshots(r.client_id, r.snapshot_partition, [this](protocol::Snapshot&& s, std::size_t bytes) {
      const TimePoint at = Clock::now();
      {
        std::lock_guard lock(inbox_.mutex);
        if (inbox_.snapshots.size() >= Inbox::kMaxSnapshots) {  // the loop is far behind: drop the oldest
          inbox_.snapshots.pop_front();
          ++inbox_.dropped;
        }
        inbox_.snapshots.push_back(Inbox::Arrived{std::move(s), bytes, at});
      }
      inbox_.notify();
    });
    transport_->subscribe_contacts(r.client_id, r.snapshot_partition, [this](protocol::ContactPairs&& c, std::size_t bytes) {
      const TimePoint at = Clock::now();
      {
        std::lock_guard lock(inbox_.mutex);
        if (inbox_.contacts.size() >= Inbox::kMaxSnapshots) inbox_.contacts.erase(inbox_.contacts.begin());
        inbox_.contacts.push_back(Inbox::ArrivedContacts{std::move(c), bytes, at});
      }
      inbox_.notify();
    });
    next_command_ = now;
  }

  // Exit code 3 when the join was refused or never answered; the join is resent every second.
  int check_join(TimePoint now) {
    if (gateway_.state() == Gateway::State::refused) {
      fmt::print(stderr, "throng-view: the server refused the join: {} ({})\n", protocol::to_string(gateway_.reply().result),
                 gateway_.reply().reason);
      return 3;
    }
    if (gateway_.state() == Gateway::State::joining) {
      const auto join_timeout = std::chrono::milliseconds(static_cast<long>(o_.join_timeout_s * 1000));
      if (now - *gateway_.join_sent_at() > join_timeout) {
        fmt::print(stderr, "throng-view: no join reply from the server within {:g} s\n", o_.join_timeout_s);
        return 3;
      }
      if (now - *gateway_.last_join_sent_at() >= 1s) transport_->send_join(gateway_.join_request(now));
    }
    return 0;
  }

  // True when a snapshot changed the world.
  bool apply(const Arrivals& a, TimePoint now) {
    bool applied = false;
    for (const auto& c : a.contacts) gateway_.on_contacts(c.contacts, c.bytes, c.at);
    for (const auto& s : a.snapshots) applied |= gateway_.on_snapshot(s.snapshot, s.bytes, s.at);
    if (!a.snapshots.empty()) {
      last_snapshot_at_ = now;
      warned_silent_ = false;
    }
    return applied;
  }

  // The page protocol promises the match first: no frames before a MatchInfo arrived (it can
  // reach us after the join reply and the first snapshots).
  void show_frame(TimePoint now, const std::array<std::uint64_t, kInputErrorCount>& errors) {
    if (web_.sessions() == 0 || !gateway_.has_match()) return;
    FrameExtras extras;
    extras.input_errors = errors;
    extras.pages = web_.sessions();
    web_.broadcast(gateway_.frame_json(now, extras));
  }

  // One command per server tick while joined; after falling behind, no burst.
  void send_command(TimePoint now, const std::optional<PageInput>& in, const std::optional<TimePoint>& in_at) {
    if (gateway_.state() != Gateway::State::joined || now < next_command_) return;
    if (auto cmd = gateway_.make_command(now, in, in_at)) transport_->send_command(*cmd);
    const auto period =
        std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / gateway_.world().tick_hz()));
    next_command_ += period;
    if (next_command_ < now) next_command_ = now + period;
  }

  void report(TimePoint now, const std::array<std::uint64_t, kInputErrorCount>& errors) {
    report_rejections(errors, reported_errors_);
    if (last_snapshot_at_ && now - *last_snapshot_at_ > 5s && !warned_silent_) {
      warned_silent_ = true;
      fmt::print(stderr, "throng-view: no snapshot from the server for 5 s\n");
    }
    if (o_.quiet || now < next_status_) return;
    next_status_ = now + 10s;
    const auto lat = gateway_.latency_ms(now);
    fmt::print(stderr, "throng-view: tick {}  objects {} (in view {})  latency {}  {:.1f} kbit/s  contacts {:.1f} kbit/s  pages {}\n",
               gateway_.world().newest_tick().value_or(0), gateway_.world().object_count(), gateway_.objects_in_view(),
               lat ? fmt::format("{:.0f} ms", *lat) : std::string("-"), gateway_.kbit_per_s(now),
               gateway_.contacts_kbit_per_s(now), web_.sessions());
  }

  // Waits (bounded) for the server to confirm the leave, so the reliable message is not lost with
  // the participant.
  void leave() {
    auto request = gateway_.leave_request();
    if (!request) return;
    transport_->send_join(*request);
    const TimePoint until = Clock::now() + 1s;
    std::unique_lock lock(inbox_.mutex);
    inbox_.wake.wait_until(lock, until, [&] {
      for (const auto& r : inbox_.replies)
        if (r.result == protocol::JoinResult::left) return true;
      return false;
    });
  }

  const ViewOptions& o_;
  WebServer& web_;
  InputSlot& input_;
  Inbox inbox_;
  Gateway gateway_;
  protocol::ClientTransport* transport_ = nullptr;  // run()'s, while it runs
  TimePoint next_command_{}, next_status_{};
  std::array<std::uint64_t, kInputErrorCount> reported_errors_{};
  std::optional<TimePoint> last_snapshot_at_;
  bool warned_silent_ = false, warned_ended_ = false;
};

}  // namespace

int run_gateway(const ViewOptions& o, const std::atomic<bool>& stop) {
  InputSlot input;
  // The web side first: a port in use is reported before anything else happens.
  std::optional<WebServer> web;
  if (!open_page_server<PageInput>(web, o.bind, o.port, o.web_root, parse_page_message, input)) return 1;
  fmt::print("view at http://{}:{}/\n", display_host(o.bind), web->port());
  std::fflush(stdout);
  int code = 1;
  try {
    GatewayLoop loop(o, *web, input);
    code = loop.run(stop);
  } catch (const protocol::TransportError& e) {
    fmt::print(stderr, "throng-view: DDS error: {}\n", e.what());
    code = 1;
  }
  web->stop();
  return code;
}

}  // namespace throng::view
