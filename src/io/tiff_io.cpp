#include "fss/io/tiff_io.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <memory>
#include <mutex>
#include <new>

#include "fss/core/error.h"
#include "fss/io/png_io.h"
#include "io/input_bytes.h"
#include "io/tiff_api.h"  // libtiff, loaded at the first use

namespace fss {
namespace {

// ---------------------------------------------------------------------------
// libtiff's messages and I/O, in memory.

// The first error libtiff reported on a handle; its warnings are dropped.
struct TiffMessages {
  char error[256] = {0};
};

int on_tiff_error(TIFF*, void* user_data, const char* module, const char* format, va_list args) {
  auto* messages = static_cast<TiffMessages*>(user_data);
  if (messages != nullptr && messages->error[0] == '\0') {
    char text[200];
    std::vsnprintf(text, sizeof text, format, args);
    std::snprintf(messages->error, sizeof messages->error, "%s%s%s", module ? module : "",
                  module ? ": " : "", text);
  }
  return 1;  // handled: libtiff's global handlers are not called
}

int on_tiff_warning(TIFF*, void*, const char*, const char*, va_list) { return 1; }

// Messages libtiff sends without a handle go to its global handlers: none.
void silence_global_handlers() {
  static std::once_flag once;
  std::call_once(once, [] {
    TIFFSetErrorHandler(nullptr);
    TIFFSetWarningHandler(nullptr);
    TIFFSetErrorHandlerExt(nullptr);
    TIFFSetWarningHandlerExt(nullptr);
  });
}

// Loads libtiff (tiff_api.h) before any other use; a missing library fails `task` ("cannot
// read TIFF 'a.tif'") in one line.
void require_libtiff(const std::string& task) {
  try {
    tiff_api();
  } catch (const Error& e) {
    throw_runtime_error(task + ": " + e.what());
  }
}

// A file in memory: read from `bytes`, or written to `sink`.
struct MemoryFile {
  const std::uint8_t* bytes = nullptr;
  std::size_t size = 0;
  std::vector<std::uint8_t>* sink = nullptr;
  std::size_t position = 0;
};

tmsize_t memory_read(thandle_t handle, void* out, tmsize_t length) {
  auto* file = static_cast<MemoryFile*>(handle);
  const std::size_t end = file->sink ? file->sink->size() : file->size;
  const std::uint8_t* data = file->sink ? file->sink->data() : file->bytes;
  if (length < 0 || file->position >= end) return 0;
  const std::size_t count = std::min(static_cast<std::size_t>(length), end - file->position);
  std::memcpy(out, data + file->position, count);
  file->position += count;
  return static_cast<tmsize_t>(count);
}

// No C++ exception may cross libtiff's C frames: a failed allocation is a
// failed write, which libtiff reports.
tmsize_t memory_write(thandle_t handle, void* data, tmsize_t length) {
  auto* file = static_cast<MemoryFile*>(handle);
  if (file->sink == nullptr || length < 0) return -1;
  const auto count = static_cast<std::size_t>(length);
  try {
    if (file->sink->size() < file->position + count) file->sink->resize(file->position + count);
  } catch (const std::bad_alloc&) {
    return -1;
  }
  std::memcpy(file->sink->data() + file->position, data, count);
  file->position += count;
  return length;
}

toff_t memory_seek(thandle_t handle, toff_t offset, int whence) {
  auto* file = static_cast<MemoryFile*>(handle);
  const std::size_t end = file->sink ? file->sink->size() : file->size;
  std::uint64_t base = 0;
  if (whence == SEEK_CUR) base = file->position;
  if (whence == SEEK_END) base = end;
  const std::uint64_t target = base + offset;
  if (target < base || target > (std::uint64_t{1} << 48)) return static_cast<toff_t>(-1);
  file->position = static_cast<std::size_t>(target);
  return target;
}

int memory_close(thandle_t) { return 0; }

toff_t memory_size(thandle_t handle) {
  auto* file = static_cast<MemoryFile*>(handle);
  return file->sink ? file->sink->size() : file->size;
}

// Reading maps the bytes: libtiff then decodes from them without a copy.
int memory_map(thandle_t handle, void** base, toff_t* size) {
  auto* file = static_cast<MemoryFile*>(handle);
  if (file->sink != nullptr) return 0;
  *base = const_cast<std::uint8_t*>(file->bytes);
  *size = file->size;
  return 1;
}

void memory_unmap(thandle_t, void*, toff_t) {}

// Largest single allocation libtiff may make (its own tables and buffers; the
// decoded samples are fss's).
constexpr tmsize_t kMaxLibtiffAllocation = tmsize_t{512} << 20;

struct TiffCloser {
  void operator()(TIFF* tiff) const { TIFFClose(tiff); }
};
using TiffHandle = std::unique_ptr<TIFF, TiffCloser>;

// Opens `file` in `mode` ("r", or "wl": written little-endian) with messages
// going to `messages`; null on failure (messages->error says why).
TiffHandle open_memory_tiff(const std::string& name, const char* mode, MemoryFile* file,
                            TiffMessages* messages) {
  silence_global_handlers();
  TIFFOpenOptions* options = TIFFOpenOptionsAlloc();
  if (options == nullptr) return nullptr;
  TIFFOpenOptionsSetErrorHandlerExtR(options, on_tiff_error, messages);
  TIFFOpenOptionsSetWarningHandlerExtR(options, on_tiff_warning, messages);
  TIFFOpenOptionsSetMaxSingleMemAlloc(options, kMaxLibtiffAllocation);
  TIFF* tiff = TIFFClientOpenExt(name.c_str(), mode, file, memory_read, memory_write, memory_seek,
                                 memory_close, memory_size, memory_map, memory_unmap, options);
  TIFFOpenOptionsFree(options);
  return TiffHandle(tiff);
}

// ---------------------------------------------------------------------------
// Reading.

enum class SampleKind { kUint8, kUint16, kFloat32 };

struct TiffLayout {
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  std::uint16_t samples_per_pixel = 1;
  std::uint16_t bits = 1;
  SampleKind kind = SampleKind::kUint8;
  int channels = 0;       // 1 (gray) or 3 (RGB) read, the rest ignored
  bool separate = false;  // one plane a sample
  bool tiled = false;
  std::uint32_t tile_width = 0;  // tiles only
  std::uint32_t tile_height = 0;
  std::uint16_t compression = COMPRESSION_NONE;
  std::size_t chunk_bytes = 0;      // a scanline or a tile, as libtiff decodes it
  std::uint64_t decoded_bytes = 0;  // every strip or tile, as libtiff decodes them
};

std::string quoted(const std::string& name) { return "TIFF '" + name + "'"; }

std::uint16_t field16(TIFF* tiff, ttag_t tag) {
  std::uint16_t value = 0;
  TIFFGetFieldDefaulted(tiff, tag, &value);
  return value;
}

// The sample kind, or an error naming what the file has.
SampleKind sample_kind(TIFF* tiff, std::uint16_t bits, const std::string& name) {
  const std::uint16_t format = field16(tiff, TIFFTAG_SAMPLEFORMAT);
  if (format == SAMPLEFORMAT_UINT && bits == 8) return SampleKind::kUint8;
  if (format == SAMPLEFORMAT_UINT && bits == 16) return SampleKind::kUint16;
  if (format == SAMPLEFORMAT_IEEEFP && bits == 32) return SampleKind::kFloat32;
  const char* format_name = format == SAMPLEFORMAT_UINT     ? "unsigned integer"
                            : format == SAMPLEFORMAT_INT    ? "signed integer"
                            : format == SAMPLEFORMAT_IEEEFP ? "float"
                                                            : "untyped or complex";
  throw_runtime_error(quoted(name) + " has " + std::to_string(bits) + "-bit " + format_name +
                      " samples; fssim reads 8- and 16-bit unsigned integer and 32-bit float "
                      "samples");
}

// 1 for min-is-black, 3 for RGB; an error naming anything else.
int photometric_channels(TIFF* tiff, std::uint16_t samples_per_pixel, const std::string& name) {
  std::uint16_t photometric = 0;
  if (!TIFFGetField(tiff, TIFFTAG_PHOTOMETRIC, &photometric)) {
    throw_runtime_error(quoted(name) + " has no photometric interpretation tag");
  }
  int channels = 0;
  if (photometric == PHOTOMETRIC_MINISBLACK) channels = 1;
  if (photometric == PHOTOMETRIC_RGB) channels = 3;
  if (channels == 0) {
    const char* kind = photometric == PHOTOMETRIC_PALETTE      ? "palette"
                       : photometric == PHOTOMETRIC_MINISWHITE ? "min-is-white"
                       : photometric == PHOTOMETRIC_YCBCR      ? "YCbCr"
                       : photometric == PHOTOMETRIC_SEPARATED  ? "CMYK (separated)"
                                                               : "unsupported";
    throw_runtime_error(quoted(name) + " has " + kind + " colour (photometric interpretation " +
                        std::to_string(photometric) +
                        "); fssim reads gray (min-is-black) and RGB TIFFs");
  }
  if (samples_per_pixel < channels) {
    throw_runtime_error(quoted(name) + " has " + std::to_string(samples_per_pixel) +
                        " samples a pixel, fewer than its colour needs (" +
                        std::to_string(channels) + ")");
  }
  return channels;
}

// Decoded bytes per compressed byte at most, for the compressions read.
// Deflate: 1032 (a 258-byte match in two 1-bit codes); LZW: a 9-bit code
// stands for at most 4096 bytes; PackBits: 2 bytes give 128. 0: refused.
std::uint64_t max_compression_ratio(std::uint16_t compression) {
  switch (compression) {
    case COMPRESSION_NONE:
      return 1;
    case COMPRESSION_PACKBITS:
      return 64;
    case COMPRESSION_LZW:
      return 4096 * 8 / 9;
    case COMPRESSION_ADOBE_DEFLATE:
    case COMPRESSION_DEFLATE:
      return 1032;
    default:
      return 0;
  }
}

void check_compression(std::uint16_t compression, const std::string& name) {
  if (max_compression_ratio(compression) == 0 || !TIFFIsCODECConfigured(compression)) {
    const TIFFCodec* codec = TIFFFindCODEC(compression);
    throw_runtime_error(quoted(name) + " uses compression " +
                        (codec ? std::string(codec->name) : std::to_string(compression)) +
                        "; fssim reads uncompressed, PackBits, LZW and Deflate TIFFs");
  }
}

void read_chunk_geometry(TIFF* tiff, TiffLayout* layout, const std::string& name) {
  layout->tiled = TIFFIsTiled(tiff) != 0;
  if (layout->tiled) {
    TIFFGetField(tiff, TIFFTAG_TILEWIDTH, &layout->tile_width);
    TIFFGetField(tiff, TIFFTAG_TILELENGTH, &layout->tile_height);
    if (layout->tile_width == 0 || layout->tile_height == 0 ||
        layout->tile_width > static_cast<std::uint32_t>(kMaxImageSide) ||
        layout->tile_height > static_cast<std::uint32_t>(kMaxImageSide)) {
      throw_runtime_error(quoted(name) + " declares " + std::to_string(layout->tile_width) + "x" +
                          std::to_string(layout->tile_height) +
                          " tiles; a tile side must be 1 to " + std::to_string(kMaxImageSide));
    }
  }
  const tmsize_t chunk = layout->tiled ? TIFFTileSize(tiff) : TIFFScanlineSize(tiff);
  if (chunk <= 0) throw_runtime_error(quoted(name) + " has an invalid strip or tile size");
  layout->chunk_bytes = static_cast<std::size_t>(chunk);
  const std::uint64_t planes = layout->separate ? layout->samples_per_pixel : 1;
  if (layout->tiled) {  // whole tiles, even where they pass the image's edge
    const std::uint64_t across = (layout->width + layout->tile_width - 1) / layout->tile_width;
    const std::uint64_t down = (layout->height + layout->tile_height - 1) / layout->tile_height;
    layout->decoded_bytes = across * down * planes * layout->chunk_bytes;
  } else {
    layout->decoded_bytes = std::uint64_t{layout->height} * planes * layout->chunk_bytes;
  }
}

// Reads and checks the fields of the first (and only) directory.
TiffLayout read_layout(TIFF* tiff, const std::string& name) {
  TiffLayout layout;
  TIFFGetField(tiff, TIFFTAG_IMAGEWIDTH, &layout.width);
  TIFFGetField(tiff, TIFFTAG_IMAGELENGTH, &layout.height);
  if (layout.width == 0 || layout.height == 0) throw_runtime_error(quoted(name) + " has no pixels");
  if (layout.width > static_cast<std::uint32_t>(kMaxImageSide) ||
      layout.height > static_cast<std::uint32_t>(kMaxImageSide)) {
    throw_runtime_error(quoted(name) + " is " + std::to_string(layout.width) + "x" +
                        std::to_string(layout.height) + " pixels; a side must be at most " +
                        std::to_string(kMaxImageSide));
  }
  if (!TIFFLastDirectory(tiff)) {
    throw_runtime_error(quoted(name) +
                        " holds several images (pages); fssim reads single-image TIFFs");
  }
  layout.samples_per_pixel = field16(tiff, TIFFTAG_SAMPLESPERPIXEL);
  layout.bits = field16(tiff, TIFFTAG_BITSPERSAMPLE);
  layout.kind = sample_kind(tiff, layout.bits, name);
  layout.channels = photometric_channels(tiff, layout.samples_per_pixel, name);
  layout.separate = field16(tiff, TIFFTAG_PLANARCONFIG) == PLANARCONFIG_SEPARATE;
  layout.compression = field16(tiff, TIFFTAG_COMPRESSION);
  check_compression(layout.compression, name);
  read_chunk_geometry(tiff, &layout, name);  // after separate: it counts the planes
  return layout;
}

std::size_t decode_bytes(const TiffLayout& layout) {
  return layout.chunk_bytes + static_cast<std::size_t>(layout.width) * layout.height *
                                  static_cast<std::size_t>(layout.channels) * sizeof(double);
}

// Refuses, before decoding, more samples than a file of `size` bytes can hold
// and (max_bytes > 0) a decoding over max_bytes, the file's bytes included.
void check_decodable(const TiffLayout& layout, std::size_t size, const std::string& name,
                     std::size_t max_bytes) {
  if (layout.decoded_bytes >
      max_compression_ratio(layout.compression) * (static_cast<std::uint64_t>(size) + 1)) {
    throw_runtime_error(quoted(name) + " declares " + std::to_string(layout.width) + "x" +
                        std::to_string(layout.height) + " pixels, more than its " +
                        std::to_string(size) +
                        " bytes can hold: it is truncated or its header is corrupt");
  }
  const std::size_t needed = decode_bytes(layout) + size;
  detail::check_decoding_memory(name, layout.width, layout.height, needed, max_bytes);
}

// One sample as a gray level: 8-bit s, 16-bit s / 257 (as a 16-bit PNG), a float as is, so that
// the float TIFFs fssim writes read back as the gray levels they hold.
double sample_value(const std::uint8_t* at, SampleKind kind) {
  switch (kind) {
    case SampleKind::kUint8:
      return *at;
    case SampleKind::kUint16: {
      std::uint16_t sample = 0;  // libtiff has put it in the host's order
      std::memcpy(&sample, at, sizeof sample);
      return sample / 257.0;
    }
    case SampleKind::kFloat32: {
      float sample = 0.0F;
      std::memcpy(&sample, at, sizeof sample);
      return sample;
    }
  }
  return 0.0;
}

// Where a decoded chunk goes: `count` pixels from image column x0 of row y,
// their samples `stride` bytes apart, starting at `source`.
struct ChunkRow {
  const std::uint8_t* source;
  int channel;
  int y;
  int x0;
  int count;
  std::size_t stride;
};

void store_row(const TiffLayout& layout, const ChunkRow& row, Image* image,
               const std::string& name) {
  double* out = image->row(row.channel, row.y) + row.x0;
  for (int i = 0; i < row.count; ++i) {
    const double value = sample_value(row.source + i * row.stride, layout.kind);
    if (!std::isfinite(value)) {
      throw_runtime_error(quoted(name) + " holds a non-finite sample (" + format_exact(value) +
                          ") at row " + std::to_string(row.y) + ", column " +
                          std::to_string(row.x0 + i));
    }
    out[i] = value;
  }
}

// The channels a chunk of plane `plane` holds: every channel when samples are
// contiguous, that plane's alone when they are separate.
int first_channel(const TiffLayout& layout, int plane) { return layout.separate ? plane : 0; }
int last_channel(const TiffLayout& layout, int plane) {
  return layout.separate ? plane + 1 : layout.channels;
}
std::size_t pixel_stride(const TiffLayout& layout) {
  return static_cast<std::size_t>(layout.bits / 8) *
         (layout.separate ? 1 : layout.samples_per_pixel);
}

void read_strips(TIFF* tiff, const TiffLayout& layout, std::uint8_t* buffer, Image* image,
                 const TiffMessages& messages, const std::string& name) {
  const int planes = layout.separate ? layout.channels : 1;
  const std::size_t stride = pixel_stride(layout);
  const std::size_t sample_bytes = layout.bits / 8;
  for (int plane = 0; plane < planes; ++plane) {
    for (std::uint32_t y = 0; y < layout.height; ++y) {
      if (TIFFReadScanline(tiff, buffer, y, static_cast<std::uint16_t>(plane)) < 0) {
        throw_runtime_error("cannot read " + quoted(name) + ": " +
                            (messages.error[0] ? messages.error : "damaged strip data"));
      }
      for (int c = first_channel(layout, plane); c < last_channel(layout, plane); ++c) {
        const std::size_t offset = layout.separate ? 0 : c * sample_bytes;
        store_row(
            layout,
            {buffer + offset, c, static_cast<int>(y), 0, static_cast<int>(layout.width), stride},
            image, name);
      }
    }
  }
}

// Stores the part of the decoded tile of plane `plane` at (tx, ty) that lies
// inside the image.
void store_tile(const TiffLayout& layout, const std::uint8_t* tile, int plane, std::uint32_t tx,
                std::uint32_t ty, Image* image, const std::string& name) {
  const std::size_t stride = pixel_stride(layout);
  const std::size_t sample_bytes = layout.bits / 8;
  const std::uint32_t rows = std::min(layout.tile_height, layout.height - ty);
  const auto count = static_cast<int>(std::min(layout.tile_width, layout.width - tx));
  for (std::uint32_t r = 0; r < rows; ++r) {
    const std::uint8_t* line = tile + r * stride * layout.tile_width;
    for (int c = first_channel(layout, plane); c < last_channel(layout, plane); ++c) {
      const std::size_t offset = layout.separate ? 0 : c * sample_bytes;
      store_row(layout,
                {line + offset, c, static_cast<int>(ty + r), static_cast<int>(tx), count, stride},
                image, name);
    }
  }
}

void read_tiles(TIFF* tiff, const TiffLayout& layout, std::uint8_t* buffer, Image* image,
                const TiffMessages& messages, const std::string& name) {
  const int planes = layout.separate ? layout.channels : 1;
  for (int plane = 0; plane < planes; ++plane) {
    for (std::uint32_t ty = 0; ty < layout.height; ty += layout.tile_height) {
      for (std::uint32_t tx = 0; tx < layout.width; tx += layout.tile_width) {
        if (TIFFReadTile(tiff, buffer, tx, ty, 0, static_cast<std::uint16_t>(plane)) < 0) {
          throw_runtime_error("cannot read " + quoted(name) + ": " +
                              (messages.error[0] ? messages.error : "damaged tile data"));
        }
        store_tile(layout, buffer, plane, tx, ty, image, name);
      }
    }
  }
}

}  // namespace

bool has_tiff_signature(const std::uint8_t* bytes, std::size_t size) {
  if (size < 4) return false;
  const bool little =
      bytes[0] == 'I' && bytes[1] == 'I' && bytes[3] == 0 && (bytes[2] == 42 || bytes[2] == 43);
  const bool big =
      bytes[0] == 'M' && bytes[1] == 'M' && bytes[2] == 0 && (bytes[3] == 42 || bytes[3] == 43);
  return little || big;
}

Image decode_tiff(const std::uint8_t* bytes, std::size_t size, const std::string& name,
                  std::size_t max_bytes, TiffSamples* samples) {
  if (!has_tiff_signature(bytes, size)) {
    throw_runtime_error("input '" + name + "' is not a TIFF file (bad signature)");
  }
  require_libtiff("cannot read " + quoted(name));
  MemoryFile file{bytes, size, nullptr, 0};
  TiffMessages messages;
  const TiffHandle tiff = open_memory_tiff(name, "r", &file, &messages);
  if (!tiff) {
    throw_runtime_error("cannot read " + quoted(name) + ": " +
                        (messages.error[0] ? messages.error : "out of memory"));
  }
  const TiffLayout layout = read_layout(tiff.get(), name);
  check_decodable(layout, size, name, max_bytes);
  if (samples != nullptr) *samples = {layout.bits, layout.kind == SampleKind::kFloat32};
  try {
    const auto buffer = std::make_unique_for_overwrite<std::uint8_t[]>(layout.chunk_bytes);
    Image image(static_cast<int>(layout.width), static_cast<int>(layout.height), layout.channels);
    if (layout.tiled) {
      read_tiles(tiff.get(), layout, buffer.get(), &image, messages, name);
    } else {
      read_strips(tiff.get(), layout, buffer.get(), &image, messages, name);
    }
    return image;
  } catch (const std::bad_alloc&) {
    throw_runtime_error("cannot read " + quoted(name) + ": not enough memory for its " +
                        std::to_string(layout.width) + "x" + std::to_string(layout.height) +
                        " pixels");
  }
}

Image read_tiff(const std::filesystem::path& path, std::size_t max_bytes) {
  const std::vector<std::uint8_t> bytes = detail::read_input_bytes(
      path, "a TIFF file",
      [](const std::uint8_t* head, std::size_t size) { return has_tiff_signature(head, size); },
      max_bytes);
  return decode_tiff(bytes.data(), bytes.size(), path.string(), max_bytes);
}

// ---------------------------------------------------------------------------
// Writing.

namespace {

// Min-is-black or RGB, contiguous samples, uncompressed, strips of libtiff's default size (about
// 8 KiB).
void set_float_fields(TIFF* tiff, int width, int height, int channels) {
  TIFFSetField(tiff, TIFFTAG_IMAGEWIDTH, static_cast<std::uint32_t>(width));
  TIFFSetField(tiff, TIFFTAG_IMAGELENGTH, static_cast<std::uint32_t>(height));
  TIFFSetField(tiff, TIFFTAG_SAMPLESPERPIXEL, static_cast<std::uint16_t>(channels));
  TIFFSetField(tiff, TIFFTAG_BITSPERSAMPLE, static_cast<std::uint16_t>(32));
  TIFFSetField(tiff, TIFFTAG_SAMPLEFORMAT, static_cast<std::uint16_t>(SAMPLEFORMAT_IEEEFP));
  TIFFSetField(
      tiff, TIFFTAG_PHOTOMETRIC,
      static_cast<std::uint16_t>(channels == 1 ? PHOTOMETRIC_MINISBLACK : PHOTOMETRIC_RGB));
  TIFFSetField(tiff, TIFFTAG_PLANARCONFIG, static_cast<std::uint16_t>(PLANARCONFIG_CONTIG));
  TIFFSetField(tiff, TIFFTAG_COMPRESSION, static_cast<std::uint16_t>(COMPRESSION_NONE));
  TIFFSetField(tiff, TIFFTAG_ROWSPERSTRIP, TIFFDefaultStripSize(tiff, 0));
}

void check_float_encodable(int width, int height, int channels) {
  if (channels != 1 && channels != 3) {
    throw_usage_error("TIFF encoding needs 1 or 3 channels, got " + std::to_string(channels));
  }
  if (width <= 0 || height <= 0 || width > kMaxImageSide || height > kMaxImageSide) {
    throw_usage_error("TIFF encoding needs 1 to " + std::to_string(kMaxImageSide) +
                      " pixels a side, got " + std::to_string(width) + "x" +
                      std::to_string(height));
  }
}

}  // namespace

std::vector<std::uint8_t> encode_tiff_float(
    int width, int height, int channels,
    const std::function<void(int c, int y, double* row)>& fill_row) {
  check_float_encodable(width, height, channels);
  require_libtiff("cannot write a float TIFF");
  std::vector<std::uint8_t> out;
  MemoryFile file{nullptr, 0, &out, 0};
  TiffMessages messages;
  bool written = false;
  {
    const TiffHandle tiff = open_memory_tiff("float TIFF", "wl", &file, &messages);
    if (!tiff) throw_runtime_error("TIFF encoding failed: out of memory");
    set_float_fields(tiff.get(), width, height, channels);
    std::vector<double> values(static_cast<std::size_t>(width));
    std::vector<float> row(static_cast<std::size_t>(width) * channels);
    written = true;
    for (int y = 0; y < height && written; ++y) {
      for (int c = 0; c < channels; ++c) {
        fill_row(c, y, values.data());
        for (int x = 0; x < width; ++x) {
          row[static_cast<std::size_t>(x) * channels + c] = static_cast<float>(values[x]);
        }
      }
      written = TIFFWriteScanline(tiff.get(), row.data(), static_cast<std::uint32_t>(y), 0) == 1;
    }
    written = written && TIFFFlush(tiff.get()) == 1;
  }
  if (!written) {
    throw_runtime_error(std::string("TIFF encoding failed: ") +
                        (messages.error[0] ? messages.error : "write error"));
  }
  return out;
}

std::vector<std::uint8_t> encode_tiff_float(const Image& image) {
  return encode_tiff_float(image.width, image.height, image.channels,
                           [&](int c, int y, double* row) {
                             std::copy(image.row(c, y), image.row(c, y) + image.width, row);
                           });
}

}  // namespace fss
