// The observed image as the 8-bit samples observed.png holds, collected row
// by row while Simulate runs: one byte a sample instead of a double.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <mutex>
#include <span>
#include <string>
#include <vector>

#include "fss/pipeline/simulate.h"

namespace fss {

// The observed image as the 8-bit samples observed.png holds, collected row
// by row as the ObservedRowSink of Simulate, so that the report need not keep
// the observed image: one byte a sample instead of a double. Rows may
// arrive concurrently; the width is that of the first. write_outputs takes
// it in place of the report's observed image.
class ObservedPng8 : public ObservedRowSink {
 public:
  ObservedPng8(int height, int channels);
  ObservedPng8(const ObservedPng8&) = delete;
  ObservedPng8& operator=(const ObservedPng8&) = delete;

  // Stores one row; consume_row calls this. A
  // row that does not fit or is stored twice is a usage error.
  void store_row(int channel, int row, std::span<const double> values);
  void consume_row(int channel, int row, std::span<const double> values) override {
    store_row(channel, row, values);
  }

  int width() const { return width_; }
  int height() const { return height_; }
  int channels() const { return channels_; }
  // Rows stored so far (channels x height when complete).
  int rows_stored() const { return rows_stored_; }
  // The PNG; the same bytes as encode_png8 of the observed image of doubles.
  std::vector<std::uint8_t> encode() const;
  // The same bytes as a std::string, what an output file holds (no copy).
  std::string encode_string() const;

 private:
  void check_complete() const;  // a usage error unless every row was stored

  int width_ = 0;
  int height_;
  int channels_;
  std::once_flag allocated_;
  std::vector<std::uint8_t> samples_;      // interleaved as PNG stores them
  std::vector<std::atomic<bool>> stored_;  // by channel * height + row
  std::atomic<int> rows_stored_{0};
};

}  // namespace fss
