#pragma once
// SHA-256 (FIPS 180-4), written here so that nothing needs a crypto library for checksums: the
// CLI's of the files it writes (status.json), storage's of what it writes into checkpoints.
// Incremental: update() any number of times, then digest() or hex_digest(). Its own library
// (lbsolid_sha256) so the CLI's unit tests link it without HDF5.
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace lbsolid::server::storage {

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

}  // namespace lbsolid::server::storage
