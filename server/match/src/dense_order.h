#pragma once
// The World re-sorts its dense body arrays into spatial order every few ticks and publishes the
// permutation (World::last_reorder), so per-body arrays kept beside it in dense order follow it.
// perm[new_dense] = old_dense.
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

namespace throng::match {

// v[new] = v_old[perm[new]]; scratch keeps its capacity, so no allocation after the first call.
template <class T>
void apply_permutation(std::vector<T>& v, std::span<const std::uint32_t> perm, std::vector<T>& scratch) {
  scratch.resize(perm.size());
  for (std::size_t d = 0; d < perm.size(); ++d) scratch[d] = v[perm[d]];
  std::swap(v, scratch);
}

}  // namespace throng::match
