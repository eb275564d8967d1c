// View error regressions: how far a client's copy of the objects in its view (as it decodes them
// from the snapshots: protocol::decode_poses, removals applied) can be from the truth with the
// default budget, a moving camera and a moving crowd.
//
// The bound asserted (2 m): the priority is the current error weighted by w in [1, 4] (near the
// camera counts up to 4x), largest first. With N objects in view and B poses per snapshot, a
// round robin refreshes each object every N / B ticks; an object far out (w = 1) can lose to near
// ones (w = 4) until its error is 4x theirs, so its error stays below about
// 4 * v * dt * (N / B + 1) = 4 * 1.5 m/s / 30 * (1000 / 100 + 1) = 2.2 m (v: the objects' top
// speed; B about 100 of the 106 poses after the entering objects and removals a camera moving at
// 4 m/s costs). What the scenes below reach is about 0.5-0.8 m. Before the priority was made the
// current error (it was an error sum, which did not grow while an object sat between radius and
// radius * exit_hysteresis), a crowd moving with the camera reached 3 m in these 300 ticks and
// 17 m in the server.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <random>
#include <vector>

#include "throng/core/object_id.h"
#include "throng/match/snapshot_builder.h"
#include "throng/protocol/codec.h"

namespace throng::match {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDt = 1.0 / 30.0;

struct Client {
  std::map<std::uint32_t, protocol::Pose> objects;
  std::vector<protocol::Pose> last;

  void apply(const protocol::Snapshot& s) {
    last.clear();
    protocol::decode_poses(s, last);
    for (const std::uint32_t r : s.removed) objects.erase(r);
    for (const auto& p : last) objects[p.id] = p;
  }
  bool sent(std::uint32_t id) const {
    return std::any_of(last.begin(), last.end(), [&](const protocol::Pose& p) { return p.id == id; });
  }
};

struct Bodies {
  std::vector<std::uint32_t> id;
  std::vector<double> x, y, z;
  std::vector<float> yaw;
  BodyView view() const { return BodyView{id, x, y, z, yaw}; }
  void add(std::uint32_t index, double px, double py) {
    id.push_back(ObjectId::make(index, 0).value);
    x.push_back(px);
    y.push_back(py);
    z.push_back(0.9);
    yaw.push_back(0.0f);
  }
};

// In view as the builder defines it: camera and body rounded to a millimetre, within the radius.
bool in_view(double bx, double by, double cx, double cy, double radius) {
  const double dx = std::nearbyint(bx * 1000.0) - std::nearbyint(cx * 1000.0);
  const double dy = std::nearbyint(by * 1000.0) - std::nearbyint(cy * 1000.0);
  return dx * dx + dy * dy <= radius * radius * 1.0e6;
}

// Largest |truth - client copy| over the objects in view the client holds.
double max_view_error(const Client& client, const Bodies& b, double cx, double cy, double radius) {
  double worst = 0.0;
  for (std::size_t i = 0; i < b.id.size(); ++i) {
    if (!in_view(b.x[i], b.y[i], cx, cy, radius)) continue;
    const auto it = client.objects.find(b.id[i]);
    if (it == client.objects.end()) continue;
    const protocol::Pose& p = it->second;
    worst = std::max(worst, std::sqrt(std::pow(p.x - b.x[i], 2) + std::pow(p.y - b.y[i], 2) + std::pow(p.z - b.z[i], 2)));
  }
  return worst;
}

struct SceneResult {
  double max_error = 0.0;     // client model
  double max_reported = 0.0;  // BuildStats::view_error_max_m
  double mean_in_view = 0.0;
  double mean_sent = 0.0;
};

// A crowd of `density` bodies per m^2 on a strip long enough for the camera, each body walking at
// `drift` m/s along +x plus its own random walk of up to `wander` m/s; the camera moves at
// `camera_speed` m/s, along +x (with the crowd) when `with_crowd`, else turning every 3 s.
SceneResult run_scene(std::uint64_t seed, double drift, double wander, double camera_speed, bool with_crowd,
                      int ticks) {
  const InterestConfig cfg;  // default: 30 m, budget 1066 bytes (about 106 poses)
  const double density = 1000.0 / (kPi * cfg.radius_m * cfg.radius_m) * 1.05;
  const double length = 120.0 + ticks * kDt * std::max(camera_speed, drift) * 1.3 + 2.0 * cfg.radius_m * 1.1;
  const double width = with_crowd ? 110.0 : length;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> px(0.0, length), py(0.0, width), ang(-kPi, kPi), unit(0.0, 1.0);
  Bodies b;
  std::vector<double> heading, speed;
  const auto n = static_cast<std::uint32_t>(density * length * width);
  for (std::uint32_t i = 0; i < n; ++i) {
    b.add(i, px(rng), py(rng));
    heading.push_back(ang(rng));
    speed.push_back(wander * unit(rng));
  }
  SnapshotBuilder sb(cfg);
  sb.add_client(1);
  Client client;
  protocol::Snapshot snap;
  double cx = with_crowd ? cfg.radius_m * 1.5 : length / 2, cy = width / 2, ch = 0.0;
  SceneResult r;
  for (int t = 1; t <= ticks; ++t) {
    for (std::size_t i = 0; i < b.id.size(); ++i) {
      if ((t + static_cast<int>(i)) % 45 == 0) heading[i] = ang(rng);
      b.x[i] += (drift + speed[i] * std::cos(heading[i])) * kDt;
      b.y[i] += speed[i] * std::sin(heading[i]) * kDt;
      b.yaw[i] = static_cast<float>(heading[i]);
    }
    if (!with_crowd && t % 90 == 0) ch = ang(rng);
    cx += camera_speed * std::cos(ch) * kDt;
    cy += camera_speed * std::sin(ch) * kDt;
    sb.index(b.view(), static_cast<std::uint64_t>(t));
    const BuildStats& st = sb.build(1, cx, cy, snap);
    EXPECT_LE(protocol::snapshot_wire_bytes(snap), cfg.budget_bytes);
    client.apply(snap);
    if (t <= 30) continue;  // the first second: the view is being filled
    const double e = max_view_error(client, b, cx, cy, cfg.radius_m);
    EXPECT_NEAR(st.view_error_max_m, e, 0.0015) << "tick " << t;  // the builder measures on mm-rounded truth
    r.max_error = std::max(r.max_error, e);
    r.max_reported = std::max(r.max_reported, st.view_error_max_m);
    r.mean_in_view += st.in_view;
    r.mean_sent += st.sent;
  }
  r.mean_in_view /= (ticks - 30);
  r.mean_sent /= (ticks - 30);
  ::testing::Test::RecordProperty("max_view_error_mm", static_cast<int>(r.max_error * 1000.0));
  return r;
}

TEST(SnapshotViewError, WanderingCrowdAndMovingCameraStayBelowTwoMetres) {
  // 1,000 in view walking at up to 1.5 m/s, the camera at 4 m/s turning every 3 s.
  const SceneResult r = run_scene(1, 0.0, 1.5, 4.0, false, 300);
  EXPECT_GT(r.mean_in_view, 900.0);
  EXPECT_LT(r.mean_in_view, 1150.0);
  EXPECT_GT(r.mean_sent, 95.0);
  EXPECT_LT(r.max_error, 2.0);
  EXPECT_LT(r.max_reported, 2.0);
}

TEST(SnapshotViewError, CrowdMovingWithTheCameraStaysBelowTwoMetres) {
  // A column marching at 1.2 m/s (+- 0.3) with the camera at 1.3 m/s: bodies linger between the
  // radius and radius * exit_hysteresis, known to the client but not in view, and come back with
  // stale copies. They must be refreshed as soon as they are back in view.
  const SceneResult r = run_scene(2, 1.2, 0.3, 1.3, true, 300);
  EXPECT_GT(r.mean_in_view, 900.0);
  EXPECT_LT(r.max_error, 2.0);
  EXPECT_LT(r.max_reported, 2.0);
}

TEST(SnapshotViewError, AStaleObjectBackInViewIsSentBeforeSmallerErrors) {
  // 400 bodies near the camera walking at 2 m/s with a budget of about 10 poses: their copies are
  // metres stale. One more object is sent, leaves the radius (not the hysteresis radius), walks
  // 20 m along the edge unseen, and comes back in: its 20 m error beats every near one's at once.
  InterestConfig cfg;
  cfg.budget_bytes = 96 + 10 * 9 + 16;
  SnapshotBuilder sb(cfg);
  sb.add_client(1);
  std::mt19937_64 rng(8);
  std::uniform_real_distribution<double> pos(-12.0, 12.0), ang(-kPi, kPi);
  Bodies b;
  std::vector<double> heading;
  for (std::uint32_t i = 0; i < 400; ++i) {
    b.add(i, pos(rng), pos(rng));
    heading.push_back(ang(rng));
  }
  const std::uint32_t stale = 400;
  b.add(stale, 29.0, 0.0);
  const std::size_t s = b.id.size() - 1;
  Client client;
  protocol::Snapshot snap;
  std::uint64_t t = 0;
  auto tick = [&] {
    ++t;
    for (std::size_t i = 0; i < s; ++i) {
      if (t % 20 == 0) heading[i] = ang(rng);
      b.x[i] += 2.0 * kDt * std::cos(heading[i]);
      b.y[i] += 2.0 * kDt * std::sin(heading[i]);
    }
    sb.index(b.view(), t);
    const BuildStats& st = sb.build(1, 0.0, 0.0, snap);
    client.apply(snap);
    return st;
  };
  while (!client.objects.count(b.id[s])) tick();
  for (int i = 0; i < 90; ++i) tick();  // the near copies go stale
  // Out to 31.5 m, then 20 m around the edge (staying between 30 and 33 m), then back to 29.5 m.
  const double a0 = 0.0, a1 = 20.0 / 31.5;
  for (int i = 0; i <= 60; ++i) {
    const double a = a0 + (a1 - a0) * i / 60.0;
    b.x[s] = 31.5 * std::cos(a);
    b.y[s] = 31.5 * std::sin(a);
    tick();
    EXPECT_FALSE(client.sent(b.id[s])) << "out of view, tick " << t;
  }
  const double reported_before = tick().view_error_max_m;  // near copies are stale by metres
  EXPECT_GT(reported_before, 1.0);
  b.x[s] = 29.5 * std::cos(a1);
  b.y[s] = 29.5 * std::sin(a1);
  const BuildStats st = tick();
  EXPECT_TRUE(client.sent(b.id[s])) << "a 20 m error back in view waited";
  EXPECT_LT(st.view_error_max_m, 19.0);
}

}  // namespace
}  // namespace throng::match
