#pragma once
// Object ids: an index into the world's dense arrays plus a generation counter, packed in 32 bits.
// 0 means "no object". The same value is the key clients see on the wire, so it must stay stable
// while the object lives and must never alias a destroyed object's id (the generation guards that).
//
// Layout: low 22 bits = index + 1 (so index 0 still gives a non-zero id), high 10 bits =
// generation. 4M live objects is far beyond any crowd we host; a slot must be reused 1024 times
// before an id repeats, and stale ids are rejected by the generation check long before that.
#include <cstdint>
#include <functional>

namespace throng {

struct ObjectId {
  static constexpr std::uint32_t kIndexBits = 22;
  static constexpr std::uint32_t kIndexMask = (1u << kIndexBits) - 1u;
  static constexpr std::uint32_t kMaxIndex = kIndexMask - 1u;  // index + 1 must fit in the mask
  static constexpr std::uint32_t kGenerationMask = (1u << (32 - kIndexBits)) - 1u;

  std::uint32_t value = 0;

  static constexpr ObjectId make(std::uint32_t index, std::uint32_t generation) {
    return ObjectId{((generation & kGenerationMask) << kIndexBits) | ((index + 1u) & kIndexMask)};
  }
  constexpr bool valid() const { return value != 0; }
  constexpr std::uint32_t index() const { return (value & kIndexMask) - 1u; }
  constexpr std::uint32_t generation() const { return value >> kIndexBits; }
  constexpr auto operator<=>(const ObjectId&) const = default;
};

inline constexpr ObjectId kNoObject{};

}  // namespace throng

template <>
struct std::hash<throng::ObjectId> {
  std::size_t operator()(throng::ObjectId id) const noexcept { return id.value; }
};
