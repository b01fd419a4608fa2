#include "fss/io/png_io.h"

#include <png.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <csetjmp>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <memory>
#include <new>
#include <utility>

#include "core/enum_names.h"
#include "core/huge_pages.h"
#include "fss/core/error.h"
#include "io/input_bytes.h"
#include "io/png_samples.h"
#include "io/png_write.h"

namespace fss {
namespace {

constexpr detail::EnumNames<PngDepth, 2> kPngDepthNames{
    {{PngDepth::k8, "8"}, {PngDepth::k16, "16"}}};

// libpng reports errors by longjmp. The functions that call setjmp below hold
// no object with a destructor, and everything they touch after setjmp lives
// in this heap-allocated context, so the jump skips no destructor and leaves
// no indeterminate local.
struct PngContext {
  png_structp png = nullptr;
  png_infop info = nullptr;
  char message[256] = {0};
  const std::uint8_t* bytes = nullptr;  // reading: the source
  std::size_t size = 0;
  std::size_t offset = 0;
  std::vector<std::uint8_t>* sink = nullptr;  // writing: the destination
};

void on_error(png_structp png, png_const_charp message) {
  auto* ctx = static_cast<PngContext*>(png_get_error_ptr(png));
  std::snprintf(ctx->message, sizeof ctx->message, "%s", message ? message : "unknown error");
  png_longjmp(png, 1);
}

void on_warning(png_structp, png_const_charp) {
  // Warnings (such as "known incorrect sRGB profile") do not affect pixels.
}

void read_from_memory(png_structp png, png_bytep out, png_size_t length) {
  auto* ctx = static_cast<PngContext*>(png_get_io_ptr(png));
  if (length > ctx->size - ctx->offset) {
    png_error(png, "file is truncated");
  }
  std::memcpy(out, ctx->bytes + ctx->offset, length);
  ctx->offset += length;
}

// libpng allocates an ancillary chunk's declared length before reading it,
// whatever its own chunk limit says: a 174-byte file declaring a 1.9 GB sCAL
// chunk had 1.9 GB allocated. Its largest real needs are a few rows (at most
// 65536 pixels of 8 bytes each) and the chunks that matter for pixels (PLTE,
// tRNS: bytes), so larger requests are refused. libpng then skips an
// ancillary chunk (a warning) or fails with an error on anything else.
constexpr png_alloc_size_t kMaxLibpngAllocation = png_alloc_size_t{16} << 20;

png_voidp limited_malloc(png_structp, png_alloc_size_t size) {
  return size <= kMaxLibpngAllocation ? std::malloc(size) : nullptr;
}

void plain_free(png_structp, png_voidp pointer) { std::free(pointer); }

// No C++ exception may cross libpng's C frames: an allocation failure becomes
// a libpng error, raised once the exception is over (no longjmp out of a
// catch block).
void write_to_memory(png_structp png, png_bytep data, png_size_t length) {
  auto* ctx = static_cast<PngContext*>(png_get_io_ptr(png));
  bool out_of_memory = false;
  try {
    ctx->sink->insert(ctx->sink->end(), data, data + length);
  } catch (const std::bad_alloc&) {
    out_of_memory = true;
  }
  if (out_of_memory) png_error(png, "out of memory");
}

void flush_nothing(png_structp) {}

struct PngHeader {
  png_uint_32 width = 0;
  png_uint_32 height = 0;
  int stored_bits_per_pixel = 0;  // as stored in the file
  int channels = 0;               // after transformations
  int bit_depth = 0;              // 8 or 16 after transformations
  std::size_t rowbytes = 0;
};

// Reads the header and sets the transformations: palette -> RGB, low bit
// depths -> 8, alpha stripped. 16-bit samples stay big-endian, as stored.
bool read_header(PngContext* ctx, PngHeader* header) {
  if (setjmp(png_jmpbuf(ctx->png))) return false;
  png_set_user_limits(ctx->png, kMaxImageSide, kMaxImageSide);
#ifdef FUZZING_BUILD_MODE_UNSAFE_FOR_PRODUCTION
  // Let the fuzzer change chunk data without having to fix the checksums.
  png_set_crc_action(ctx->png, PNG_CRC_QUIET_USE, PNG_CRC_QUIET_USE);
#endif
  png_set_read_fn(ctx->png, ctx, read_from_memory);
  png_read_info(ctx->png, ctx->info);
  const int color_type = png_get_color_type(ctx->png, ctx->info);
  const int bit_depth = png_get_bit_depth(ctx->png, ctx->info);
  header->stored_bits_per_pixel = bit_depth * png_get_channels(ctx->png, ctx->info);
  if (color_type == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(ctx->png);
  if (color_type == PNG_COLOR_TYPE_GRAY && bit_depth < 8) png_set_expand_gray_1_2_4_to_8(ctx->png);
  if (color_type & PNG_COLOR_MASK_ALPHA) png_set_strip_alpha(ctx->png);
  png_set_interlace_handling(ctx->png);
  png_read_update_info(ctx->png, ctx->info);
  header->width = png_get_image_width(ctx->png, ctx->info);
  header->height = png_get_image_height(ctx->png, ctx->info);
  header->channels = png_get_channels(ctx->png, ctx->info);
  header->bit_depth = png_get_bit_depth(ctx->png, ctx->info);
  header->rowbytes = png_get_rowbytes(ctx->png, ctx->info);
  return true;
}

bool read_rows(PngContext* ctx, png_bytepp rows) {
  if (setjmp(png_jmpbuf(ctx->png))) return false;
  png_read_image(ctx->png, rows);
  png_read_end(ctx->png, nullptr);
  return true;
}

bool write_image(PngContext* ctx, png_uint_32 width, png_uint_32 height, int bit_depth,
                 int color_type, png_bytepp rows) {
  if (setjmp(png_jmpbuf(ctx->png))) return false;
  png_set_write_fn(ctx->png, ctx, write_to_memory, flush_nothing);

  // The "up" filter alone, and zlib's level 3 for the plots (CONTRIBUTING.md,
  // "Hand-written fast paths").
  png_set_filter(ctx->png, 0, PNG_FILTER_UP);
  png_set_compression_level(ctx->png, 3);
  png_set_IHDR(ctx->png, ctx->info, width, height, bit_depth, color_type, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(ctx->png, ctx->info);
  png_write_image(ctx->png, rows);
  png_write_end(ctx->png, nullptr);
  return true;
}

struct ReadStructs {
  PngContext ctx;
  ~ReadStructs() {
    if (ctx.png) png_destroy_read_struct(&ctx.png, ctx.info ? &ctx.info : nullptr, nullptr);
  }
};

struct WriteStructs {
  PngContext ctx;
  ~WriteStructs() {
    if (ctx.png) png_destroy_write_struct(&ctx.png, ctx.info ? &ctx.info : nullptr);
  }
};

// Deflate turns one compressed byte into at most 1032 bytes (a 258-byte match
// coded in two 1-bit Huffman codes): a file of `size` bytes cannot hold more.
constexpr std::uint64_t kMaxDeflateRatio = 1032;

std::string dimensions(const PngHeader& header) {
  return std::to_string(header.width) + "x" + std::to_string(header.height);
}

// Refuses, before anything is allocated for them, a header declaring more
// pixels than the file of `size` bytes can hold, and an image whose decoding
// would need more than `max_bytes` (when > 0), the file's bytes included.
void check_decodable(const PngHeader& header, std::size_t size, const std::string& name,
                     std::size_t max_bytes) {
  const std::uint64_t stored_bytes = static_cast<std::uint64_t>(header.width) * header.height *
                                     static_cast<std::uint64_t>(header.stored_bits_per_pixel) / 8;
  if (stored_bytes > kMaxDeflateRatio * (static_cast<std::uint64_t>(size) + 1)) {
    throw_runtime_error("PNG '" + name + "' declares " + dimensions(header) +
                        " pixels, more than its " + std::to_string(size) +
                        " bytes can hold: it is truncated or its header is corrupt");
  }
  const int out_channels = header.channels >= 3 ? 3 : 1;
  const std::size_t needed =
      png_decode_bytes(header.width, header.height, out_channels, header.rowbytes) + size;
  detail::check_decoding_memory(name, header.width, header.height, needed, max_bytes);
}

// The decoded rows (1 to 4 channels after the transformations, 8 or 16
// bits) as an image of `out_channels` channels on the 0..255 scale.
Image to_image(const PngHeader& header, int out_channels, const std::vector<png_bytep>& rows) {
  const int in_channels = header.channels;
  Image image(static_cast<int>(header.width), static_cast<int>(header.height), out_channels);
  for (png_uint_32 y = 0; y < header.height; ++y) {
    const std::uint8_t* row = rows[y];
    for (png_uint_32 x = 0; x < header.width; ++x) {
      for (int c = 0; c < out_channels; ++c) {
        const std::size_t sample = static_cast<std::size_t>(x) * in_channels + c;
        double value;
        if (header.bit_depth == 16) {  // big-endian, whatever the host
          value = ((row[2 * sample] << 8) | row[2 * sample + 1]) / 257.0;
        } else {
          value = row[sample];
        }
        image.at(c, static_cast<int>(y), static_cast<int>(x)) = value;
      }
    }
  }
  return image;
}

}  // namespace

std::size_t png_decode_bytes(std::size_t width, std::size_t height, int channels,
                             std::size_t row_bytes) {
  // the decoded rows, then the planar doubles
  return row_bytes * height + width * height * static_cast<std::size_t>(channels) * sizeof(double);
}

Image decode_png(const std::uint8_t* bytes, std::size_t size, const std::string& name,
                 std::size_t max_bytes) {
  if (size < 8 || png_sig_cmp(bytes, 0, 8) != 0) {
    throw_runtime_error("input '" + name + "' is not a PNG file (bad signature)");
  }
  auto structs = std::make_unique<ReadStructs>();
  PngContext* ctx = &structs->ctx;
  ctx->bytes = bytes;
  ctx->size = size;
  ctx->png = png_create_read_struct_2(PNG_LIBPNG_VER_STRING, ctx, on_error, on_warning, nullptr,
                                      limited_malloc, plain_free);
  if (!ctx->png) throw_runtime_error("cannot read '" + name + "': out of memory");
  ctx->info = png_create_info_struct(ctx->png);
  if (!ctx->info) throw_runtime_error("cannot read '" + name + "': out of memory");

  PngHeader header;
  if (!read_header(ctx, &header)) {
    throw_runtime_error("cannot read PNG '" + name + "': " + ctx->message);
  }
  if (header.width == 0 || header.height == 0) {
    throw_runtime_error("PNG '" + name + "' has no pixels");
  }
  check_decodable(header, size, name, max_bytes);
  const int out_channels = header.channels >= 3 ? 3 : 1;
  try {
    // Not zero-filled: only the rows libpng actually decodes are touched, on huge pages when
    // large (detail::allocate_buffer).
    const detail::BufferArray<std::uint8_t> pixels(std::size_t{header.rowbytes} * header.height);
    std::vector<png_bytep> rows(header.height);
    for (png_uint_32 y = 0; y < header.height; ++y) rows[y] = pixels.data() + y * header.rowbytes;
    if (!read_rows(ctx, rows.data())) {
      throw_runtime_error("cannot read PNG '" + name + "': " + ctx->message);
    }
    return to_image(header, out_channels, rows);
  } catch (const std::bad_alloc&) {
    throw_runtime_error("cannot read PNG '" + name + "': not enough memory for its " +
                        dimensions(header) + " pixels");
  }
}

std::optional<PngHeaderSize> read_png_header_size(const std::filesystem::path& path) {
  // A pipe or a terminal is read once, by the decoder: never peeked at here.
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return std::nullopt;
  std::ifstream file(path, std::ios::binary);
  std::uint8_t head[33] = {};
  if (!file.read(reinterpret_cast<char*>(head), sizeof head)) return std::nullopt;
  if (png_sig_cmp(head, 0, 8) != 0 || std::memcmp(head + 12, "IHDR", 4) != 0) return std::nullopt;
  const auto be32 = [&](int at) {
    return (std::uint32_t{head[at]} << 24) | (std::uint32_t{head[at + 1]} << 16) |
           (std::uint32_t{head[at + 2]} << 8) | std::uint32_t{head[at + 3]};
  };
  const std::uint32_t width = be32(16);
  const std::uint32_t height = be32(20);
  if (width == 0 || height == 0 || width > 0x7fffffffU || height > 0x7fffffffU) return std::nullopt;
  const int bit_depth = head[24];
  const int colour_type = head[25];
  const bool colour = colour_type == PNG_COLOR_TYPE_RGB || colour_type == PNG_COLOR_TYPE_RGBA ||
                      colour_type == PNG_COLOR_TYPE_PALETTE;  // a palette is decoded as RGB
  return PngHeaderSize{static_cast<int>(width), static_cast<int>(height), colour ? 3 : 1,
                       bit_depth};
}

Image read_png(const std::filesystem::path& path, std::size_t max_bytes) {
  const std::vector<std::uint8_t> bytes = detail::read_input_bytes(
      path, "a PNG file",
      [](const std::uint8_t* head, std::size_t size) {
        return size == 8 && png_sig_cmp(head, 0, 8) == 0;
      },
      max_bytes);
  return decode_png(bytes.data(), bytes.size(), path.string(), max_bytes);
}

namespace {

using FillRow = std::function<void(int c, int y, double* row)>;

// The values of channel c, row y: either written into `buffer` (room for a
// row), which is then returned, or a pointer to them where they are.
using ValueRowSource = std::function<const double*(int c, int y, double* buffer)>;

void check_encodable(int width, int height, int channels) {
  if (channels != 1 && channels != 3) {
    throw_usage_error("PNG encoding needs 1 or 3 channels, got " + std::to_string(channels));
  }
  if (width <= 0 || height <= 0) {
    throw_usage_error("PNG encoding needs a non-empty image, got " + std::to_string(width) + "x" +
                      std::to_string(height));
  }
}

// The rows of the values as the PNG of `raster` stores them, one at a time.
class StoredValueRows {
 public:
  StoredValueRows(const detail::PngRaster& raster, ValueRowSource values)
      : raster_(raster),
        values_(std::move(values)),
        buffer_(static_cast<std::size_t>(raster.width) * raster.channels),
        scratch_(static_cast<std::size_t>(raster.width) * raster.channels) {}

  const std::uint8_t* operator()(int y, std::uint8_t* row) {
    std::array<const double*, 3> channels{};
    for (int c = 0; c < raster_.channels; ++c) {
      channels[c] = values_(c, y, buffer_.data() + static_cast<std::size_t>(c) * raster_.width);
    }
    detail::store_sample_row(channels.data(), raster_.channels, raster_.width, raster_.bit_depth,
                             scratch_.data(), row);
    return row;
  }

 private:
  detail::PngRaster raster_;
  ValueRowSource values_;
  std::vector<double> buffer_;          // the values of each channel, when copied
  std::vector<std::uint16_t> scratch_;  // the samples of each channel
};

// PngCompression::kGraphics: the whole raster, then libpng and zlib. Rows
// held elsewhere (the samples of a plot) are not copied.
std::vector<std::uint8_t> encode_with_libpng(const detail::PngRaster& raster,
                                             const detail::StoredRowSource& rows) {
  const std::size_t row_bytes = raster.row_bytes();
  std::vector<std::uint8_t> scratch(row_bytes);
  std::vector<std::uint8_t> pixels;  // the rows written into scratch
  std::vector<png_bytep> row_pointers(static_cast<std::size_t>(raster.height));
  for (int y = 0; y < raster.height; ++y) {
    const std::uint8_t* row = rows(y, scratch.data());
    if (row == scratch.data()) {
      if (pixels.empty()) pixels.resize(row_bytes * static_cast<std::size_t>(raster.height));
      row = static_cast<const std::uint8_t*>(
          std::memcpy(pixels.data() + static_cast<std::size_t>(y) * row_bytes, row, row_bytes));
    }
    // libpng's row pointers are not const, but writing only reads them.
    row_pointers[y] = const_cast<png_bytep>(row);
  }
  std::vector<std::uint8_t> out;
  auto structs = std::make_unique<WriteStructs>();
  PngContext* ctx = &structs->ctx;
  ctx->sink = &out;
  ctx->png = png_create_write_struct(PNG_LIBPNG_VER_STRING, ctx, on_error, on_warning);
  if (!ctx->png) throw_runtime_error("PNG encoding: out of memory");
  ctx->info = png_create_info_struct(ctx->png);
  if (!ctx->info) throw_runtime_error("PNG encoding: out of memory");
  const int color_type = raster.channels == 1 ? PNG_COLOR_TYPE_GRAY : PNG_COLOR_TYPE_RGB;
  if (!write_image(ctx, static_cast<png_uint_32>(raster.width),
                   static_cast<png_uint_32>(raster.height), raster.bit_depth, color_type,
                   row_pointers.data())) {
    throw_runtime_error(std::string("PNG encoding failed: ") + ctx->message);
  }
  return out;
}

// kImage: the average filter and ISA-L's deflate at level 1, streamed over blocks of rows
// (png_write.cpp): faster than zlib on large images and as small (CONTRIBUTING.md, "Hand-written
// fast paths"). kGraphics: libpng, the "up" filter and zlib level 3, whose long matches suit the
// repeated runs of flat colour and text in plots better than run-length matching.
std::vector<std::uint8_t> encode_rows(const detail::PngRaster& raster,
                                      const detail::StoredRowSource& rows,
                                      PngCompression compression) {
  if (compression == PngCompression::kGraphics) return encode_with_libpng(raster, rows);
  return detail::write_png<std::vector<std::uint8_t>>(raster, rows);
}

detail::PngRaster raster_of(int width, int height, int channels, PngDepth depth) {
  check_encodable(width, height, channels);
  return {width, height, channels, depth == PngDepth::k16 ? 16 : 8};
}

ValueRowSource filled_rows(const FillRow& fill_row) {
  return [&fill_row](int c, int y, double* buffer) -> const double* {
    fill_row(c, y, buffer);
    return buffer;
  };
}

ValueRowSource image_rows(const Image& image) {
  return [&image](int c, int y, double*) { return image.row(c, y); };
}

// The rows of samples already interleaved as the PNG stores them, after
// checking their count.
detail::StoredRowSource sample_rows(const detail::PngRaster& raster,
                                    std::span<const std::uint8_t> samples) {
  const std::size_t row_bytes = raster.row_bytes();
  if (samples.size() != row_bytes * static_cast<std::size_t>(raster.height)) {
    throw_usage_error("PNG encoding of a " + std::to_string(raster.width) + "x" +
                      std::to_string(raster.height) + "x" + std::to_string(raster.channels) +
                      " image needs " +
                      std::to_string(row_bytes * static_cast<std::size_t>(raster.height)) +
                      " samples, got " + std::to_string(samples.size()));
  }
  return [samples, row_bytes](int y, std::uint8_t*) {
    return samples.data() + static_cast<std::size_t>(y) * row_bytes;
  };
}

}  // namespace

std::string to_string(PngDepth depth) { return detail::enum_name(kPngDepthNames, depth); }

std::optional<PngDepth> png_depth_from_string(std::string_view text) {
  return detail::enum_from_name(kPngDepthNames, text);
}

std::vector<std::uint8_t> encode_png8(const Image& image, PngCompression compression) {
  return encode_png(image, PngDepth::k8, compression);
}

std::vector<std::uint8_t> encode_png8(int width, int height, int channels, const FillRow& fill_row,
                                      PngCompression compression) {
  return encode_png(width, height, channels, fill_row, PngDepth::k8, compression);
}

std::vector<std::uint8_t> encode_png(int width, int height, int channels, const FillRow& fill_row,
                                     PngDepth depth, PngCompression compression) {
  const detail::PngRaster raster = raster_of(width, height, channels, depth);
  return encode_rows(raster, StoredValueRows(raster, filled_rows(fill_row)), compression);
}

std::vector<std::uint8_t> encode_png(const Image& image, PngDepth depth,
                                     PngCompression compression) {
  const detail::PngRaster raster = raster_of(image.width, image.height, image.channels, depth);
  return encode_rows(raster, StoredValueRows(raster, image_rows(image)), compression);
}

std::vector<std::uint8_t> encode_png8_samples(int width, int height, int channels,
                                              std::span<const std::uint8_t> samples,
                                              PngCompression compression) {
  const detail::PngRaster raster = raster_of(width, height, channels, PngDepth::k8);
  return encode_rows(raster, sample_rows(raster, samples), compression);
}

namespace detail {

std::string encode_png_string(int width, int height, int channels, const FillRow& fill_row,
                              PngDepth depth) {
  const PngRaster raster = raster_of(width, height, channels, depth);
  return write_png<std::string>(raster, StoredValueRows(raster, filled_rows(fill_row)));
}

std::string encode_png_string(const Image& image, PngDepth depth) {
  const PngRaster raster = raster_of(image.width, image.height, image.channels, depth);
  return write_png<std::string>(raster, StoredValueRows(raster, image_rows(image)));
}

std::string encode_png8_samples_string(int width, int height, int channels,
                                       std::span<const std::uint8_t> samples) {
  const PngRaster raster = raster_of(width, height, channels, PngDepth::k8);
  return write_png<std::string>(raster, sample_rows(raster, samples));
}

}  // namespace detail

}  // namespace fss
