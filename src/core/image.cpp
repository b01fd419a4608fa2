#include "fss/core/image.h"

#include <sys/mman.h>

#include <algorithm>
#include <cstdint>
#include <string>

#include "core/huge_pages.h"
#include "fss/core/error.h"

namespace fss {

namespace {

// Buffers at least this large are prefaulted in one call.
constexpr std::size_t kPrefaultBytes = std::size_t{1} << 20;

// Maps the whole pages of [data, data + bytes) writable in one system call, where a first
// touch would fault once per page (MADV_POPULATE_WRITE, Linux 5.14); the kernel's per-fault
// cost, large in a virtual machine, is paid once. A hint only: where the kernel lacks it, the
// pages fault in as they are touched.
void prefault(void* data, std::size_t bytes) {
#ifdef __linux__
  constexpr int kPopulateWrite = 23;  // MADV_POPULATE_WRITE, absent from older headers
  constexpr std::uintptr_t kPage = 4096;
  const auto address = reinterpret_cast<std::uintptr_t>(data);
  const std::uintptr_t head = (kPage - address % kPage) % kPage;  // to the first whole page
  if (bytes < head + kPage) return;
  const std::size_t length = (bytes - head) & ~(kPage - 1);  // whole pages only
  ::madvise(static_cast<char*>(data) + head, length, kPopulateWrite);
#else
  (void)data;
  (void)bytes;
#endif
}

}  // namespace

// Samples of less than 1 MiB come from the heap; larger buffers are mapped on huge pages
// (core/huge_pages.cpp): an image's first touch, a page fault every 4 KiB otherwise, is a large
// part of a small run's time on a virtual machine.
void* detail::allocate_samples(std::size_t bytes) { return detail::allocate_buffer(bytes); }

void detail::free_samples(void* data, std::size_t bytes) noexcept {
  detail::free_buffer(data, bytes);
}

bool operator==(const Samples& a, const std::vector<double>& b) {
  return std::equal(a.begin(), a.end(), b.begin(), b.end());
}

Image::Image(int width_px, int height_px, int channel_count, double fill)
    : width(width_px), height(height_px), channels(channel_count) {
  if (width_px < 0 || height_px < 0 || channel_count < 0) {
    throw_usage_error("image size " + std::to_string(width_px) + "x" + std::to_string(height_px) +
                      "x" + std::to_string(channel_count) + " must not be negative");
  }
  const std::size_t count = plane_size() * static_cast<std::size_t>(channel_count);
  data.reserve(count);
  if (count * sizeof(double) >= kPrefaultBytes) prefault(data.data(), count * sizeof(double));
  data.assign(count, fill);
}

Image crop_columns(const Image& image, int first, int count) {
  if (first < 0 || count < 0 || first + count > image.width) {
    throw_usage_error("column range [" + std::to_string(first) + ", " +
                      std::to_string(first + count) + ") is outside an image of width " +
                      std::to_string(image.width));
  }
  Image out(count, image.height, image.channels);
  for (int c = 0; c < image.channels; ++c) {
    for (int y = 0; y < image.height; ++y) {
      const double* src = image.row(c, y) + first;
      std::copy(src, src + count, out.row(c, y));
    }
  }
  return out;
}

Image scaled(const Image& image, double factor) {
  Image out = image;
  for (double& value : out.data) value *= factor;
  return out;
}

}  // namespace fss
