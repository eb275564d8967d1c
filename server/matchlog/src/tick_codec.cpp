// Tick entries: the binary layout of FORMAT.md "Tick entry". Encoding sizes the output once and
// stores through a pointer (the tick thread calls this for every tick, so it must be cheap and
// allocation-free once the buffer has grown to the busiest tick).
#include <bit>
#include <cstring>

#include "byte_io.h"
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

class Out {
 public:
  explicit Out(std::uint8_t* p) : p_(p) {}
  void u8(std::uint8_t v) { *p_++ = v; }
  void u32(std::uint32_t v) { detail::store_u32(p_, v); p_ += 4; }
  void u64(std::uint64_t v) { u32(static_cast<std::uint32_t>(v)); u32(static_cast<std::uint32_t>(v >> 32)); }
  void f32(float v) { u32(std::bit_cast<std::uint32_t>(v)); }
  void f64(double v) { u64(std::bit_cast<std::uint64_t>(v)); }
  void key(const protocol::ParticipantKey& k) {
    std::memcpy(p_, k.bytes.data(), k.bytes.size());
    p_ += k.bytes.size();
  }
  void str(const std::string& s) {
    u32(static_cast<std::uint32_t>(s.size()));
    if (!s.empty()) std::memcpy(p_, s.data(), s.size());
    p_ += s.size();
  }
  std::uint8_t* ptr() const { return p_; }

 private:
  std::uint8_t* p_;
};

protocol::ParticipantKey read_key(detail::ByteReader& r) {
  protocol::ParticipantKey k;
  for (auto& b : k.bytes) b = r.u8();
  return k;
}

}  // namespace

std::size_t encoded_tick_size(const match::TickInputs& in) {
  std::size_t n = kTickFixedBytes + in.commands.size() * kCommandBytes;
  for (const auto& j : in.joins) n += kJoinFixedBytes + j.name.size() + j.identity.size();
  for (const auto& p : in.params) n += kParamFixedBytes + p.param.size() + p.policy_json.size();
  return n;
}

void encode_tick(std::uint64_t tick, const match::TickInputs& in, std::uint64_t state_hash, std::uint8_t flags,
                 std::vector<std::uint8_t>& out) {
  const std::size_t start = out.size();
  const std::size_t size = encoded_tick_size(in);
  out.resize(start + size);
  Out o(out.data() + start);
  o.u64(tick);
  o.u64(state_hash);
  o.u8(flags);
  o.u32(static_cast<std::uint32_t>(in.joins.size()));
  o.u32(static_cast<std::uint32_t>(in.commands.size()));
  o.u32(static_cast<std::uint32_t>(in.params.size()));
  for (const auto& j : in.joins) {
    o.u64(j.client_nonce);
    o.u32(j.protocol_version);
    o.u8(j.leave ? 1 : 0);
    o.u32(j.client_id);
    o.str(j.name);
    o.key(j.sender);
    o.str(j.identity);
  }
  for (const auto& c : in.commands) {
    o.u32(c.client_id);
    o.u32(c.entity);
    o.u32(c.sequence);
    o.u64(c.last_seen_tick);
    o.f32(c.move_x);
    o.f32(c.move_y);
    o.f32(c.facing_rad);
    o.u32(c.actions);
    o.f32(c.camera_x);
    o.f32(c.camera_y);
    o.f32(c.camera_z);
    o.key(c.sender);
  }
  for (const auto& p : in.params) {
    o.u64(p.request_id);
    o.u32(p.entity);
    o.str(p.param);
    o.f64(p.value);
    o.str(p.policy_json);
  }
}

void decode_tick(std::span<const std::uint8_t> bytes, std::size_t& pos, TickRecord& t, std::uint32_t format_version) {
  const bool senders = format_version >= 3;
  detail::ByteReader r(bytes, pos);
  t.tick = r.u64();
  t.state_hash = r.u64();
  t.flags = r.u8();
  if ((t.flags & ~kKnownTickFlags) != 0)
    throw LogError("tick " + std::to_string(t.tick) + " has unknown flag bits 0x" + std::to_string(t.flags) +
                   " (written by a newer build?)");
  const std::uint32_t nj = r.count(senders ? kJoinFixedBytes : kJoinFixedBytesV2);
  const std::uint32_t nc = r.count(senders ? kCommandBytes : kCommandBytesV2);
  const std::uint32_t np = r.count(kParamFixedBytes);
  t.inputs.joins.resize(nj);
  t.inputs.commands.resize(nc);
  t.inputs.params.resize(np);
  for (auto& j : t.inputs.joins) {
    j.client_nonce = r.u64();
    j.protocol_version = r.u32();
    const std::uint8_t leave = r.u8();
    if (leave > 1) throw LogError("tick " + std::to_string(t.tick) + ": join 'leave' byte is " + std::to_string(leave));
    j.leave = leave != 0;
    j.client_id = r.u32();
    j.name = r.str();
    j.sender = senders ? read_key(r) : protocol::ParticipantKey{};
    j.identity = senders ? r.str() : std::string();
  }
  for (auto& c : t.inputs.commands) {
    c.client_id = r.u32();
    c.entity = r.u32();
    c.sequence = r.u32();
    c.last_seen_tick = r.u64();
    c.move_x = r.f32();
    c.move_y = r.f32();
    c.facing_rad = r.f32();
    c.actions = r.u32();
    c.camera_x = r.f32();
    c.camera_y = r.f32();
    c.camera_z = r.f32();
    c.sender = senders ? read_key(r) : protocol::ParticipantKey{};
  }
  for (auto& p : t.inputs.params) {
    p.request_id = r.u64();
    p.entity = r.u32();
    p.param = r.str();
    p.value = r.f64();
    p.policy_json = r.str();
  }
  pos = r.pos();
}

}  // namespace throng::matchlog
