#pragma once
// The World re-sorts its dense body arrays into spatial order every few ticks (world_step.cpp:
// reorder_dense, every 16 ticks), so per-body arrays kept beside it in dense order must follow.
// perm[new_dense] = old_dense.
#include <cstdint>
#include <utility>
#include <vector>

namespace throng::match {

// v[new] = v_old[perm[new]]; scratch keeps its capacity, so no allocation after the first call.
template <class T>
void apply_permutation(std::vector<T>& v, const std::vector<std::uint32_t>& perm, std::vector<T>& scratch) {
  scratch.resize(perm.size());
  for (std::size_t d = 0; d < perm.size(); ++d) scratch[d] = v[perm[d]];
  std::swap(v, scratch);
}

}  // namespace throng::match
