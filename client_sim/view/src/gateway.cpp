#include "throng/view/gateway.h"

#include <algorithm>
#include <iterator>
#include <vector>

#include <fmt/format.h>

#include "throng/protocol/contacts.h"
#include "throng/view/match_json.h"

namespace throng::view {

namespace {

constexpr auto kWindow = std::chrono::seconds(1);
// Contact pairs older than this many ticks behind the newest snapshot are not drawn (the server
// stopped sending them, or they were lost).
constexpr std::uint64_t kContactsMaxAgeTicks = 15;

}  // namespace

Gateway::Gateway(GatewayOptions options)
    : options_(std::move(options)), join_(options_.nonce, options_.name), world_(options_.world) {
  options_.nonce = join_.nonce();  // the drawn one when the options left it 0
}

protocol::JoinRequest Gateway::join_request(TimePoint now) { return join_.join_request(now); }

bool Gateway::on_join_reply(const protocol::JoinReply& reply) { return join_.on_join_reply(reply); }

std::optional<protocol::JoinRequest> Gateway::leave_request() { return join_.leave_request(); }

void Gateway::on_match_info(const protocol::MatchInfo& info) {
  match_ = std::make_shared<const client_sim::MatchView>(info);
  world_.set_match(match_);
  match_json_ = match_info_json(info, "live");
}

bool Gateway::on_snapshot(const protocol::Snapshot& snap, std::size_t wire_bytes, TimePoint now) {
  if (join_.state() != State::joined || snap.client_id != join_.reply().client_id) return false;
  if (!first_snapshot_) first_snapshot_ = now;
  bytes_window_.emplace_back(now, wire_bytes);
  if (world_.apply(snap) != client_sim::ClientWorld::ApplyResult::applied) {
    expire_windows(now);
    return false;
  }
  objects_in_view_ = snap.objects_in_view;
  last_applied_sequence_ = std::max(last_applied_sequence_, snap.last_applied_sequence);
  while (!pending_.empty() && pending_.front().sequence <= snap.last_applied_sequence) {
    latency_window_.emplace_back(now, std::chrono::duration<double, std::milli>(now - pending_.front().sent).count());
    pending_.pop_front();
  }
  expire_windows(now);
  return true;
}

bool Gateway::on_contacts(const protocol::ContactPairs& c, std::size_t wire_bytes, TimePoint now) {
  if (join_.state() != State::joined || c.client_id != join_.reply().client_id ||
      protocol::check_contact_pairs(c)) {
    ++contacts_rejected_;
    return false;
  }
  contacts_bytes_window_.emplace_back(now, wire_bytes);
  expire_windows(now);
  if (contacts_ && c.tick < contacts_->tick) return false;  // best-effort: an older one arrived late
  contacts_ = c;
  ++contacts_received_;
  return true;
}

std::optional<protocol::Command> Gateway::make_command(TimePoint now, const std::optional<PageInput>& input,
                                                       std::optional<TimePoint> input_received) {
  if (join_.state() != State::joined) return std::nullopt;
  const auto own = world_.own_pose();
  if (!own) return std::nullopt;
  const bool fresh = input && input_received && now - *input_received <= options_.input_timeout;
  PageInput in;
  if (fresh) {
    in = *input;
  } else {
    in.facing_rad = static_cast<float>(own->yaw);  // stand still, keep facing where it faces
  }
  protocol::Command c;
  c.client_id = join_.reply().client_id;
  c.entity = join_.reply().entity;
  c.sequence = next_sequence_++;
  c.last_seen_tick = world_.newest_tick().value_or(0);
  c.move_x = in.move_x;
  c.move_y = in.move_y;
  c.facing_rad = in.facing_rad;
  c.actions = in.actions;
  contacts_requested_ = (c.actions & protocol::kActionContacts) != 0u;
  panned_ = in.panned();
  c.camera_x = panned_ ? *in.camera_x : static_cast<float>(own->x);
  c.camera_y = panned_ ? *in.camera_y : static_cast<float>(own->y);
  c.camera_z = static_cast<float>(own->z);
  camera_x_ = c.camera_x;
  camera_y_ = c.camera_y;
  ++commands_sent_;
  pending_.push_back(Pending{c.sequence, now});
  while (pending_.size() > options_.max_pending_commands) pending_.pop_front();
  return c;
}

void Gateway::expire_windows(TimePoint now) const {
  while (!latency_window_.empty() && now - latency_window_.front().first > kWindow) latency_window_.pop_front();
  while (!bytes_window_.empty() && now - bytes_window_.front().first > kWindow) bytes_window_.pop_front();
  while (!contacts_bytes_window_.empty() && now - contacts_bytes_window_.front().first > kWindow)
    contacts_bytes_window_.pop_front();
}

std::optional<double> Gateway::latency_ms(TimePoint now) const {
  expire_windows(now);
  if (latency_window_.empty()) return std::nullopt;
  std::vector<double> v;
  v.reserve(latency_window_.size());
  for (const auto& [t, ms] : latency_window_) v.push_back(ms);
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

double Gateway::kbit_per_s(TimePoint now) const {
  expire_windows(now);
  if (!first_snapshot_) return 0.0;
  std::size_t bytes = 0;
  for (const auto& [t, b] : bytes_window_) bytes += b;
  // Over the last second, or since the first snapshot when that is shorter (but at least 0.2 s).
  const double span = std::clamp(std::chrono::duration<double>(now - *first_snapshot_).count(), 0.2, 1.0);
  return static_cast<double>(bytes) * 8.0 / 1000.0 / span;
}

double Gateway::contacts_kbit_per_s(TimePoint now) const {
  expire_windows(now);
  std::size_t bytes = 0;
  for (const auto& [t, b] : contacts_bytes_window_) bytes += b;
  return static_cast<double>(bytes) * 8.0 / 1000.0;
}

std::string contacts_json(const protocol::ContactPairs& c) {
  fmt::memory_buffer b;
  auto out = std::back_inserter(b);
  fmt::format_to(out, R"({{"tick":{},"near":{},"camera":[{:.3f},{:.3f}],"radius":{:.3f},"pairs":[)", c.tick, c.pairs_near,
                 c.camera_x, c.camera_y, c.radius_m);
  for (std::size_t i = 0; i < c.a.size(); ++i)
    fmt::format_to(out, "{}{},{},{:.5f},{:.1f},{:.1f}", i ? "," : "", c.a[i], c.b[i], protocol::dequantize_share(c.share_a[i]),
                   protocol::dequantize_contact_m(c.depth[i]) * 1000.0, protocol::dequantize_contact_m(c.push[i]) * 1000.0);
  fmt::format_to(out, "]}}");
  return fmt::to_string(b);
}

std::string Gateway::frame_json(TimePoint now, const FrameExtras& extras) const {
  std::vector<client_sim::ObjectState> objects;
  objects.reserve(world_.object_count());
  world_.for_each([&](const client_sim::ObjectState& o) { objects.push_back(o); });
  std::sort(objects.begin(), objects.end(), [](const auto& a, const auto& b) { return a.id < b.id; });

  fmt::memory_buffer b;
  auto out = std::back_inserter(b);
  fmt::format_to(out, R"({{"type":"frame","tick":{},"render_tick":{:.2f},"client_id":{},"entity":{},"faction":{},)",
                 world_.newest_tick().value_or(0), world_.render_tick(), join_.reply().client_id, join_.reply().entity,
                 static_cast<unsigned>(join_.reply().faction));
  if (const auto self = world_.own_pose()) {
    fmt::format_to(out, R"("self":{{"x":{:.3f},"y":{:.3f},"z":{:.3f},"yaw":{:.3f}}},)", self->x, self->y, self->z,
                   self->yaw);
  } else {
    fmt::format_to(out, R"("self":null,)");
  }
  fmt::format_to(out, R"("objects":[)");
  for (std::size_t i = 0; i < objects.size(); ++i) {
    const auto& o = objects[i];
    fmt::format_to(out, "{}{},{:.3f},{:.3f},{:.2f}", i ? "," : "", o.id, o.x, o.y, o.yaw);
  }
  const auto latency = latency_ms(now);
  fmt::format_to(out, R"(],"in_view":{},"tracked":{},"latency_ms":{},"kbps":{:.1f},"sent_seq":{},"applied_seq":{},)",
                 objects_in_view_, objects.size(), latency ? fmt::format("{:.1f}", *latency) : std::string("null"),
                 kbit_per_s(now), next_sequence_ - 1, last_applied_sequence_);
  fmt::format_to(out, R"("camera":{{"x":{:.3f},"y":{:.3f},"panned":{}}},"pages":{},"ended":{},"input_errors":{{)",
                 camera_x_, camera_y_, panned_, extras.pages, match_ended());
  std::uint64_t total = 0;
  for (std::size_t i = 0; i < kInputErrorCount; ++i) {
    fmt::format_to(out, R"({}"{}":{})", i ? "," : "", view::to_string(static_cast<InputError>(i)), extras.input_errors[i]);
    total += extras.input_errors[i];
  }
  const std::uint64_t newest = world_.newest_tick().value_or(0);
  const bool show_contacts = contacts_requested_ && contacts_ && contacts_->tick + kContactsMaxAgeTicks >= newest;
  fmt::format_to(out, R"(}},"input_errors_total":{},"contacts_kbps":{:.1f},"contacts":{}}})", total,
                 contacts_kbit_per_s(now), show_contacts ? contacts_json(*contacts_) : std::string("null"));
  return fmt::to_string(b);
}

}  // namespace throng::view
