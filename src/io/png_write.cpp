#include "io/png_write.h"

#include <isa-l/crc.h>
#include <isa-l/igzip_lib.h>

#include <algorithm>
#include <array>
#include <memory>
#include <new>

#include "core/huge_pages.h"
#include "fss/core/error.h"

// The image PNGs are deflated by ISA-L at level 1 after the average filter
// (PNG type 3): the fastest of the compressors tried for files as small as
// zlib's (CONTRIBUTING.md, "Hand-written fast paths", has the comparison).
//
// Determinism: the bytes depend on the rows, on the fixed sizes below and
// on ISA-L's version, never on the thread. ISA-L picks its code at run time
// by the processor's instructions; its deflate finds the same matches on
// every x86-64 processor with SSE4.2, and other ones on a processor without
// it (a hash computed otherwise).

namespace fss::detail {
namespace {

constexpr std::array<std::uint8_t, 8> kSignature = {137, 80, 78, 71, 13, 10, 26, 10};
constexpr std::uint8_t kAverageFilter = 3;

// Rows go to the compressor in blocks of about this many bytes (at least one
// row): the block and its rows stay in the L2 cache between the filter and
// the compressor. The block size is part of what decides the bytes.
constexpr std::size_t kBlockBytes = std::size_t{256} << 10;

// The zlib stream is cut into IDAT chunks of this many bytes (the last one
// shorter): each chunk's CRC is computed while it is in the cache, and the
// 12 bytes of a chunk's frame add 0.005 %.
constexpr std::size_t kIdatBytes = std::size_t{256} << 10;

// Bytes of a chunk before its data: length, type.
constexpr std::size_t kChunkHead = 8;

void put_be32(std::uint8_t* out, std::uint32_t value) {
  out[0] = static_cast<std::uint8_t>(value >> 24);
  out[1] = static_cast<std::uint8_t>(value >> 16);
  out[2] = static_cast<std::uint8_t>(value >> 8);
  out[3] = static_cast<std::uint8_t>(value);
}

// Not inlined: GCC 12, seeing a constant size appended to an empty vector
// whose reserve it does not follow, warns of an overflow (-Wstringop-overflow).
[[gnu::noinline]] void append_bytes(std::vector<std::uint8_t>& out, const std::uint8_t* data,
                                    std::size_t size) {
  out.insert(out.end(), data, data + size);
}

void append_bytes(std::string& out, const std::uint8_t* data, std::size_t size) {
  out.append(reinterpret_cast<const char*>(data), size);
}

// Frames the chunk whose type and data are at chunk[4 ...] (room for its
// length before them) and appends it, with its CRC-32 (of type and data), to
// `out`. ISA-L's CRC-32 is zlib's (the same polynomial, reflected, and the
// same pre- and post-conditioning; tested), 8 times as fast here; it is
// never called on an empty range, where its result differs from zlib's.
template <class Bytes>
void append_chunk(Bytes& out, std::uint8_t* chunk, std::size_t data_size) {
  put_be32(chunk, static_cast<std::uint32_t>(data_size));
  const std::uint32_t crc = crc32_gzip_refl(0, chunk + 4, 4 + data_size);
  append_bytes(out, chunk, kChunkHead + data_size);
  std::array<std::uint8_t, 4> tail{};
  put_be32(tail.data(), crc);
  append_bytes(out, tail.data(), tail.size());
}

template <class Bytes>
void append_header(Bytes& out, const PngRaster& raster) {
  append_bytes(out, kSignature.data(), kSignature.size());
  std::array<std::uint8_t, kChunkHead + 13> ihdr = {0, 0, 0, 0, 'I', 'H', 'D', 'R'};
  put_be32(&ihdr[8], static_cast<std::uint32_t>(raster.width));
  put_be32(&ihdr[12], static_cast<std::uint32_t>(raster.height));
  ihdr[16] = static_cast<std::uint8_t>(raster.bit_depth);
  ihdr[17] = raster.channels == 3 ? 2 : 0;  // colour type: RGB or gray
  ihdr[18] = 0;                             // compression: deflate
  ihdr[19] = 0;                             // filter method: adaptive (types 0 to 4)
  ihdr[20] = 0;                             // no interlace
  append_chunk(out, ihdr.data(), 13);
}

template <class Bytes>
void append_end(Bytes& out) {
  std::array<std::uint8_t, kChunkHead> iend = {0, 0, 0, 0, 'I', 'E', 'N', 'D'};
  append_chunk(out, iend.data(), 0);
}

// The bytes of an encoder's buffers: ISA-L's level buffer and a chunk (kLevelBytes and
// kChunkBytes, in `buffers`), then a block of filtered rows and three rows.
constexpr std::size_t kLevelBytes = ISAL_DEF_LVL1_DEFAULT;
constexpr std::size_t kChunkBytes = kChunkHead + kIdatBytes;

// The zlib stream of the filtered rows (ISA-L, level 1), cut into IDAT
// chunks appended to `out` as they fill. Large (82 KB of stream state, and
// the 276 KB level buffer and a chunk in `buffers`, zeros): allocated once an image.
template <class Bytes>
class IdatWriter {
 public:
  IdatWriter(Bytes& out, std::uint8_t* buffers) : out_(out), chunk_(buffers + kLevelBytes) {
    isal_deflate_init(&stream_);
    stream_.level = 1;
    stream_.level_buf = buffers;
    stream_.level_buf_size = static_cast<std::uint32_t>(kLevelBytes);
    stream_.gzip_flag = IGZIP_ZLIB;
    stream_.flush = NO_FLUSH;
    std::copy_n("IDAT", 4, chunk_ + 4);
    start_chunk();
  }

  // Compresses `size` bytes; `last` ends the stream and its last chunk.
  void compress(const std::uint8_t* data, std::size_t size, bool last) {
    stream_.next_in = const_cast<std::uint8_t*>(data);  // ISA-L only reads it
    stream_.avail_in = static_cast<std::uint32_t>(size);
    stream_.end_of_stream = last ? 1 : 0;
    for (;;) {
      const std::uint32_t in_before = stream_.avail_in, out_before = stream_.avail_out;
      const int status = isal_deflate(&stream_);
      if (status != COMP_OK) fail("ISA-L's isal_deflate returned " + std::to_string(status));
      const bool ended = stream_.internal_state.state == ZSTATE_END;
      if (stream_.avail_in == 0 && (last ? ended : stream_.avail_out != 0)) break;
      const bool progress = stream_.avail_in != in_before || stream_.avail_out != out_before;
      if (!progress && stream_.avail_out == kIdatBytes) fail("ISA-L's isal_deflate is stuck");
      // A full chunk, or one whose room is too small for the compressor's
      // next step (the chunk sizes follow from the data alone).
      if (stream_.avail_out == 0 || !progress) next_chunk();
    }
    if (last && stream_.avail_out < kIdatBytes) next_chunk();
  }

 private:
  // Appends the chunk filled so far and starts the next one.
  void next_chunk() {
    append_chunk(out_, chunk_, kIdatBytes - stream_.avail_out);
    start_chunk();
  }

  void start_chunk() {
    stream_.next_out = chunk_ + kChunkHead;
    stream_.avail_out = static_cast<std::uint32_t>(kIdatBytes);
  }

  [[noreturn]] static void fail(const std::string& why) {
    throw_runtime_error("PNG encoding failed: " + why);
  }

  Bytes& out_;
  isal_zstream stream_{};
  std::uint8_t* chunk_;  // length, "IDAT", then up to kIdatBytes of stream
};

// The largest file: the rows stored as they are (ISA-L stores what it
// cannot compress, with a few bytes of block headers) with a margin,
// zlib's 6 bytes and the chunks' frames. Reserved at once, so the file is
// never copied while it grows; the pages not written are never touched, so
// they cost no memory.
std::size_t reserved_bytes(const PngRaster& raster) {
  const std::size_t stream = static_cast<std::size_t>(raster.height) * (raster.row_bytes() + 1);
  return stream + stream / 1024 + (stream / kIdatBytes + 1) * 12 + 1024;
}

}  // namespace

void average_filter(const std::uint8_t* __restrict current, const std::uint8_t* __restrict previous,
                    std::size_t row_bytes, std::size_t bytes_per_pixel,
                    std::uint8_t* __restrict out) {
  const std::size_t first = std::min(bytes_per_pixel, row_bytes);
  for (std::size_t i = 0; i < first; ++i) {
    out[i] = static_cast<std::uint8_t>(current[i] - (previous[i] >> 1));
  }
  // Vectorized by the compiler (no dependence between outputs).
  for (std::size_t i = first; i < row_bytes; ++i) {
    out[i] =
        static_cast<std::uint8_t>(current[i] - ((current[i - bytes_per_pixel] + previous[i]) >> 1));
  }
}

template <class Bytes>
Bytes write_png(const PngRaster& raster, const StoredRowSource& rows) {
  const std::size_t row_bytes = raster.row_bytes();
  const std::size_t pixel_bytes = row_bytes / static_cast<std::size_t>(raster.width);
  const int block_rows = static_cast<int>(std::clamp<std::size_t>(
      kBlockBytes / (row_bytes + 1), 1, static_cast<std::size_t>(raster.height)));
  try {
    Bytes out;
    reserve_on_huge_pages(out, reserved_bytes(raster));
    append_header(out, raster);
    // The encoder's buffers, a block of filtered rows, this row and the one above, and a row of
    // zeros, on huge pages of their own: their first touch is one page fault, not hundreds.
    const std::size_t block_bytes = static_cast<std::size_t>(block_rows) * (row_bytes + 1);
    const detail::HugePageBuffer buffers(kLevelBytes + kChunkBytes + block_bytes + 3 * row_bytes);
    auto idat = std::make_unique<IdatWriter<Bytes>>(out, buffers.data());
    std::uint8_t* const block = buffers.data() + kLevelBytes + kChunkBytes;
    std::uint8_t* const scratch = block + block_bytes;
    const std::uint8_t* above = scratch + 2 * row_bytes;  // zeros
    for (int first = 0; first < raster.height; first += block_rows) {
      const int count = std::min(block_rows, raster.height - first);
      for (int i = 0; i < count; ++i) {
        const int y = first + i;
        const std::uint8_t* row = rows(y, scratch + static_cast<std::size_t>(y % 2) * row_bytes);
        std::uint8_t* filtered = block + static_cast<std::size_t>(i) * (row_bytes + 1);
        filtered[0] = kAverageFilter;
        average_filter(row, above, row_bytes, pixel_bytes, filtered + 1);
        above = row;
      }
      idat->compress(block, static_cast<std::size_t>(count) * (row_bytes + 1),
                     first + count == raster.height);
    }
    append_end(out);
    return out;
  } catch (const std::bad_alloc&) {
    throw_runtime_error("PNG encoding of a " + std::to_string(raster.width) + " x " +
                        std::to_string(raster.height) + " x " + std::to_string(raster.channels) +
                        " image failed: out of memory");
  }
}

template std::vector<std::uint8_t> write_png(const PngRaster&, const StoredRowSource&);
template std::string write_png(const PngRaster&, const StoredRowSource&);

}  // namespace fss::detail
