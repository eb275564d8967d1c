#pragma once
// How the fuzz targets turn bytes into the plain protocol structs that DDS hands the decoders
// (Snapshot, ContactPairs, Command), and back (corpus_gen.cpp writes real messages this way).
//
// Layout: fields in declaration order, little-endian, floats as their raw bits (so NaN, infinities
// and denormals all reach the decoder); every vector is a u16 count then its elements; strings a
// u16 length then bytes. Reading past the end gives zeros, so every input is a message: the fuzzer
// explores the decoder, not this layout.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <string>
#include <type_traits>
#include <vector>

#include "throng/protocol/messages.h"

namespace throng::fuzz {

class In {
 public:
  In(const std::uint8_t* data, std::size_t size) : p_(data), n_(size) {}
  explicit In(std::span<const std::uint8_t> b) : In(b.data(), b.size()) {}

  bool empty() const { return pos_ >= n_; }
  std::size_t remaining() const { return pos_ < n_ ? n_ - pos_ : 0; }
  std::span<const std::uint8_t> rest() const { return {p_ + pos_, remaining()}; }

  template <class T>
  T get() {
    static_assert(std::is_trivially_copyable_v<T>);
    T v{};
    const std::size_t k = std::min(sizeof(T), remaining());
    if (k > 0) std::memcpy(&v, p_ + pos_, k);  // little-endian host (x86-64)
    pos_ += sizeof(T);
    return v;
  }
  template <class T>
  std::vector<T> vec() {
    const std::size_t count = get<std::uint16_t>();
    std::vector<T> v;
    for (std::size_t i = 0; i < count && !empty(); ++i) v.push_back(get<T>());
    return v;
  }
  std::string str() {
    const std::size_t len = std::min<std::size_t>(get<std::uint16_t>(), remaining());
    std::string s(reinterpret_cast<const char*>(p_ + pos_), len);
    pos_ += len;
    return s;
  }

 private:
  const std::uint8_t* p_;
  std::size_t n_;
  std::size_t pos_ = 0;
};

class Out {
 public:
  template <class T>
  void put(T v) {
    static_assert(std::is_trivially_copyable_v<T>);
    const auto* b = reinterpret_cast<const std::uint8_t*>(&v);
    bytes.insert(bytes.end(), b, b + sizeof(T));
  }
  template <class T>
  void vec(const std::vector<T>& v) {
    put(static_cast<std::uint16_t>(v.size()));
    for (const T& x : v) put(x);
  }
  void str(const std::string& s) {
    put(static_cast<std::uint16_t>(s.size()));
    bytes.insert(bytes.end(), s.begin(), s.end());
  }
  std::vector<std::uint8_t> bytes;
};

inline protocol::Snapshot read_snapshot(In& in) {
  protocol::Snapshot s;
  s.client_id = in.get<std::uint32_t>();
  s.tick = in.get<std::uint64_t>();
  s.last_applied_sequence = in.get<std::uint32_t>();
  s.last_applied_tick = in.get<std::uint64_t>();
  s.entity = in.get<std::uint32_t>();
  s.entity_x = in.get<float>();
  s.entity_y = in.get<float>();
  s.entity_z = in.get<float>();
  s.entity_yaw = in.get<float>();
  s.origin_x_mm = in.get<std::int32_t>();
  s.origin_y_mm = in.get<std::int32_t>();
  s.unit_mm = in.get<std::uint16_t>();
  s.objects_in_view = in.get<std::uint32_t>();
  s.id_codes = in.vec<std::uint16_t>();
  s.x = in.vec<std::int16_t>();
  s.y = in.vec<std::int16_t>();
  s.z = in.vec<std::int16_t>();
  s.yaw = in.vec<std::uint8_t>();
  s.removed = in.vec<std::uint32_t>();
  return s;
}

inline void write_snapshot(Out& o, const protocol::Snapshot& s) {
  o.put(s.client_id);
  o.put(s.tick);
  o.put(s.last_applied_sequence);
  o.put(s.last_applied_tick);
  o.put(s.entity);
  o.put(s.entity_x);
  o.put(s.entity_y);
  o.put(s.entity_z);
  o.put(s.entity_yaw);
  o.put(s.origin_x_mm);
  o.put(s.origin_y_mm);
  o.put(s.unit_mm);
  o.put(s.objects_in_view);
  o.vec(s.id_codes);
  o.vec(s.x);
  o.vec(s.y);
  o.vec(s.z);
  o.vec(s.yaw);
  o.vec(s.removed);
}

inline protocol::ContactPairs read_contacts(In& in) {
  protocol::ContactPairs c;
  c.client_id = in.get<std::uint32_t>();
  c.tick = in.get<std::uint64_t>();
  c.pairs_near = in.get<std::uint32_t>();
  c.camera_x = in.get<float>();
  c.camera_y = in.get<float>();
  c.radius_m = in.get<float>();
  c.a = in.vec<std::uint32_t>();
  c.b = in.vec<std::uint32_t>();
  c.share_a = in.vec<std::uint16_t>();
  c.depth = in.vec<std::uint16_t>();
  c.push = in.vec<std::uint16_t>();
  return c;
}

inline void write_contacts(Out& o, const protocol::ContactPairs& c) {
  o.put(c.client_id);
  o.put(c.tick);
  o.put(c.pairs_near);
  o.put(c.camera_x);
  o.put(c.camera_y);
  o.put(c.radius_m);
  o.vec(c.a);
  o.vec(c.b);
  o.vec(c.share_a);
  o.vec(c.depth);
  o.vec(c.push);
}

inline protocol::Command read_command(In& in) {
  protocol::Command c;
  c.client_id = in.get<std::uint32_t>();
  c.entity = in.get<std::uint32_t>();
  c.sequence = in.get<std::uint32_t>();
  c.last_seen_tick = in.get<std::uint64_t>();
  c.move_x = in.get<float>();
  c.move_y = in.get<float>();
  c.facing_rad = in.get<float>();
  c.actions = in.get<std::uint32_t>();
  c.camera_x = in.get<float>();
  c.camera_y = in.get<float>();
  c.camera_z = in.get<float>();
  return c;
}

inline void write_command(Out& o, const protocol::Command& c) {
  o.put(c.client_id);
  o.put(c.entity);
  o.put(c.sequence);
  o.put(c.last_seen_tick);
  o.put(c.move_x);
  o.put(c.move_y);
  o.put(c.facing_rad);
  o.put(c.actions);
  o.put(c.camera_x);
  o.put(c.camera_y);
  o.put(c.camera_z);
}

}  // namespace throng::fuzz
