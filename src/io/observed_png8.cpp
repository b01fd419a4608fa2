#include "io/observed_png8.h"

#include <string>

#include "core/huge_pages.h"
#include "fss/core/error.h"
#include "fss/io/png_io.h"
#include "io/png_write.h"

namespace fss {

ObservedPng8::ObservedPng8(int height, int channels) : height_(height), channels_(channels) {
  if (height <= 0 || (channels != 1 && channels != 3)) {
    throw_usage_error("ObservedPng8 needs a height > 0 and 1 or 3 channels, got height " +
                      std::to_string(height) + " and " + std::to_string(channels) + " channels");
  }
  stored_ = std::vector<std::atomic<bool>>(static_cast<std::size_t>(height) * channels);
}

void ObservedPng8::store_row(int channel, int row, std::span<const double> values) {
  std::call_once(allocated_, [&] {
    width_ = static_cast<int>(values.size());
    const std::size_t samples = values.size() * static_cast<std::size_t>(height_) * channels_;
    detail::reserve_on_huge_pages(samples_, samples);
    samples_.resize(samples);
  });
  if (channel < 0 || channel >= channels_ || row < 0 || row >= height_ ||
      values.size() != static_cast<std::size_t>(width_)) {
    throw_usage_error("ObservedPng8: row " + std::to_string(row) + " of channel " +
                      std::to_string(channel) + " with " + std::to_string(values.size()) +
                      " values does not fit a " + std::to_string(width_) + " x " +
                      std::to_string(height_) + " x " + std::to_string(channels_) + " image");
  }
  if (stored_[static_cast<std::size_t>(channel) * height_ + row].exchange(true)) {
    throw_usage_error("ObservedPng8: row " + std::to_string(row) + " of channel " +
                      std::to_string(channel) + " was stored twice");
  }
  // Interleaved as PNG stores them: sample (row, x, channel).
  std::uint8_t* out =
      samples_.data() + static_cast<std::size_t>(row) * width_ * channels_ + channel;
  for (const double v : values) {
    *out = png8_sample(v);
    out += channels_;
  }
  ++rows_stored_;
}

void ObservedPng8::check_complete() const {
  if (rows_stored_ != height_ * channels_) {
    throw_usage_error("observed.png: " + std::to_string(rows_stored_) + " of " +
                      std::to_string(height_ * channels_) + " observed rows were collected");
  }
}

std::vector<std::uint8_t> ObservedPng8::encode() const {
  check_complete();
  return encode_png8_samples(width_, height_, channels_, samples_);
}

std::string ObservedPng8::encode_string() const {
  check_complete();
  return detail::encode_png8_samples_string(width_, height_, channels_, samples_);
}

}  // namespace fss
