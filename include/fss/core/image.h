// The image type of fss: planar doubles on the 0..255 scale (conventions: fss/fss.h).
#pragma once

#include <cstddef>
#include <new>
#include <vector>

namespace fss {

namespace detail {
void* allocate_samples(std::size_t bytes);
void free_samples(void* data, std::size_t bytes) noexcept;
}  // namespace detail

// The allocator of an image's samples: the heap's, but a buffer of 1 MiB or more
// gets a mapping of its own on huge pages (see detail::allocate_samples).
template <typename T>
struct SampleAllocator {
  using value_type = T;
  SampleAllocator() = default;
  template <typename U>
  // NOLINTNEXTLINE(google-explicit-constructor): allocators convert implicitly
  SampleAllocator(const SampleAllocator<U>& /*other*/) noexcept {}
  T* allocate(std::size_t n) {
    if (n > static_cast<std::size_t>(-1) / sizeof(T)) throw std::bad_array_new_length();
    return static_cast<T*>(detail::allocate_samples(n * sizeof(T)));
  }
  void deallocate(T* data, std::size_t n) noexcept { detail::free_samples(data, n * sizeof(T)); }
  friend bool operator==(const SampleAllocator& /*a*/, const SampleAllocator& /*b*/) {
    return true;
  }
};

// An image's samples: a std::vector of doubles with SampleAllocator. To set them from a
// std::vector<double> v: samples.assign(v.begin(), v.end()).
using Samples = std::vector<double, SampleAllocator<double>>;

// Whether `a` holds the values of `b`, in order.
bool operator==(const Samples& a, const std::vector<double>& b);

struct Image {
  int width = 0;
  int height = 0;
  int channels = 0;
  Samples data;

  Image() = default;
  Image(int width_px, int height_px, int channel_count, double fill = 0.0);

  std::size_t plane_size() const {
    return static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  }
  double* row(int c, int y) {
    return data.data() + (static_cast<std::size_t>(c) * height + y) * width;
  }
  const double* row(int c, int y) const {
    return data.data() + (static_cast<std::size_t>(c) * height + y) * width;
  }
  double& at(int c, int y, int x) { return row(c, y)[x]; }
  double at(int c, int y, int x) const { return row(c, y)[x]; }
};

// Columns [first, first + count) of every row; throws if out of range.
Image crop_columns(const Image& image, int first, int count);

// Every value multiplied by `factor`.
Image scaled(const Image& image, double factor);

}  // namespace fss
