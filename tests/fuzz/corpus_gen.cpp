// Writes the fuzz targets' seed corpora (tests/fuzz/corpus/<target>/) from real data: a small match
// played tick by tick (the snapshots and contact pairs it sends its client, the commands it
// receives, its checkpoints), the match log it records, the built-in scenes and the parameter /
// policy files, and the page / HTTP messages the viewer and the admin endpoint are sent. Run once
// by hand when a format changes (tests/fuzz/README.md); CI never runs it.
//   fuzz_corpus_gen <corpus dir>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "fuzz_bytes.h"
#include "match_test_util.h"
#include "throng/matchlog/format.h"
#include "throng/matchlog/log_header.h"
#include "throng/matchlog/tick_record.h"
#include "throng/matchlog/writer.h"
#include "throng/scene/build_scene.h"
#include "throng/scene/builtin_scenes.h"
#include "throng/scene/scale.h"
#include "throng/scene/scene_json.h"

using namespace throng;
namespace fs = std::filesystem;

namespace {

fs::path g_root;

void write(const std::string& target, const std::string& name, const void* data, std::size_t n) {
  const fs::path dir = g_root / target;
  fs::create_directories(dir);
  std::ofstream out(dir / name, std::ios::binary | std::ios::trunc);
  out.write(static_cast<const char*>(data), static_cast<std::streamsize>(n));
}
void write(const std::string& target, const std::string& name, const std::vector<std::uint8_t>& b) {
  write(target, name, b.data(), b.size());
}
void write(const std::string& target, const std::string& name, const std::string& s) {
  write(target, name, s.data(), s.size());
}
std::string read_text(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

match::MatchConfig fuzz_config() {  // the config of the command / match_checkpoint targets
  match::MatchConfig c = match::test::small_config();
  c.worker_threads = 1;
  return c;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: fuzz_corpus_gen <corpus dir>\n");
    return 2;
  }
  g_root = argv[1];
  const fs::path src = THRONG_SOURCE_DIR;

  // --- a small match with one client that moves, sprints and asks for contact pairs --------------
  const scene::SceneDef scene = match::test::two_armies(4);
  const match::MatchConfig config = fuzz_config();
  match::Match m(scene, config, "corpus");
  match::Outbox out;
  const std::string log_path = (fs::temp_directory_path() / "throng_fuzz_corpus.tlog").string();
  matchlog::WriterOptions wo;
  wo.block_ticks = 8;
  wo.index_interval_ticks = 16;
  wo.keyframe_interval_ticks = 16;
  matchlog::MatchLogWriter log(log_path, wo);
  matchlog::LogHeader header;
  header.build_id = "corpus";
  header.match_id = "corpus";
  header.scene = scene;
  header.config = config;
  log.begin(header);
  write("log_header", "header.json", matchlog::header_to_json_text(header));

  std::uint32_t client = 0, entity = 0, seq = 0;
  std::vector<protocol::Snapshot> snaps;
  std::vector<std::uint8_t> checkpoint;
  std::vector<std::uint8_t> ticks_v3{2};  // tick_codec: version byte (2 -> format 3), entries
  int commands_written = 0;
  for (std::uint64_t t = 1; t <= 40; ++t) {
    if (t == 1) m.inputs().push(match::test::join_request(1, "corpus"));
    if (t == 3) m.inputs().push(match::test::join_request(2, "second"));
    if (t == 15) m.inputs().push(match::test::leave_request(2, 2));  // checkpoints then skip a departed id
    if (client != 0) {
      protocol::Command c = match::test::command(client, entity, ++seq, 0.6f, t % 2 ? 0.3f : -0.3f);
      c.last_seen_tick = t - 1;
      c.facing_rad = 0.1f * static_cast<float>(t % 30) - 1.5f;
      c.actions = protocol::kActionContacts | (t % 3 == 0 ? protocol::kActionSprint : 0u);
      c.camera_x = -15.0f;
      c.camera_z = 10.0f;
      if (t % 10 == 0 && commands_written < 4) {
        fuzz::Out o;
        o.put<std::uint8_t>(1);
        fuzz::write_command(o, c);
        protocol::Command bad = c;  // rejected ones too: out of range, then unknown bits
        bad.move_x = 2.0f;
        o.put<std::uint8_t>(1);
        fuzz::write_command(o, bad);
        bad = c;
        bad.actions = 0x80;
        o.put<std::uint8_t>(0);
        fuzz::write_command(o, bad);
        write("command", "commands_" + std::to_string(t), o.bytes);
        ++commands_written;
      }
      m.inputs().push(std::move(c));
    }
    const match::TickReport& r = m.tick(out);
    for (const auto& reply : out.join_replies)
      if (reply.client_nonce == 1 && reply.result == protocol::JoinResult::accepted) {
        client = reply.client_id;
        entity = reply.entity;
      }
    for (std::size_t i = 0; i < out.snapshot_count; ++i)
      if (out.snapshots[i].client_id == client) snaps.push_back(out.snapshots[i]);
    log.append_tick(r.tick, m.last_inputs(), r.state_hash, 0);
    if (t <= 12) matchlog::encode_tick(r.tick, m.last_inputs(), r.state_hash, 0, ticks_v3);
    if (r.tick % wo.keyframe_interval_ticks == 0) {
      m.save_checkpoint(checkpoint);
      log.append_keyframe(r.tick, checkpoint);
    }
    if (t == 20 || t == 40) {  // match_checkpoint: options byte then the checkpoint
      m.save_checkpoint(checkpoint);
      std::vector<std::uint8_t> b{static_cast<std::uint8_t>(t == 40 ? 1 : 0)};
      b.insert(b.end(), checkpoint.begin(), checkpoint.end());
      write("match_checkpoint", "checkpoint_tick" + std::to_string(t), b);
    }
  }
  log.close();
  write("tick_codec", "ticks_v3", ticks_v3);
  write("matchlog", "match.tlog", read_text(log_path));
  fs::remove(log_path);

  // snapshot: three consecutive snapshots per file (the first full, then deltas), twice.
  for (std::size_t start : {std::size_t{0}, std::size_t{20}}) {
    fuzz::Out o;
    for (std::size_t i = start; i < start + 3 && i < snaps.size(); ++i) fuzz::write_snapshot(o, snaps[i]);
    write("snapshot", "snapshots_" + std::to_string(start), o.bytes);
  }

  // contacts: a crowded match (two armies pressed together) whose client asks for contact pairs.
  {
    match::Match dense(match::test::two_armies(12, 1.0, 1.2), config, "contacts");
    dense.inputs().push(match::test::join_request(1, "contacts"));
    std::uint32_t id = 0, ent = 0, sq = 0;
    int written = 0;
    for (std::uint64_t t = 1; t <= 30 && written < 3; ++t) {
      if (id != 0) {
        protocol::Command c = match::test::command(id, ent, ++sq, 0.5f, 0.0f);
        c.actions = protocol::kActionContacts;
        c.camera_x = 0.0f;
        dense.inputs().push(std::move(c));
      }
      dense.tick(out);
      for (const auto& reply : out.join_replies)
        if (reply.result == protocol::JoinResult::accepted) {
          id = reply.client_id;
          ent = reply.entity;
        }
      for (std::size_t i = 0; i < out.contacts_count; ++i)
        if (!out.contacts[i].a.empty() && t % 5 == 0) {
          fuzz::Out o;
          fuzz::write_contacts(o, out.contacts[i]);
          write("contacts", "contacts_" + std::to_string(t), o.bytes);
          ++written;
        }
    }
  }

  // world_checkpoint: the world of the same scene, stepped a little.
  {
    scene::BuiltScene built = scene::build_scene(scene);
    std::vector<std::uint8_t> state;
    for (int i = 0; i < 10; ++i) scene::step_scene(built);
    built.world.save_state(state);
    write("world_checkpoint", "world_step10", state);
  }

  // scene_json: the scene files in server/engine/data/scenes and two built-ins, dumped small.
  for (const auto& e : fs::directory_iterator(src / "server/engine/data/scenes"))
    if (e.path().extension() == ".json") write("scene_json", e.path().filename().string(), read_text(e.path()));
  write("scene_json", "builtin_mixed.json", scene::scene_to_text(scene::scale_scene(scene::builtin_scene("mixed"), 50)));
  write("scene_json", "two_armies.json", scene::scene_to_text(scene));

  // params / policy documents.
  write("params_json", "default_params.json", read_text(src / "server/engine/data/default_params.json"));
  write("policy_json", "default_policy.json", read_text(src / "server/engine/data/default_policy.json"));
  write("policy_json", "patent_examples_policy.json", read_text(src / "server/engine/data/patent_examples_policy.json"));

  // view_ws_input: the messages the page sends (client_sim/view/web/app.js), live and log mode.
  const char* page[] = {
      R"({"type":"input","move_x":0.5,"move_y":-0.5,"facing":1.2,"actions":1,"camera_x":10.5,"camera_y":-3})",
      R"({"type":"input","move_x":0,"move_y":0,"facing":0,"actions":0})",
      R"({"type":"speed","speed":2})",
      R"({"type":"seek","tick":1234})",
      R"({"type":"focus","id":42})",
      R"({"type":"contacts","on":true,"camera_x":1.5,"camera_y":2.5})",
      R"({"type":"toggle"})",
  };
  int k = 0;
  for (const char* p : page) write("view_ws_input", "msg_" + std::to_string(k++), std::string(p));

  // admin_http / view_http: what curl, Prometheus and a browser send.
  write("admin_http", "get_metrics",
        std::string("GET /metrics HTTP/1.1\r\nHost: 127.0.0.1:9100\r\nUser-Agent: Prometheus/2.42\r\nAccept: text/plain\r\n\r\n"));
  write("admin_http", "pipelined",
        std::string("GET /healthz HTTP/1.1\r\nHost: a\r\n\r\nHEAD /readyz?x=1 HTTP/1.1\r\nHost: a\r\n\r\n"
                    "POST /metrics HTTP/1.1\r\nHost: a\r\nContent-Length: 3\r\n\r\nabc"));
  write("view_http", "get_index", std::string(1, '\0') + "GET / HTTP/1.1\r\nHost: localhost:8088\r\nAccept: text/html\r\n\r\n");
  write("view_http", "get_asset_root",
        std::string("\x01GET /app.js?v=1 HTTP/1.1\r\nHost: localhost:8088\r\n\r\nHEAD /style.css HTTP/1.0\r\n\r\n"));
  write("view_http", "ws_upgrade",
        std::string(1, '\0') + std::string("GET /ws HTTP/1.1\r\nHost: localhost:8088\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
                    "Origin: http://localhost:8088\r\nSec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\n"
                    "Sec-WebSocket-Version: 13\r\n\r\n"));
  std::printf("corpora written to %s\n", g_root.c_str());
  return 0;
}
