#include "io/storage/checkpoint_checksum.h"

#include <bit>

#include "io/storage/sha256.h"

namespace lbsolid::server::storage {
namespace {

void add_u64(Sha256& hash, std::uint64_t value) {
  std::uint8_t bytes[8];
  for (int i = 0; i < 8; ++i) bytes[i] = static_cast<std::uint8_t>(value >> (8 * i));
  hash.update(bytes, sizeof bytes);
}

// Each field as name, NUL, length, bytes: no two different records hash the same input.
class Record {
 public:
  void text(std::string_view name, std::string_view value) {
    field(name, value.size());
    hash_.update(value);
  }
  void number(std::string_view name, long value) {
    field(name, 8);
    add_u64(hash_, static_cast<std::uint64_t>(value));
  }
  std::string hex_digest() { return hash_.hex_digest(); }

 private:
  void field(std::string_view name, std::size_t length) {
    hash_.update(name);
    hash_.update("\0", 1);
    add_u64(hash_, length);
  }
  Sha256 hash_;
};

}  // namespace

std::string values_checksum(const std::vector<std::uint64_t>& dims, const double* values, std::size_t count) {
  Sha256 hash;
  add_u64(hash, dims.size());
  for (std::uint64_t d : dims) add_u64(hash, d);
  if constexpr (std::endian::native == std::endian::little) {
    if (count > 0) hash.update(values, count * sizeof(double));
  } else {
    for (std::size_t i = 0; i < count; ++i) add_u64(hash, std::bit_cast<std::uint64_t>(values[i]));
  }
  return hash.hex_digest();
}

std::string text_checksum(std::string_view text) { return sha256_hex(text); }

std::string root_checksum(int format_version, const WriterInfo& writer, const CheckpointContents& contents,
                          const DatasetChecksums& datasets) {
  Record record;
  record.number("format_version", format_version);
  record.text("lbsolid_version", writer.version);
  record.text("git_revision", writer.git_revision);
  record.text("session_id", contents.session_id);
  record.text("session_name", contents.session_name);
  record.text("request_id", contents.request_id);
  if (format_version >= 3) record.text("owner", contents.owner);
  record.number("done", contents.done ? 1 : 0);
  record.number("started", contents.started ? 1 : 0);
  record.number("target_step", contents.target_step);
  const scene::SimulationState& state = contents.state;
  record.number("step", state.step);
  record.number("has_fluid", state.has_fluid ? 1 : 0);
  if (state.has_fluid) {
    record.number("fluid/steps", state.fluid.steps);
    record.number("fluid/current", state.fluid.current);
    record.number("fluid/pulled", state.fluid.pulled ? 1 : 0);
    record.number("fluid/stepped", state.fluid.stepped ? 1 : 0);
    record.number("fluid/buffers", state.fluid.buffers);
    record.number("fluid/cells", state.fluid.cells);
  }
  record.number("has_solid", state.has_solid ? 1 : 0);
  for (const auto& [path, checksum] : datasets) record.text(path, checksum);
  return record.hex_digest();
}

}  // namespace lbsolid::server::storage
