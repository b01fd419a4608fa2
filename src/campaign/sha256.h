// SHA-256 (FIPS 180-4), for the provenance columns of a campaign
// (image_sha256, code_sha256) and the hash of its specification.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <string_view>

namespace fss {

class Sha256 {
 public:
  Sha256();
  void update(std::string_view bytes);
  // The digest of everything given to update(); the object is spent.
  std::array<std::uint8_t, 32> finish();

 private:
  void compress(const std::uint8_t* block);

  std::array<std::uint32_t, 8> state_;
  std::array<std::uint8_t, 64> buffer_{};
  std::size_t buffered_ = 0;
  std::uint64_t length_bytes_ = 0;
};

// The digest of `bytes` as 64 lowercase hexadecimal digits.
std::string sha256_hex(std::string_view bytes);

}  // namespace fss
