// Buffers mapped on their own: large ones on transparent huge pages, and zeroed ones whose
// pages are touched on demand. Internal to the library.
#pragma once

#include <cstddef>
#include <memory>

namespace fss::detail {

// The size of a huge page (x86-64 and most 64-bit Linux systems).
inline constexpr std::size_t kHugePageBytes = std::size_t{2} << 20;
// Buffers of at least this many bytes are worth a mapping on huge pages.
inline constexpr std::size_t kHugeBufferBytes = std::size_t{1} << 20;

void* map_on_huge_pages(std::size_t bytes);
void unmap_huge_pages(void* data, std::size_t bytes) noexcept;

void* allocate_buffer(std::size_t bytes);
void free_buffer(void* data, std::size_t bytes) noexcept;

// `bytes` of zeros on huge pages of their own (map_on_huge_pages): the scratch of one task (a
// PNG encoder's, a sorter's), whose first touch is then one page fault per 2 MiB.
class HugePageBuffer {
 public:
  explicit HugePageBuffer(std::size_t bytes)
      : bytes_(bytes), data_(static_cast<unsigned char*>(map_on_huge_pages(bytes))) {}
  ~HugePageBuffer() { unmap_huge_pages(data_, bytes_); }
  HugePageBuffer(const HugePageBuffer&) = delete;
  HugePageBuffer& operator=(const HugePageBuffer&) = delete;
  unsigned char* data() const { return data_; }

 private:
  std::size_t bytes_;
  unsigned char* data_;
};

// n values of T (a trivial type) from Acquire(bytes), given back by Release(data, bytes).
template <typename T, void* (*Acquire)(std::size_t), void (*Release)(void*, std::size_t) noexcept>
class OwnedArray {
 public:
  explicit OwnedArray(std::size_t n)
      : data_(static_cast<T*>(Acquire(n * sizeof(T))), Give{n * sizeof(T)}) {}
  T* data() const { return data_.get(); }
  T& operator[](std::size_t i) const { return data_.get()[i]; }

 private:
  struct Give {
    std::size_t bytes;
    void operator()(T* data) const noexcept { Release(data, bytes); }
  };
  std::unique_ptr<T, Give> data_;
};

// n values of T, not initialized, from allocate_buffer: on huge pages of their own from
// kHugeBufferBytes on.
template <typename T>
using BufferArray = OwnedArray<T, allocate_buffer, free_buffer>;

void* map_zeroed_pages(std::size_t bytes);
void unmap_zeroed_pages(void* data, std::size_t bytes) noexcept;

// n zeros of T (an integer type) on pages of their own (map_zeroed_pages).
template <typename T>
using ZeroedArray = OwnedArray<T, map_zeroed_pages, unmap_zeroed_pages>;

void advise_huge_pages(void* data, std::size_t bytes) noexcept;

// v.reserve(n), and the whole huge pages of its storage advised as such (advise_huge_pages):
// for a large std::vector or std::string about to be written through once.
template <typename Container>
void reserve_on_huge_pages(Container& v, std::size_t n) {
  v.reserve(n);
  if (v.capacity() >= kHugeBufferBytes) advise_huge_pages(v.data(), v.capacity());
}

}  // namespace fss::detail
