#include "core/huge_pages.h"

#include <cstdint>
#include <cstring>
#include <new>

#ifdef __linux__
#include <sys/mman.h>
#endif

namespace fss::detail {

namespace {
constexpr std::size_t kPageBytes = 4096;
constexpr std::size_t kBufferAlignment = 64;  // a cache line

// Mappings of their own on Linux; elsewhere, and under AddressSanitizer (which sees an access
// beyond a heap buffer, not beyond a mapping's requested bytes), aligned heap buffers.
#if defined(__SANITIZE_ADDRESS__)
constexpr bool kOwnMappings = false;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
constexpr bool kOwnMappings = false;
#else
constexpr bool kOwnMappings = true;
#endif
#else
constexpr bool kOwnMappings = true;
#endif

std::size_t round_up(std::size_t bytes, std::size_t unit) {
  return (bytes + unit - 1) / unit * unit;
}

void* heap_zeros(std::size_t bytes, std::size_t alignment) {
  void* data = ::operator new (bytes == 0 ? 1 : bytes, std::align_val_t{alignment});
  std::memset(data, 0, bytes);
  return data;
}
}  // namespace

// A mapping of its own for `bytes`, rounded up to whole huge pages and starting on a huge-page
// boundary, advised to the kernel as such (MADV_HUGEPAGE): where transparent huge pages are on,
// the first touch of each 2 MiB costs one page fault instead of 512, which on a virtual machine
// is most of the cost of fresh memory (CONTRIBUTING.md, "Hand-written fast paths"). The
// resident memory is at most the rounded length: less than `bytes` + 2 MiB (memory_estimate.cpp
// counts it). The bytes are zeros. Throws std::bad_alloc when the system has no room.
void* map_on_huge_pages(std::size_t bytes) {
#ifdef __linux__
  if (kOwnMappings) {
    const std::size_t length = round_up(bytes == 0 ? 1 : bytes, kHugePageBytes);
    const std::size_t span = length + kHugePageBytes - kPageBytes;
    if (length < bytes || span < length) throw std::bad_alloc();
    void* mapped =
        ::mmap(nullptr, span, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (mapped == MAP_FAILED) throw std::bad_alloc();
    auto* const first = static_cast<char*>(mapped);
    const auto address = reinterpret_cast<std::uintptr_t>(mapped);
    const std::size_t head = round_up(address, kHugePageBytes) - address;
    // The unaligned head and what is left beyond `length` go back at once.
    if (head > 0) ::munmap(first, head);
    if (span - head > length) ::munmap(first + head + length, span - head - length);
    char* const data = first + head;
    ::madvise(data, length, MADV_HUGEPAGE);  // a hint only
    return data;
  }
#endif
  return heap_zeros(bytes, kHugePageBytes);
}

void unmap_huge_pages(void* data, std::size_t bytes) noexcept {
  if (data == nullptr) return;
#ifdef __linux__
  if (kOwnMappings) {
    ::munmap(data, round_up(bytes == 0 ? 1 : bytes, kHugePageBytes));
    return;
  }
#endif
  ::operator delete (data, std::align_val_t{kHugePageBytes});
}

// A buffer of `bytes`, not initialized: from the heap, 64-byte aligned, below kHugeBufferBytes;
// on huge pages of its own (map_on_huge_pages) from there. free_buffer takes the same `bytes`.
void* allocate_buffer(std::size_t bytes) {
  if (bytes < kHugeBufferBytes) return ::operator new (bytes, std::align_val_t{kBufferAlignment});
  return map_on_huge_pages(bytes);
}

void free_buffer(void* data, std::size_t bytes) noexcept {
  if (bytes < kHugeBufferBytes) {
    ::operator delete (data, std::align_val_t{kBufferAlignment});
  } else {
    unmap_huge_pages(data, bytes);
  }
}

// The whole huge pages inside [data, data + bytes) advised to the kernel as such (MADV_HUGEPAGE),
// on memory of the heap: where transparent huge pages are on, their first touch is then one page
// fault each, not 512. The few kilobytes before the first huge-page boundary and after the last
// keep small pages. A hint only; nothing under AddressSanitizer or off Linux.
void advise_huge_pages(void* data, std::size_t bytes) noexcept {
#ifdef __linux__
  if (kOwnMappings) {
    const auto start = reinterpret_cast<std::uintptr_t>(data);
    const std::size_t head = round_up(start, kHugePageBytes) - start;
    const std::size_t whole = bytes > head ? (bytes - head) / kHugePageBytes * kHugePageBytes : 0;
    if (whole > 0) ::madvise(static_cast<char*>(data) + head, whole, MADV_HUGEPAGE);
  }
#endif
  (void)data;
  (void)bytes;
}

// A mapping of its own for `bytes` of zeros: the kernel hands out a zeroed page at its first
// touch, so that a large table of counters of which few are used (a histogram of 2^16 levels
// of an 8-bit image) costs the pages touched, not a fill of the whole.
void* map_zeroed_pages(std::size_t bytes) {
#ifdef __linux__
  if (kOwnMappings) {
    void* mapped = ::mmap(nullptr, bytes == 0 ? 1 : bytes, PROT_READ | PROT_WRITE,
                          MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (mapped == MAP_FAILED) throw std::bad_alloc();
    return mapped;
  }
#endif
  return heap_zeros(bytes, kPageBytes);
}

void unmap_zeroed_pages(void* data, std::size_t bytes) noexcept {
  if (data == nullptr) return;
#ifdef __linux__
  if (kOwnMappings) {
    ::munmap(data, round_up(bytes == 0 ? 1 : bytes, kPageBytes));
    return;
  }
#endif
  ::operator delete (data, std::align_val_t{kPageBytes});
}

}  // namespace fss::detail
