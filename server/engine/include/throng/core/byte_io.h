#pragma once
// The project's one binary codec: little-endian writing and bounds-checked reading, for
// checkpoints (World::save_state, match::Match::save_checkpoint) and the match log's records.
// Explicit field-by-field encoding: scalars and arrays of scalars are copied as bytes (the project
// only targets little-endian hosts, checked below, so host order is the format's order), structs
// are never copied whole (their padding bytes are unspecified and would make equal states differ).
//
// Why a reader that throws instead of returning status: a checkpoint is decoded by a chain of
// nested decoders (world, groups, policy, clients, AI, snapshots); one exception type carrying
// "what, at which offset" keeps every one of them short and makes truncation impossible to miss.
// The exception type is the caller's (a checkpoint's, the match log's), so each format reports
// errors in its own terms.
#include <bit>
#include <cstdint>
#include <cstring>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

namespace throng {

static_assert(std::endian::native == std::endian::little, "checkpoints and logs are written in host order = little-endian");

// A checkpoint (or one of its sections) is truncated, malformed, of another version or from
// another scene/config. The message says which.
class CheckpointError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Types whose bytes are exactly their value: scalars, and padding-free wrappers of one integer
// (ObjectId). Arrays of these may be copied as a block.
template <class T>
inline constexpr bool kPlainBytes = std::is_arithmetic_v<T> || std::has_unique_object_representations_v<T>;

// A scalar at a raw position, for framing code that has already checked the bounds itself.
template <class T>
T load_bytes(const std::uint8_t* p) {
  static_assert(std::is_arithmetic_v<T>);
  T v;
  std::memcpy(&v, p, sizeof(T));
  return v;
}
template <class T>
void store_bytes(std::uint8_t* p, T v) {
  static_assert(std::is_arithmetic_v<T>);
  std::memcpy(p, &v, sizeof(T));
}

// Writes into a caller-owned buffer. Two modes:
//  - append (ByteWriter(out)): after out's current contents;
//  - overwrite (ByteWriter(out, ByteWriter::kOverwrite)): from the start, without clearing first,
//    and finish() cuts the buffer to what was written. Why: a cleared vector grown with resize()
//    zero-fills every byte before it is written (a noticeable share of a checkpoint save,
//    docs/design/match-log.md); overwriting the previous checkpoint in place only zero-fills what
//    exceeds the previous size.
// A warm buffer (capacity already reached) never allocates.
class ByteWriter {
 public:
  enum OverwriteTag { kOverwrite };
  explicit ByteWriter(std::vector<std::uint8_t>& out) : out_(out), pos_(out.size()) {}
  ByteWriter(std::vector<std::uint8_t>& out, OverwriteTag) : out_(out), pos_(0) {}

  // Room for n bytes at the write position; the caller fills them (one call for a whole array).
  std::uint8_t* grow(std::size_t n) {
    const std::size_t at = pos_;
    pos_ += n;
    if (pos_ > out_.size()) out_.resize(pos_);
    return out_.data() + at;
  }
  template <class T>
  void put(T v) {
    static_assert(std::is_arithmetic_v<T> || std::is_enum_v<T>);
    std::memcpy(grow(sizeof(T)), &v, sizeof(T));
  }
  // Count (u32) then the elements' bytes.
  template <class T>
  void put_array(std::span<const T> v) {
    static_assert(kPlainBytes<T>);
    put(static_cast<std::uint32_t>(v.size()));
    if (!v.empty()) std::memcpy(grow(v.size() * sizeof(T)), v.data(), v.size() * sizeof(T));
  }
  template <class T>
  void put_array(const std::vector<T>& v) { put_array(std::span<const T>(v)); }
  void put_string(std::string_view s) {
    put(static_cast<std::uint32_t>(s.size()));
    if (!s.empty()) std::memcpy(grow(s.size()), s.data(), s.size());
  }
  // Bytes written so far (the write position).
  std::size_t size() const { return pos_; }
  // Overwrites a u32 written earlier (section lengths are known only after the section).
  void patch_u32(std::size_t at, std::uint32_t v) { std::memcpy(out_.data() + at, &v, sizeof(v)); }
  // Cuts the buffer to what was written (needed in overwrite mode; harmless in append mode).
  void finish() { out_.resize(pos_); }

 private:
  std::vector<std::uint8_t>& out_;
  std::size_t pos_;
};

// Reads what ByteWriter wrote. Every failure throws Error (constructible from a string) naming
// the subject ("checkpoint", "tick entry"), the field and the offset. The subject and every `what`
// are string literals: the reader keeps the subject's pointer.
template <class Error>
class BasicByteReader {
 public:
  BasicByteReader(std::span<const std::uint8_t> bytes, const char* subject, std::size_t pos = 0)
      : bytes_(bytes), subject_(subject), pos_(pos) {}

  const std::uint8_t* take(std::size_t n, const char* what) {
    if (n > remaining()) {
      throw Error(std::string(subject_) + " truncated: " + what + " needs " + std::to_string(n) + " bytes at offset " +
                  std::to_string(pos_) + ", only " + std::to_string(remaining()) + " left");
    }
    const std::uint8_t* p = bytes_.data() + pos_;
    pos_ += n;
    return p;
  }
  template <class T>
  T get(const char* what) {
    static_assert(std::is_arithmetic_v<T> || std::is_enum_v<T>);
    T v;
    std::memcpy(&v, take(sizeof(T), what), sizeof(T));
    return v;
  }
  bool get_bool(const char* what) {
    const auto b = get<std::uint8_t>(what);
    if (b > 1) fail(std::string(what) + ": boolean byte " + std::to_string(b));
    return b != 0;
  }
  // A count that must not exceed `max`, and whose elements (at least min_bytes_each each) must
  // fit in what is left: a corrupt count fails here instead of making the caller allocate gigabytes.
  std::uint32_t get_count(const char* what, std::size_t max, std::size_t min_bytes_each = 0) {
    const auto n = get<std::uint32_t>(what);
    if (n > max) fail(std::string(what) + ": count " + std::to_string(n) + " exceeds " + std::to_string(max));
    if (std::size_t{n} * min_bytes_each > remaining()) {
      throw Error(std::string(subject_) + " truncated: " + what + " lists " + std::to_string(n) + " entries at offset " +
                  std::to_string(pos_) + ", only " + std::to_string(remaining()) + " bytes left");
    }
    return n;
  }
  template <class T>
  void get_array(std::vector<T>& v, const char* what, std::size_t max) {
    static_assert(kPlainBytes<T>);
    const std::uint32_t n = get_count(what, max);
    const std::uint8_t* p = take(std::size_t{n} * sizeof(T), what);
    v.resize(n);
    if (n != 0) std::memcpy(v.data(), p, std::size_t{n} * sizeof(T));
  }
  // An array whose length must be exactly n.
  template <class T>
  void get_array_exact(std::vector<T>& v, const char* what, std::size_t n) {
    get_array(v, what, n);
    if (v.size() != n) fail(std::string(what) + ": " + std::to_string(v.size()) + " entries, expected " + std::to_string(n));
  }
  std::string get_string(const char* what, std::size_t max = 1u << 20) {
    const std::uint32_t n = get_count(what, max);
    const std::uint8_t* p = take(n, what);
    return std::string(reinterpret_cast<const char*>(p), n);
  }

  [[noreturn]] void fail(const std::string& msg) const {
    throw Error(std::string(subject_) + " malformed at offset " + std::to_string(pos_) + ": " + msg);
  }
  std::size_t offset() const { return pos_; }
  std::size_t remaining() const { return bytes_.size() - pos_; }

 private:
  std::span<const std::uint8_t> bytes_;
  const char* subject_;
  std::size_t pos_;
};

// A checkpoint's reader: throws CheckpointError.
class ByteReader : public BasicByteReader<CheckpointError> {
 public:
  explicit ByteReader(std::span<const std::uint8_t> bytes) : BasicByteReader(bytes, "checkpoint") {}
};

}  // namespace throng
