#pragma once
// SHA-256 (FIPS 180-4), written here so the CLI needs no crypto library for the checksums of the
// files it writes (status.json). Incremental: update() any number of times, then hex_digest().
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace lbsolid::cli {

class Sha256 {
 public:
  Sha256();
  void update(const void* data, std::size_t size);
  void update(std::string_view text) { update(text.data(), text.size()); }
  std::array<std::uint8_t, 32> digest();  // finishes the hash; call once
  std::string hex_digest();               // digest() as 64 lowercase hex digits

 private:
  void compress(const std::uint8_t* block);
  std::array<std::uint32_t, 8> state_;
  std::array<std::uint8_t, 64> buffer_{};
  std::size_t buffered_ = 0;
  std::uint64_t total_bytes_ = 0;
};

std::string sha256_hex(std::string_view data);
// Hashes a file in blocks; throws std::runtime_error naming the path if it cannot be read.
std::string sha256_file_hex(const std::string& path);

}  // namespace lbsolid::cli
