#pragma once
// The serialized size of an XCDR1 payload, computed field by field: primitives aligned to their
// size, sequences as a 4-byte length then their elements. Shared by the wire-size functions.
#include <cstddef>

namespace throng::protocol::detail {

struct CdrSize {
  std::size_t n = 0;
  void align(std::size_t a) { n = (n + a - 1) / a * a; }
  void prim(std::size_t s) { align(s); n += s; }
  void seq(std::size_t count, std::size_t elem) { prim(4); if (count) { align(elem); n += count * elem; } }
};

}  // namespace throng::protocol::detail
