// throng-replay export: re-simulate up to --to (from the logged keyframe before --from, else from
// tick 1) and write the poses and push events of ticks --from..--to as CSV or JSON. Every
// re-simulated tick is checked against the logged hash, so an export is never silently of a
// different match.
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <vector>
#include <fstream>
#include <iostream>
#include <memory>

#include <fmt/format.h>

#include "commands.h"
#include "open_log.h"
#include "throng/match/match.h"
#include "throng/matchlog/reader.h"
#include "throng/matchlog/replay.h"
#include "throng/world/world.h"

namespace throng::replay {
namespace {

// Facing (yaw, radians) of every body in the world's dense order, as snapshots carry it
// (Match::facing_rad: a client's from its commands, an NPC's from the AI).
class Facing {
 public:
  const std::vector<float>& read(const match::Match& m) {
    const World& w = m.world();
    yaw_.resize(w.body_count());
    for (std::size_t d = 0; d < yaw_.size(); ++d) yaw_[d] = m.facing_rad(w.id_at(d)).value_or(0.0f);
    return yaw_;
  }

 private:
  std::vector<float> yaw_;
};

class Sink {
 public:
  virtual ~Sink() = default;
  virtual void begin() = 0;
  // yaw: facing per body in the world's dense order (Facing::read).
  virtual void tick(std::uint64_t tick, std::uint64_t hash, const World& w, const std::vector<float>& yaw) = 0;
  virtual void end() = 0;
};

class CsvSink : public Sink {
 public:
  CsvSink(std::ostream& os, bool poses, bool pushes) : os_(os), poses_(poses), pushes_(pushes) {}
  void begin() override { os_ << "record,tick,id,x,y,z,vx,vy,vz,yaw,other_id,depth_m,share_a,push_m\n"; }
  void tick(std::uint64_t tick, std::uint64_t, const World& w, const std::vector<float>& yaw) override {
    std::string line;
    if (poses_) {
      const auto x = w.pos_x(), y = w.pos_y(), z = w.pos_z();
      for (std::size_t d = 0; d < w.body_count(); ++d) {
        const ObjectId id = w.id_at(d);
        const Vec3 v = w.velocity(id);
        line.clear();
        fmt::format_to(std::back_inserter(line), "pose,{},{},{},{},{},{},{},{},{},,,,\n", tick, id.value, x[d], y[d], z[d], v.x,
                       v.y, v.z, yaw[d]);
        os_ << line;
      }
    }
    if (pushes_) {
      for (const PushEvent& e : w.push_events()) {
        line.clear();
        fmt::format_to(std::back_inserter(line), "push,{},{},,,,,,,,{},{},{},{}\n", tick, e.a.value, e.b.value, e.depth_m, e.share_a,
                       e.push_m);
        os_ << line;
      }
    }
  }
  void end() override {}

 private:
  std::ostream& os_;
  bool poses_, pushes_;
};

class JsonSink : public Sink {
 public:
  JsonSink(std::ostream& os, bool poses, bool pushes, const matchlog::LogHeader& h, std::uint64_t from, std::uint64_t to)
      : os_(os), poses_(poses), pushes_(pushes), h_(h), from_(from), to_(to) {}
  void begin() override {
    os_ << fmt::format(
        "{{\"match_id\":\"{}\",\"scene\":\"{}\",\"tick_hz\":{},\"from\":{},\"to\":{},\n"
        "\"pose_fields\":[\"id\",\"x\",\"y\",\"z\",\"vx\",\"vy\",\"vz\",\"yaw\"],\n"
        "\"push_fields\":[\"a\",\"b\",\"depth_m\",\"share_a\",\"push_m\"],\n\"ticks\":[\n",
        escape(h_.match_id), escape(h_.scene.name), h_.config.tick_hz, from_, to_);
  }
  void tick(std::uint64_t tick, std::uint64_t hash, const World& w, const std::vector<float>& yaw) override {
    std::string s;
    auto out = std::back_inserter(s);
    fmt::format_to(out, "{}{{\"tick\":{},\"state_hash\":\"{:016x}\"", first_ ? "" : ",\n", tick, hash);
    first_ = false;
    if (poses_) {
      s += ",\"poses\":[";
      const auto x = w.pos_x(), y = w.pos_y(), z = w.pos_z();
      for (std::size_t d = 0; d < w.body_count(); ++d) {
        const ObjectId id = w.id_at(d);
        const Vec3 v = w.velocity(id);
        fmt::format_to(out, "{}[{},{},{},{},{},{},{},{}]", d == 0 ? "" : ",", id.value, x[d], y[d], z[d], v.x, v.y, v.z, yaw[d]);
      }
      s += "]";
    }
    if (pushes_) {
      s += ",\"pushes\":[";
      bool first = true;
      for (const PushEvent& e : w.push_events()) {
        fmt::format_to(out, "{}[{},{},{},{},{}]", first ? "" : ",", e.a.value, e.b.value, e.depth_m, e.share_a, e.push_m);
        first = false;
      }
      s += "]";
    }
    s += "}";
    os_ << s;
  }
  void end() override { os_ << "\n]}\n"; }

 private:
  static std::string escape(const std::string& in) {
    std::string o;
    for (char c : in) {
      if (c == '"' || c == '\\') o += '\\';
      if (static_cast<unsigned char>(c) < 0x20) o += fmt::format("\\u{:04x}", static_cast<unsigned>(c));
      else o += c;
    }
    return o;
  }
  std::ostream& os_;
  bool poses_, pushes_;
  const matchlog::LogHeader& h_;
  std::uint64_t from_, to_;
  bool first_ = true;
};

}  // namespace

int run_export(const ExportOptions& o) {
  const auto reader = open_log<matchlog::MatchLogReader>("export", o.log);
  if (!reader) return kExitBadInput;
  const matchlog::LogScan& s = reader->scan();
  const std::uint64_t to = o.to == 0 ? o.from : o.to;
  if (o.from < 1 || to < o.from) {
    fmt::print(stderr, "throng-replay export: --from {} --to {}: need 1 <= from <= to\n", o.from, to);
    return kExitBadInput;
  }
  if (const std::uint64_t base = matchlog::start_keyframe_tick(s); base > 0) {
    fmt::print(stderr, "throng-replay export: this log starts after tick {} from a checkpoint (a hot standby's log); "
                       "export re-simulates from tick 1 and does not read such logs yet (verify, seek and play do)\n",
               base);
    return kExitBadInput;
  }
  // Re-simulation needs every tick from 1 to `to`.
  const std::uint64_t contiguous_last = s.gaps.empty() ? s.last_tick : s.gaps.front().first_tick - 1;
  if (to > contiguous_last) {
    fmt::print(stderr, "throng-replay export: --to {} is past the last tick that can be re-simulated ({}{})\n", to,
               contiguous_last, s.problem.empty() ? "" : ": " + s.problem);
    return s.end == matchlog::LogEnd::corrupt || !s.gaps.empty() ? kExitDamaged : kExitBadInput;
  }

  std::ofstream file;
  std::ostream* os = &std::cout;
  if (!o.out.empty()) {
    file.open(o.out, std::ios::binary | std::ios::trunc);
    if (!file) {
      fmt::print(stderr, "throng-replay export: cannot create {}\n", o.out);
      return kExitBadInput;
    }
    os = &file;
  }
  std::unique_ptr<Sink> sink;
  if (o.format == "csv") sink = std::make_unique<CsvSink>(*os, o.poses, o.pushes);
  else sink = std::make_unique<JsonSink>(*os, o.poses, o.pushes, reader->header(), o.from, to);

  Progress progress("export", !o.quiet);
  try {
    matchlog::ResimOptions ro;
    ro.record_push_events = o.pushes;
    ro.exact_interest = o.exact_config;
    // Start from the logged keyframe at or before --from - 1 when there is one (restored without
    // its snapshot baselines unless --exact-config: export reads the world, not snapshots), else
    // from tick 1. A keyframe that does not restore here (e.g. the log's scene records no push
    // events and --pushes forces them on: another world config) falls back to tick 1.
    std::vector<std::uint8_t> checkpoint;
    const matchlog::KeyframeInfo* k = o.from > 1 ? reader->find_keyframe(o.from - 1) : nullptr;
    if (k != nullptr) {
      reader->read_keyframe(*k, checkpoint);
      if (!ro.exact_interest && !matchlog::Resimulator::restores_with_fast_interest(checkpoint)) ro.exact_interest = true;
    }
    matchlog::Resimulator sim(reader->header(), ro);
    if (k != nullptr) {
      try {
        sim.restore(checkpoint);  // leaves the match at tick 0 when it throws
      } catch (const match::CheckpointError& e) {
        if (!o.quiet)
          fmt::print(stderr, "throng-replay export: the keyframe of tick {} does not restore here ({}); re-simulating from tick 1\n",
                     k->tick, e.what());
      }
    }
    Facing facing;
    sink->begin();
    matchlog::TickRecord t;
    if (sim.tick() > 0) {
      if (!o.quiet) fmt::print(stderr, "throng-replay export: re-simulating from the keyframe of tick {}\n", sim.tick());
      reader->seek(sim.tick() + 1);
    } else {
      reader->rewind();
    }
    while (reader->next(t) && t.tick <= to) {
      const std::uint64_t tick = t.tick, expected = t.state_hash;
      const std::uint64_t actual = sim.step(t);
      if (actual != expected) {
        progress.finish();
        fmt::print(stderr,
                   "throng-replay export: the re-simulation diverged at tick {} (log {:016x}, re-simulated {:016x}); "
                   "run verify\n",
                   tick, expected, actual);
        return kExitMismatch;
      }
      if (tick >= o.from) {
        static const std::vector<float> none;
        sink->tick(tick, actual, sim.match().world(), o.poses ? facing.read(sim.match()) : none);
      }
      if (tick % 30 == 0 || tick == to) progress.update(tick, to);
    }
    sink->end();
  } catch (const std::exception& e) {
    progress.finish();
    fmt::print(stderr, "throng-replay export: {}\n", e.what());
    return kExitBadInput;
  }
  progress.finish();
  os->flush();
  if (!*os) {
    fmt::print(stderr, "throng-replay export: writing the output failed\n");
    return kExitBadInput;
  }
  return kExitOk;
}

}  // namespace throng::replay
