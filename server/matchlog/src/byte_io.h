#pragma once
// Little-endian writers/readers with explicit sizes. Floats and doubles travel as their IEEE-754
// bit patterns (std::bit_cast), so a log is byte-identical on every platform.
#include <bit>
#include <cstdint>
#include <cstring>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "throng/matchlog/format.h"

namespace throng::matchlog::detail {

inline void put_u8(std::vector<std::uint8_t>& o, std::uint8_t v) { o.push_back(v); }
inline void put_u32(std::vector<std::uint8_t>& o, std::uint32_t v) {
  // Four push_backs, not an insert of a 4-byte array: GCC 12 warns falsely (-Wstringop-overflow)
  // about the insert into a vector it believes empty once this is inlined into small functions.
  o.push_back(static_cast<std::uint8_t>(v));
  o.push_back(static_cast<std::uint8_t>(v >> 8));
  o.push_back(static_cast<std::uint8_t>(v >> 16));
  o.push_back(static_cast<std::uint8_t>(v >> 24));
}
inline void put_u64(std::vector<std::uint8_t>& o, std::uint64_t v) {
  put_u32(o, static_cast<std::uint32_t>(v));
  put_u32(o, static_cast<std::uint32_t>(v >> 32));
}
inline void put_f32(std::vector<std::uint8_t>& o, float v) { put_u32(o, std::bit_cast<std::uint32_t>(v)); }
inline void put_f64(std::vector<std::uint8_t>& o, double v) { put_u64(o, std::bit_cast<std::uint64_t>(v)); }
inline void put_str(std::vector<std::uint8_t>& o, std::string_view s) {
  put_u32(o, static_cast<std::uint32_t>(s.size()));
  o.insert(o.end(), s.begin(), s.end());
}
inline void store_u32(std::uint8_t* p, std::uint32_t v) {
  p[0] = static_cast<std::uint8_t>(v);
  p[1] = static_cast<std::uint8_t>(v >> 8);
  p[2] = static_cast<std::uint8_t>(v >> 16);
  p[3] = static_cast<std::uint8_t>(v >> 24);
}
inline std::uint32_t load_u32(const std::uint8_t* p) {
  return static_cast<std::uint32_t>(p[0]) | static_cast<std::uint32_t>(p[1]) << 8 |
         static_cast<std::uint32_t>(p[2]) << 16 | static_cast<std::uint32_t>(p[3]) << 24;
}
inline std::uint64_t load_u64(const std::uint8_t* p) {
  return static_cast<std::uint64_t>(load_u32(p)) | static_cast<std::uint64_t>(load_u32(p + 4)) << 32;
}

// Bounds-checked cursor over a byte span; every read past the end throws LogError(what + context).
class ByteReader {
 public:
  ByteReader(std::span<const std::uint8_t> b, std::size_t pos = 0) : b_(b), pos_(pos) {}
  std::size_t pos() const { return pos_; }
  std::size_t remaining() const { return b_.size() - pos_; }
  bool at_end() const { return pos_ == b_.size(); }
  std::uint8_t u8() { need(1); return b_[pos_++]; }
  std::uint32_t u32() { need(4); const std::uint32_t v = load_u32(b_.data() + pos_); pos_ += 4; return v; }
  std::uint64_t u64() { need(8); const std::uint64_t v = load_u64(b_.data() + pos_); pos_ += 8; return v; }
  float f32() { return std::bit_cast<float>(u32()); }
  double f64() { return std::bit_cast<double>(u64()); }
  std::string str() {
    const std::uint32_t n = u32();
    need(n);
    std::string s(reinterpret_cast<const char*>(b_.data() + pos_), n);
    pos_ += n;
    return s;
  }
  // A count of items each at least min_item_bytes long: rejects counts the remaining bytes cannot
  // hold, so a damaged count never makes the decoder reserve gigabytes.
  std::uint32_t count(std::size_t min_item_bytes) {
    const std::uint32_t n = u32();
    if (min_item_bytes > 0 && n > remaining() / min_item_bytes) throw LogError("item count " + std::to_string(n) + " exceeds the bytes left");
    return n;
  }
  void need(std::size_t n) const {
    if (n > remaining()) throw LogError("entry runs past the end of its block (needs " + std::to_string(n) + " bytes, " + std::to_string(remaining()) + " left)");
  }

 private:
  std::span<const std::uint8_t> b_;
  std::size_t pos_;
};

}  // namespace throng::matchlog::detail
