#pragma once
// LSD radix sort of (64-bit key, 32-bit payload) pairs, stable, 8 passes of 8 bits at most.
// Passes whose digit is the same for every key are skipped, so clustered crowds (narrow key range)
// usually need 2-4 passes. Stable + deterministic: equal keys keep their input order, which is the
// previous tick's order, so the broadphase output only depends on the inputs.
#include <array>
#include <cstdint>
#include <vector>

namespace throng::detail {

struct KeyIndex {
  std::uint64_t key;
  std::uint32_t index;
};

// max_key bounds every key: digits above it are all zero and are neither counted nor sorted (the
// broadphase's dense cell keys need 2-3 of the 8 digits; counting all 8 was half the sort's cost).
inline void radix_sort(std::vector<KeyIndex>& items, std::vector<KeyIndex>& scratch,
                       std::uint64_t max_key = ~std::uint64_t{0}) {
  const std::size_t n = items.size();
  if (n < 2) return;
  scratch.resize(n);
  int digits = 1;
  while (digits < 8 && (max_key >> (8 * digits)) != 0) ++digits;
  std::array<std::array<std::uint32_t, 256>, 8> hist{};
  for (const KeyIndex& it : items) {
    std::uint64_t k = it.key;
    for (int p = 0; p < digits; ++p) { ++hist[p][k & 0xFFu]; k >>= 8; }
  }
  KeyIndex* src = items.data();
  KeyIndex* dst = scratch.data();
  for (int p = 0; p < digits; ++p) {
    auto& h = hist[p];
    bool trivial = false;
    for (std::uint32_t c : h) { if (c == n) { trivial = true; break; } }
    if (trivial) continue;
    std::uint32_t sum = 0;
    for (std::uint32_t& c : h) { const std::uint32_t t = c; c = sum; sum += t; }
    const int shift = 8 * p;
    for (std::size_t i = 0; i < n; ++i) dst[h[(src[i].key >> shift) & 0xFFu]++] = src[i];
    std::swap(src, dst);
  }
  if (src != items.data()) items.swap(scratch);
}

}  // namespace throng::detail
