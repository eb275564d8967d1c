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

}  // namespace

int run_gateway(const ViewOptions& o, const std::atomic<bool>& stop) {
  Inbox inbox;
  InputSlot input;

  // The web side first: a port in use is reported before anything else happens.
  std::optional<WebServer> web;
  if (!open_page_server<PageInput>(web, o.bind, o.port, o.web_root, parse_page_message, input)) return 1;
  fmt::print("view at http://{}:{}/\n", display_host(o.bind), web->port());
  std::fflush(stdout);

  GatewayOptions go;
  go.name = o.name;
  Gateway gateway(go);

  try {
    protocol::TransportOptions t;
    t.domain_id = o.domain;
    t.loopback_only = o.loopback;
    if (!o.server.empty()) t.tcp_server = protocol::parse_tcp_endpoint(o.server);
    t.participant_name = o.name;
    if (!o.security_dir.empty()) t.security = protocol::security_files(o.security_dir, o.identity);
    protocol::ClientTransport transport(t);
    protocol::ClientTransport::Handlers h;
    h.on_match_info = [&inbox](protocol::MatchInfo&& info) {
      {
        std::lock_guard lock(inbox.mutex);
        inbox.match = std::move(info);
      }
      inbox.notify();
    };
    h.on_join_reply = [&inbox, nonce = gateway.nonce()](protocol::JoinReply&& reply) {
      if (reply.client_nonce != nonce) return;  // other clients' replies
      {
        std::lock_guard lock(inbox.mutex);
        inbox.replies.push_back(std::move(reply));
      }
      inbox.notify();
    };
    h.on_param_reply = [](protocol::ParamReply&&) {};
    h.on_stats = [](protocol::ServerStats&&) {};
    transport.start(std::move(h));

    const auto server_wait = std::chrono::milliseconds(static_cast<long>(o.server_wait_s * 1000));
    if (!transport.wait_for_server(server_wait)) {
      fmt::print(stderr, "throng-view: no server on domain {} within {:g} s\n", o.domain, o.server_wait_s);
      return 2;
    }

    const auto join_timeout = std::chrono::milliseconds(static_cast<long>(o.join_timeout_s * 1000));
    transport.send_join(gateway.join_request(Clock::now()));

    TimePoint next_command = Clock::now();
    TimePoint next_status = Clock::now() + 10s;
    std::array<std::uint64_t, kInputErrorCount> reported_errors{};
    std::optional<TimePoint> last_snapshot_at;
    bool warned_silent = false, warned_ended = false;
    int exit_code = 0;

    while (!stop.load()) {
      const TimePoint now0 = Clock::now();
      // Wake for the next command, a snapshot, or at least every 100 ms to check the stop flag.
      const TimePoint wake_at = std::min(now0 + 100ms, gateway.state() == Gateway::State::joined ? next_command : now0 + 100ms);
      std::optional<protocol::MatchInfo> match;
      std::vector<protocol::JoinReply> replies;
      std::deque<Inbox::Arrived> arrived;
      std::vector<Inbox::ArrivedContacts> arrived_contacts;
      {
        std::unique_lock lock(inbox.mutex);
        inbox.wake.wait_until(lock, wake_at, [&] {
          return inbox.match || !inbox.replies.empty() || !inbox.snapshots.empty() || !inbox.contacts.empty();
        });
        match.swap(inbox.match);
        replies.swap(inbox.replies);
        arrived.swap(inbox.snapshots);
        arrived_contacts.swap(inbox.contacts);
      }
      const TimePoint now = Clock::now();

      if (match) {
        gateway.on_match_info(*match);
        web->set_greeting(gateway.match_json());
        if (gateway.match_ended() && !warned_ended) {
          warned_ended = true;
          fmt::print(stderr, "throng-view: the match ended\n");
        }
      }
      for (const auto& r : replies) {
        if (!gateway.on_join_reply(r)) continue;
        fmt::print(stderr, "throng-view: joined as client {}, controlling entity {} (faction {})\n", r.client_id, r.entity,
                   static_cast<unsigned>(r.faction));
        transport.subscribe_snapshots(r.client_id, r.snapshot_partition, [&inbox](protocol::Snapshot&& s, std::size_t bytes) {
          const TimePoint at = Clock::now();
          {
            std::lock_guard lock(inbox.mutex);
            if (inbox.snapshots.size() >= Inbox::kMaxSnapshots) {
              inbox.snapshots.pop_front();
              ++inbox.dropped;
            }
            inbox.snapshots.push_back(Inbox::Arrived{std::move(s), bytes, at});
          }
          inbox.notify();
        });
        // The contacts overlay: nothing arrives until the page asks and the server grants it.
        transport.subscribe_contacts(r.client_id, r.snapshot_partition, [&inbox](protocol::ContactPairs&& c, std::size_t bytes) {
          const TimePoint at = Clock::now();
          {
            std::lock_guard lock(inbox.mutex);
            if (inbox.contacts.size() >= Inbox::kMaxSnapshots) inbox.contacts.erase(inbox.contacts.begin());
            inbox.contacts.push_back(Inbox::ArrivedContacts{std::move(c), bytes, at});
          }
          inbox.notify();
        });
        next_command = now;
      }
      if (gateway.state() == Gateway::State::refused) {
        fmt::print(stderr, "throng-view: the server refused the join: {} ({})\n", protocol::to_string(gateway.reply().result),
                   gateway.reply().reason);
        exit_code = 3;
        break;
      }
      if (gateway.state() == Gateway::State::joining) {
        if (now - *gateway.join_sent_at() > join_timeout) {
          fmt::print(stderr, "throng-view: no join reply from the server within {:g} s\n", o.join_timeout_s);
          exit_code = 3;
          break;
        }
        if (now - *gateway.last_join_sent_at() >= 1s) transport.send_join(gateway.join_request(now));
      }

      bool applied = false;
      for (const auto& a : arrived_contacts) gateway.on_contacts(a.contacts, a.bytes, a.at);
      for (const auto& a : arrived) applied |= gateway.on_snapshot(a.snapshot, a.bytes, a.at);
      if (!arrived.empty()) {
        last_snapshot_at = now;
        warned_silent = false;
      }

      std::optional<PageInput> in;
      std::optional<TimePoint> in_at;
      std::array<std::uint64_t, kInputErrorCount> errors{};
      input.read(in, in_at, errors);

      // The page protocol promises the match first: no frames before a MatchInfo arrived (it can
      // reach us after the join reply and the first snapshots).
      if (applied && web->sessions() > 0 && gateway.has_match()) {
        FrameExtras extras;
        extras.input_errors = errors;
        extras.pages = web->sessions();
        web->broadcast(gateway.frame_json(now, extras));
      }

      if (gateway.state() == Gateway::State::joined && now >= next_command) {
        if (auto cmd = gateway.make_command(now, in, in_at)) transport.send_command(*cmd);
        const auto period = std::chrono::duration_cast<Clock::duration>(
            std::chrono::duration<double>(1.0 / gateway.world().tick_hz()));
        next_command += period;
        if (next_command < now) next_command = now + period;  // fell behind: do not burst
      }

      report_rejections(errors, reported_errors);
      if (last_snapshot_at && now - *last_snapshot_at > 5s && !warned_silent) {
        warned_silent = true;
        fmt::print(stderr, "throng-view: no snapshot from the server for 5 s\n");
      }
      if (!o.quiet && now >= next_status) {
        next_status = now + 10s;
        const auto lat = gateway.latency_ms(now);
        fmt::print(stderr, "throng-view: tick {}  objects {} (in view {})  latency {}  {:.1f} kbit/s  contacts {:.1f} kbit/s  pages {}\n",
                   gateway.world().newest_tick().value_or(0), gateway.world().object_count(), gateway.objects_in_view(),
                   lat ? fmt::format("{:.0f} ms", *lat) : std::string("-"), gateway.kbit_per_s(now),
                   gateway.contacts_kbit_per_s(now), web->sessions());
      }
    }

    if (auto leave = gateway.leave_request()) {
      transport.send_join(*leave);
      // Wait (bounded) for the server to confirm, so the reliable leave is not lost with the participant.
      const TimePoint until = Clock::now() + 1s;
      std::unique_lock lock(inbox.mutex);
      inbox.wake.wait_until(lock, until, [&] {
        for (const auto& r : inbox.replies)
          if (r.result == protocol::JoinResult::left) return true;
        return false;
      });
    }
    web->stop();
    return exit_code;
  } catch (const protocol::TransportError& e) {
    fmt::print(stderr, "throng-view: DDS error: {}\n", e.what());
    return 1;
  }
}

}  // namespace throng::view
