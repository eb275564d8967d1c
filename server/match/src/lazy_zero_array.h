#pragma once
// An array of zero-initialised records whose memory is not touched until written. Why: every
// snapshot client keeps a record per object index (tens of thousands of bytes per client), and a
// match restored from a checkpoint creates all its clients at once: zero-filling their arrays with
// std::vector page-faulted and cleared every page, half of a seek's first re-simulated tick. A
// large calloc maps fresh zero pages lazily, so only the records a client actually sees cost.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <new>
#include <type_traits>
#include <utility>

namespace throng::match::detail {

// T must be trivially copyable and its all-zero bytes must be its default state (the records'
// defaults are all zero); the storage is aligned to alignof(T).
template <class T>
class LazyZeroArray {
  static_assert(std::is_trivially_copyable_v<T>, "records are moved with memcpy");

 public:
  LazyZeroArray() = default;
  LazyZeroArray(const LazyZeroArray&) = delete;
  LazyZeroArray& operator=(const LazyZeroArray&) = delete;
  LazyZeroArray(LazyZeroArray&& o) noexcept { swap(o); }
  LazyZeroArray& operator=(LazyZeroArray&& o) noexcept {
    LazyZeroArray(std::move(o)).swap(*this);
    return *this;
  }
  ~LazyZeroArray() { std::free(raw_); }

  // Grows to n records, keeping the first size() and zeroing the rest; never shrinks.
  void grow_to(std::size_t n) {
    if (n <= size_) return;
    void* raw = std::calloc(n * sizeof(T) + alignof(T), 1);
    if (raw == nullptr) throw std::bad_alloc();
    const auto at = (reinterpret_cast<std::uintptr_t>(raw) + alignof(T) - 1) & ~(std::uintptr_t{alignof(T)} - 1);
    T* data = reinterpret_cast<T*>(at);
    if (size_ > 0) std::memcpy(static_cast<void*>(data), static_cast<const void*>(data_), size_ * sizeof(T));
    std::free(raw_);
    raw_ = raw;
    data_ = data;
    size_ = n;
  }

  std::size_t size() const { return size_; }
  T* data() { return data_; }
  const T* data() const { return data_; }
  T& operator[](std::size_t i) { return data_[i]; }
  const T& operator[](std::size_t i) const { return data_[i]; }
  T* begin() { return data_; }
  T* end() { return data_ + size_; }

 private:
  void swap(LazyZeroArray& o) noexcept {
    std::swap(raw_, o.raw_);
    std::swap(data_, o.data_);
    std::swap(size_, o.size_);
  }

  void* raw_ = nullptr;
  T* data_ = nullptr;
  std::size_t size_ = 0;
};

}  // namespace throng::match::detail
