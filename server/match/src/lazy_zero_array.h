#pragma once
// An array of zero-initialised records whose memory is not touched until written. Why: every
// snapshot client keeps a record per object index (tens of thousands of bytes per client), and a
// match restored from a checkpoint creates all its clients at once: zero-filling their arrays with
// std::vector page-faulted and cleared every page, half of a seek's first re-simulated tick. A
// fresh anonymous mapping is zero pages until written, so only the records a client actually sees
// cost, unless the owner commits the array (a live join does: snapshot_builder.cpp says why).
//
// Why mmap and not calloc: glibc serves a large calloc from a mapping only until the first such
// block is freed, then raises its mapping threshold above that size, and later clients' arrays come
// from the heap, where calloc clears every byte and a departed client's hole outlives it (a server
// whose clients come and go for hours grows). A mapping of its own is zero without clearing and
// goes back to the kernel whole when the client leaves.
#include <sys/mman.h>
#include <unistd.h>

#include <cstddef>
#include <new>
#include <type_traits>
#include <utility>

namespace throng::match::detail {

// T must be trivially copyable and its all-zero bytes must be its default state (the records'
// defaults are all zero).
template <class T>
class LazyZeroArray {
  static_assert(std::is_trivially_copyable_v<T>, "records are moved by remapping their pages");

 public:
  LazyZeroArray() = default;
  LazyZeroArray(const LazyZeroArray&) = delete;
  LazyZeroArray& operator=(const LazyZeroArray&) = delete;
  LazyZeroArray(LazyZeroArray&& o) noexcept { swap(o); }
  LazyZeroArray& operator=(LazyZeroArray&& o) noexcept {
    LazyZeroArray(std::move(o)).swap(*this);
    return *this;
  }
  ~LazyZeroArray() {
    if (data_ != nullptr) munmap(data_, mapped_);
  }

  // Grows to n records, keeping the first size() and zeroing the rest; never shrinks. The bytes past
  // the records in the mapping's last page were never written, so they are still zero.
  void grow_to(std::size_t n) {
    if (n <= size_) return;
    if (n > max_records()) throw std::bad_alloc();
    const std::size_t bytes = page_round(n * sizeof(T));
    if (bytes > mapped_) {
      void* p = data_ == nullptr ? mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0)
                                 : mremap(data_, mapped_, bytes, MREMAP_MAYMOVE);  // keeps the records, zero tail
      if (p == MAP_FAILED) throw std::bad_alloc();
      // No transparent huge pages: one record written would make 2 MiB resident, which is what
      // the laziness is there to avoid (the flag stays with the mapping through mremap).
      if (data_ == nullptr) madvise(p, bytes, MADV_NOHUGEPAGE);
      data_ = static_cast<T*>(p);
      mapped_ = bytes;
    }
    size_ = n;
  }

  // Makes the mapping's pages resident now, records unchanged; after a growth only the pages the
  // last commit did not cover. Each page's first byte is read and written back: a write is what
  // gives an untouched page memory of its own.
  void commit() {
    const auto page = static_cast<std::size_t>(sysconf(_SC_PAGESIZE));
    auto* bytes = reinterpret_cast<volatile unsigned char*>(data_);
    for (std::size_t off = committed_; off < mapped_; off += page) bytes[off] = bytes[off];
    committed_ = mapped_;
  }

  std::size_t size() const { return size_; }
  T* data() { return data_; }
  const T* data() const { return data_; }
  T& operator[](std::size_t i) { return data_[i]; }
  const T& operator[](std::size_t i) const { return data_[i]; }
  T* begin() { return data_; }
  T* end() { return data_ + size_; }

 private:
  static std::size_t max_records() { return (std::size_t{1} << 40) / sizeof(T); }
  static std::size_t page_round(std::size_t bytes) {
    const auto page = static_cast<std::size_t>(sysconf(_SC_PAGESIZE));
    return (bytes + page - 1) / page * page;
  }
  void swap(LazyZeroArray& o) noexcept {
    std::swap(data_, o.data_);
    std::swap(size_, o.size_);
    std::swap(mapped_, o.mapped_);
    std::swap(committed_, o.committed_);
  }

  T* data_ = nullptr;   // page-aligned (alignof(T) is far smaller)
  std::size_t size_ = 0;
  std::size_t mapped_ = 0;  // bytes mapped, a whole number of pages
  std::size_t committed_ = 0;  // bytes commit() made resident (the mapping's first ones)
};

}  // namespace throng::match::detail
