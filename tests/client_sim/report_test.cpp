#include <gtest/gtest.h>

#include "throng/client_sim/ramp.h"
#include "throng/client_sim/report.h"

namespace throng::client_sim {
namespace {

BotReport bot(const std::string& name, int first_latency, double kbit) {
  BotReport b;
  b.name = name;
  b.behavior = "wander";
  b.state = "joined";
  for (int i = 0; i < 50; ++i) b.latency_ms.add(first_latency + i);
  b.interarrival_ms.add(33);
  b.commands.sent = 60;
  b.commands.expect_accept = 60;
  b.commands.applied = 50;
  b.snapshots.samples = 300;
  b.snapshots.missed_ticks = 2;
  b.active_s = 10.0;
  b.snapshots.bytes = static_cast<std::uint64_t>(kbit * 1000 / 8 * 10);
  b.join_ms = first_latency * 10.0;
  return b;
}

TEST(Report, AggregatesKnownInputs) {
  RunReport r;
  r.tick_hz = 30;
  r.duration_s = 10;
  r.behavior = "wander";
  r.bots.push_back(bot("a", 1, 100));   // latencies 1..50
  r.bots.push_back(bot("b", 51, 300));  // latencies 51..100
  r.bots[0].snapshots.longest_gap_ticks = 2;
  r.bots[1].snapshots.longest_gap_ticks = 1;
  BotReport failed;
  failed.name = "c";
  failed.state = "timed_out";
  r.bots.push_back(failed);

  const Aggregate a = aggregate(r);
  EXPECT_EQ(a.clients, 3u);
  EXPECT_EQ(a.joined, 2u);
  EXPECT_EQ(a.join_failed, 1u);
  EXPECT_DOUBLE_EQ(a.latency_ms.p50, 50);
  EXPECT_DOUBLE_EQ(a.latency_ms.p90, 90);
  EXPECT_DOUBLE_EQ(a.latency_ms.p99, 99);
  EXPECT_DOUBLE_EQ(a.latency_ms.max, 100);
  EXPECT_EQ(a.gap_ticks, 4u);
  EXPECT_EQ(a.longest_gap_ticks, 2u);  // the longest at any bot, not a sum
  EXPECT_NEAR(a.kbit_per_s_mean, 200, 1e-9);
  EXPECT_NEAR(a.kbit_per_s_max, 300, 1e-9);
  EXPECT_DOUBLE_EQ(a.join_ms.p50, 10);
  EXPECT_DOUBLE_EQ(a.join_ms.p99, 510);
  EXPECT_EQ(a.commands.sent, 120u);
  EXPECT_EQ(a.commands.applied, 100u);
  EXPECT_NEAR(a.snapshots_per_s_per_client, 30.0, 1e-9);

  const auto j = to_json(r);
  EXPECT_EQ(j["clients"], 3);
  EXPECT_EQ(j["tick_hz"], 30);
  EXPECT_DOUBLE_EQ(j["latency_ms"]["p50"].get<double>(), 50);
  EXPECT_DOUBLE_EQ(j["latency_ms"]["p90"].get<double>(), 90);
  EXPECT_DOUBLE_EQ(j["latency_ms"]["p99"].get<double>(), 99);
  EXPECT_DOUBLE_EQ(j["latency_ms"]["max"].get<double>(), 100);
  EXPECT_EQ(j["snapshot_gap_ticks"], 4);
  EXPECT_EQ(j["max_snapshot_gap_ticks"], 2);
  EXPECT_EQ(j["per_client"][0]["snapshots"]["longest_gap_ticks"], 2);
  EXPECT_NEAR(j["kbit_per_s_per_client"]["mean"].get<double>(), 200, 1e-9);
  EXPECT_NEAR(j["kbit_per_s_per_client"]["max"].get<double>(), 300, 1e-9);
  EXPECT_DOUBLE_EQ(j["join_ms"]["p50"].get<double>(), 10);
  EXPECT_DOUBLE_EQ(j["join_ms"]["p99"].get<double>(), 510);
  EXPECT_EQ(j["commands"]["sent"], 120);
  EXPECT_EQ(j["commands"]["applied"], 100);
  EXPECT_TRUE(j["server_stats"].is_null());
  ASSERT_EQ(j["per_client"].size(), 3u);
  EXPECT_EQ(j["per_client"][1]["name"], "b");
  EXPECT_DOUBLE_EQ(j["per_client"][1]["latency_ms"]["p50"].get<double>(), 75);
  EXPECT_TRUE(j["per_client"][2]["join_ms"].is_null());
  EXPECT_FALSE(j.contains("ramp"));

  protocol::ServerStats st;
  st.tick = 300;
  st.overruns = 2;
  st.tick_ms_p99 = 4.5f;
  r.server_stats = st;
  const auto j2 = to_json(r);
  EXPECT_EQ(j2["server_stats"]["tick"], 300);
  EXPECT_EQ(j2["server_stats"]["overruns"], 2);

  const std::string text = to_text(r);
  EXPECT_NE(text.find("3 clients"), std::string::npos) << text;
  EXPECT_NE(text.find("p99 99.0 ms"), std::string::npos) << text;
}

TEST(Ramp, JudgesSteps) {
  RampOptions o;
  o.start = 10;
  o.step = 10;
  o.max_clients = 30;
  RampStep ok;
  ok.clients = 10;
  ok.joined = 10;
  ok.server_stats_seen = true;
  ok.ticks = 300;
  ok.overruns = 2;  // 0.67% < 1%
  judge_step(ok, o);
  EXPECT_TRUE(ok.pass) << ok.verdict;
  EXPECT_EQ(ok.verdict, "ok");

  RampStep overrun = ok;
  overrun.overruns = 3;  // exactly 1%: fails (must stay under)
  judge_step(overrun, o);
  EXPECT_FALSE(overrun.pass);
  EXPECT_NE(overrun.verdict.find("overruns"), std::string::npos);

  RampStep missed = ok;
  missed.missed_snapshots = 1;
  judge_step(missed, o);
  EXPECT_FALSE(missed.pass);

  RampStep nostats = ok;
  nostats.server_stats_seen = false;
  judge_step(nostats, o);
  EXPECT_FALSE(nostats.pass);

  RampStep notjoined = ok;
  notjoined.joined = 9;
  judge_step(notjoined, o);
  EXPECT_FALSE(notjoined.pass);
}

TEST(Ramp, StopsAtFirstFailureOrTheMaximum) {
  RampOptions o;
  o.start = 10;
  o.step = 10;
  o.max_clients = 25;
  RampResult r;
  RampStep s;
  s.joined = s.clients = 10;
  s.server_stats_seen = true;
  s.ticks = 300;
  EXPECT_TRUE(record_step(r, s, o));
  EXPECT_EQ(r.max_sustained, 10u);
  EXPECT_EQ(next_clients(10, o), 20u);
  EXPECT_EQ(next_clients(20, o), 25u);
  s.joined = s.clients = 20;
  s.missed_snapshots = 3;
  EXPECT_FALSE(record_step(r, s, o));
  EXPECT_EQ(r.max_sustained, 10u);
  EXPECT_NE(r.stopped_because.find("20 clients"), std::string::npos);

  RampResult full;
  s.missed_snapshots = 0;
  s.joined = s.clients = 25;
  EXPECT_FALSE(record_step(full, s, o));
  EXPECT_EQ(full.max_sustained, 25u);
  EXPECT_NE(full.stopped_because.find("ramp-max"), std::string::npos);
  const auto j = to_json(full);
  EXPECT_EQ(j["max_sustained_clients"], 25);
  EXPECT_EQ(j["steps"].size(), 1u);
}

}  // namespace
}  // namespace throng::client_sim
