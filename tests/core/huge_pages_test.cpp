// Tests of the buffers mapped on their own (core/huge_pages.h) and of the image samples'
// allocator (fss/core/image.h): alignment, zeros, every byte writable, the advice to the
// kernel where Linux shows it, and images that behave as before.
#include "core/huge_pages.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "fss/core/image.h"
#include "support/test_util.h"

namespace fss {
namespace {

constexpr std::size_t kMiB = std::size_t{1} << 20;

bool all_zero(const unsigned char* data, std::size_t bytes) {
  return std::all_of(data, data + bytes, [](unsigned char b) { return b == 0; });
}

// The VmFlags line of the mapping holding `address` in /proc/self/smaps ("" when not found).
std::string vm_flags_of(const void* address) {
  std::ifstream smaps("/proc/self/smaps");
  const auto where = reinterpret_cast<std::uintptr_t>(address);
  bool inside = false;
  for (std::string line; std::getline(smaps, line);) {
    std::uintptr_t low = 0;
    std::uintptr_t high = 0;
    char dash = 0;
    std::istringstream range(line);
    if (range >> std::hex >> low >> dash >> high && dash == '-') {
      inside = low <= where && where < high;
    } else if (inside && line.rfind("VmFlags:", 0) == 0) {
      return line;
    }
  }
  return "";
}

TEST(HugePages, MappedBuffersAreAlignedZerosAndWritable) {
  for (const std::size_t bytes : {std::size_t{0}, std::size_t{1}, std::size_t{4096}, kMiB + 1,
                                  2 * kMiB - 1, 2 * kMiB, 2 * kMiB + 1, 5 * kMiB + 12345}) {
    SCOPED_TRACE(bytes);
    auto* data = static_cast<unsigned char*>(detail::map_on_huge_pages(bytes));
    ASSERT_NE(data, nullptr);
    EXPECT_EQ(reinterpret_cast<std::uintptr_t>(data) % detail::kHugePageBytes, 0U);
    EXPECT_TRUE(all_zero(data, bytes));
    std::fill(data, data + bytes, static_cast<unsigned char>(0xA5));
    EXPECT_EQ(std::count(data, data + bytes, static_cast<unsigned char>(0xA5)),
              static_cast<std::ptrdiff_t>(bytes));
    detail::unmap_huge_pages(data, bytes);
  }
}

#ifdef __linux__
TEST(HugePages, MappingIsAdvisedForHugePages) {
  // MADV_HUGEPAGE shows as "hg" in the mapping's VmFlags whatever the system's THP setting.
  if (test::kAddressSanitizer) GTEST_SKIP() << "heap buffers under AddressSanitizer";
  auto* data = static_cast<unsigned char*>(detail::map_on_huge_pages(3 * kMiB));
  const std::string flags = vm_flags_of(data);
  ASSERT_FALSE(flags.empty()) << "no mapping holds the buffer in /proc/self/smaps";
  EXPECT_NE(flags.find(" hg"), std::string::npos) << flags;
  detail::unmap_huge_pages(data, 3 * kMiB);
  EXPECT_TRUE(vm_flags_of(data).find(" hg") == std::string::npos);  // unmapped: gone
}
#endif

TEST(HugePages, HugePageBufferIsZeros) {
  const detail::HugePageBuffer buffer(700 * 1024);
  EXPECT_TRUE(all_zero(buffer.data(), 700 * 1024));
  buffer.data()[700 * 1024 - 1] = 1;
  EXPECT_EQ(buffer.data()[700 * 1024 - 1], 1);
}

TEST(HugePages, ZeroedArrayIsZerosAndWritable) {
  const detail::ZeroedArray<std::uint64_t> counts(65536);
  EXPECT_TRUE(all_zero(reinterpret_cast<const unsigned char*>(counts.data()),
                       65536 * sizeof(std::uint64_t)));
  counts[0] += 3;
  counts[65535] += 4;
  EXPECT_EQ(counts[0] + counts[65535], 7U);
}

TEST(SampleAllocator, ImagesOfEverySizeHoldTheirValues) {
  // Below, at and above the 1 MiB threshold (131072 doubles), and growing across it.
  for (const int width : {1, 128, 256, 512, 700}) {
    SCOPED_TRACE(width);
    Image image(width, 512, 1, 7.5);
    ASSERT_EQ(image.data.size(), static_cast<std::size_t>(width) * 512);
    EXPECT_TRUE(
        std::all_of(image.data.begin(), image.data.end(), [](double v) { return v == 7.5; }));
    image.at(0, 511, width - 1) = -1.0;
    const Image copy = image;
    EXPECT_EQ(copy.data, image.data);
    Image moved = std::move(image);
    EXPECT_EQ(moved.at(0, 511, width - 1), -1.0);
  }
  Samples grown;
  for (int i = 0; i < 400000; ++i) grown.push_back(i);
  EXPECT_EQ(grown[399999], 399999.0);
  EXPECT_EQ(grown[131071], 131071.0);
}

}  // namespace
}  // namespace fss
