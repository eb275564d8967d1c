// Log mode frames from a re-simulated Match (see log_frame.h).
#include "throng/view/log_frame.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <vector>

#include <fmt/format.h>

#include "throng/params/object_params.h"
#include "throng/view/gateway.h"
#include "throng/world/world.h"

namespace throng::view {

namespace {

struct Body {
  std::uint32_t id;
  double x, y, z;
};

void focus_json(fmt::memory_buffer& b, const World& w, std::uint32_t focus) {
  auto out = std::back_inserter(b);
  ObjectId id{focus};
  if (focus == 0 || !w.is_body(id)) {
    fmt::format_to(out, "null");
    return;
  }
  const params::ObjectParams& p = w.params(id);
  const Vec3 pos = w.position(id);
  const Vec3 v = w.velocity(id);
  fmt::format_to(out,
                 R"({{"id":{},"x":{:.3f},"y":{:.3f},"z":{:.3f},"speed_mps":{:.2f},"weight_kg":{:.1f},"importance":{:.2f},)"
                 R"("equipment_level":{:.2f},"softness":{:.2f},"faction":{},"character_type":{},"group_id":{},"hp":{:.1f},)"
                 R"("level":{:.1f},"size_m":{:.2f}}})",
                 focus, pos.x, pos.y, pos.z, std::hypot(v.x, v.y), p.weight_kg, p.importance, p.equipment_level, p.softness,
                 static_cast<unsigned>(p.faction), static_cast<unsigned>(p.character_type), p.group_id, p.hp, p.level,
                 p.size_m);
}

}  // namespace

const protocol::ContactPairs& LogFrameBuilder::contacts(const match::Match& match, double camera_x, double camera_y) {
  const match::ContactsConfig config{};
  selector_.prepare(match.world());
  selector_.select(camera_x, camera_y, config.radius_m, config.max_pairs, contacts_);
  contacts_.tick = match.tick_index();
  return contacts_;
}

std::string LogFrameBuilder::frame_json(const match::Match& match, const std::string& timeline_fields, std::uint32_t focus,
                                        std::size_t pages, std::uint64_t input_errors_total,
                                        const std::optional<ContactsView>& contacts_view) {
  const World& w = match.world();
  const auto xs = w.pos_x();
  const auto ys = w.pos_y();
  const auto zs = w.pos_z();
  std::vector<Body> bodies(w.body_count());
  for (std::size_t i = 0; i < bodies.size(); ++i) bodies[i] = Body{w.id_at(i).value, xs[i], ys[i], zs[i]};
  // Id order: the world re-sorts its dense arrays spatially every few ticks; the page should not
  // see the order change.
  std::sort(bodies.begin(), bodies.end(), [](const Body& a, const Body& b) { return a.id < b.id; });

  fmt::memory_buffer b;
  auto out = std::back_inserter(b);
  fmt::format_to(out,
                 R"({{"type":"frame","mode":"replay","tick":{},"render_tick":{},"client_id":0,"entity":0,"faction":0,"self":null,"objects":[)",
                 match.tick_index(), match.tick_index());
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    const Body& o = bodies[i];
    const float yaw = match.facing_rad(ObjectId{o.id}).value_or(0.0f);
    fmt::format_to(out, "{}{},{:.3f},{:.3f},{:.2f}", i ? "," : "", o.id, o.x, o.y, yaw);
  }
  fmt::format_to(out, R"(],"in_view":{},"tracked":{},"latency_ms":null,"kbps":0,"clients":{},"camera":null,"pages":{},)",
                 bodies.size(), bodies.size(), match.client_count(), pages);
  fmt::format_to(out, R"("ended":{},"input_errors_total":{},"focus":)",
                 match.match_info().state == protocol::MatchState::ended, input_errors_total);
  focus_json(b, w, focus);
  fmt::format_to(out, R"(,"contacts":{})",
                 contacts_view ? contacts_json(contacts(match, contacts_view->camera_x, contacts_view->camera_y))
                               : std::string("null"));
  fmt::format_to(out, R"(,"replay":{{{}}}}})", timeline_fields);
  return fmt::to_string(b);
}

std::string timeline_json(const std::string& timeline_fields) {
  return fmt::format(R"({{"type":"timeline",{}}})", timeline_fields);
}

}  // namespace throng::view
