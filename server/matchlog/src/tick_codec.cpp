// Tick entries: the binary layout of FORMAT.md "Tick entry". Encoding reserves the output once and
// appends to it (the tick thread calls this for every tick, so it must be cheap and allocation-free
// once the buffer has grown to the busiest tick).
#include <cstring>
#include <limits>

#include "throng/core/byte_io.h"
#include "throng/matchlog/format.h"
#include "throng/matchlog/tick_record.h"

namespace throng::matchlog {
namespace {

constexpr std::size_t kTickFixedBytes = 8 + 8 + 1 + 4 + 4 + 4;  // tick, hash, flags, three counts
constexpr std::size_t kSenderBytes = 12;                           // ParticipantKey (format version 3)
constexpr std::size_t kJoinFixedBytesV2 = 8 + 4 + 1 + 4 + 4;       // nonce, version, leave, client, name length
constexpr std::size_t kJoinFixedBytes = kJoinFixedBytesV2 + kSenderBytes + 4;  // + sender, identity length
constexpr std::size_t kCommandBytesV2 = 4 + 4 + 4 + 8 + 4 + 4 + 4 + 4 + 4 + 4 + 4;  // 48
constexpr std::size_t kCommandBytes = kCommandBytesV2 + kSenderBytes;                // 60
constexpr std::size_t kParamFixedBytes = 8 + 4 + 4 + 8 + 4;      // request, entity, param length, value, policy length

using TickReader = BasicByteReader<LogError>;

void put_key(ByteWriter& o, const protocol::ParticipantKey& k) {
  std::memcpy(o.grow(k.bytes.size()), k.bytes.data(), k.bytes.size());
}

protocol::ParticipantKey read_key(TickReader& r, const char* what) {
  protocol::ParticipantKey k;
  std::memcpy(k.bytes.data(), r.take(k.bytes.size(), what), k.bytes.size());
  return k;
}

// No limit of its own on strings: the block that holds the entry bounds them.
constexpr std::size_t kAnyLength = std::numeric_limits<std::uint32_t>::max();

}  // namespace

std::size_t encoded_tick_size(const match::TickInputs& in) {
  std::size_t n = kTickFixedBytes + in.commands.size() * kCommandBytes;
  for (const auto& j : in.joins) n += kJoinFixedBytes + j.name.size() + j.identity.size();
  for (const auto& p : in.params) n += kParamFixedBytes + p.param.size() + p.policy_json.size();
  return n;
}

void encode_tick(std::uint64_t tick, const match::TickInputs& in, std::uint64_t state_hash, std::uint8_t flags,
                 std::vector<std::uint8_t>& out) {
  out.reserve(out.size() + encoded_tick_size(in));
  ByteWriter o(out);
  o.put<std::uint64_t>(tick);
  o.put<std::uint64_t>(state_hash);
  o.put<std::uint8_t>(flags);
  o.put(static_cast<std::uint32_t>(in.joins.size()));
  o.put(static_cast<std::uint32_t>(in.commands.size()));
  o.put(static_cast<std::uint32_t>(in.params.size()));
  for (const auto& j : in.joins) {
    o.put<std::uint64_t>(j.client_nonce);
    o.put<std::uint32_t>(j.protocol_version);
    o.put<std::uint8_t>(j.leave ? 1 : 0);
    o.put<std::uint32_t>(j.client_id);
    o.put_string(j.name);
    put_key(o, j.sender);
    o.put_string(j.identity);
  }
  for (const auto& c : in.commands) {
    o.put<std::uint32_t>(c.client_id);
    o.put<std::uint32_t>(c.entity);
    o.put<std::uint32_t>(c.sequence);
    o.put<std::uint64_t>(c.last_seen_tick);
    o.put<float>(c.move_x);
    o.put<float>(c.move_y);
    o.put<float>(c.facing_rad);
    o.put<std::uint32_t>(c.actions);
    o.put<float>(c.camera_x);
    o.put<float>(c.camera_y);
    o.put<float>(c.camera_z);
    put_key(o, c.sender);
  }
  for (const auto& p : in.params) {
    o.put<std::uint64_t>(p.request_id);
    o.put<std::uint32_t>(p.entity);
    o.put_string(p.param);
    o.put<double>(p.value);
    o.put_string(p.policy_json);
  }
}

void decode_tick(std::span<const std::uint8_t> bytes, std::size_t& pos, TickRecord& t, std::uint32_t format_version) {
  const bool senders = format_version >= 3;
  TickReader r(bytes, "tick entry", pos);
  t.tick = r.get<std::uint64_t>("tick");
  t.state_hash = r.get<std::uint64_t>("state hash");
  t.flags = r.get<std::uint8_t>("flags");
  if ((t.flags & ~kKnownTickFlags) != 0)
    throw LogError("tick " + std::to_string(t.tick) + " has unknown flag bits 0x" + std::to_string(t.flags) +
                   " (written by a newer build?)");
  const std::uint32_t nj = r.get_count("joins", kAnyLength, senders ? kJoinFixedBytes : kJoinFixedBytesV2);
  const std::uint32_t nc = r.get_count("commands", kAnyLength, senders ? kCommandBytes : kCommandBytesV2);
  const std::uint32_t np = r.get_count("parameter changes", kAnyLength, kParamFixedBytes);
  t.inputs.joins.resize(nj);
  t.inputs.commands.resize(nc);
  t.inputs.params.resize(np);
  for (auto& j : t.inputs.joins) {
    j.client_nonce = r.get<std::uint64_t>("join nonce");
    j.protocol_version = r.get<std::uint32_t>("join protocol version");
    const auto leave = r.get<std::uint8_t>("join leave");
    if (leave > 1) throw LogError("tick " + std::to_string(t.tick) + ": join 'leave' byte is " + std::to_string(leave));
    j.leave = leave != 0;
    j.client_id = r.get<std::uint32_t>("join client id");
    j.name = r.get_string("join name", kAnyLength);
    j.sender = senders ? read_key(r, "join sender") : protocol::ParticipantKey{};
    j.identity = senders ? r.get_string("join identity", kAnyLength) : std::string();
  }
  for (auto& c : t.inputs.commands) {
    c.client_id = r.get<std::uint32_t>("command client id");
    c.entity = r.get<std::uint32_t>("command entity");
    c.sequence = r.get<std::uint32_t>("command sequence");
    c.last_seen_tick = r.get<std::uint64_t>("command last seen tick");
    c.move_x = r.get<float>("command move x");
    c.move_y = r.get<float>("command move y");
    c.facing_rad = r.get<float>("command facing");
    c.actions = r.get<std::uint32_t>("command actions");
    c.camera_x = r.get<float>("command camera x");
    c.camera_y = r.get<float>("command camera y");
    c.camera_z = r.get<float>("command camera z");
    c.sender = senders ? read_key(r, "command sender") : protocol::ParticipantKey{};
  }
  for (auto& p : t.inputs.params) {
    p.request_id = r.get<std::uint64_t>("parameter request id");
    p.entity = r.get<std::uint32_t>("parameter entity");
    p.param = r.get_string("parameter name", kAnyLength);
    p.value = r.get<double>("parameter value");
    p.policy_json = r.get_string("parameter policy", kAnyLength);
  }
  pos = r.offset();
}

}  // namespace throng::matchlog
