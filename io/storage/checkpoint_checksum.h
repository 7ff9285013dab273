#pragma once
// The checksums of a checkpoint (format 2), so that damage anywhere in the file is detected before
// a run continues from it. Both are SHA-256, as 64 lowercase hex digits in an attribute "sha256":
//   on each dataset   of its extent and its values as read (values_checksum, text_checksum);
//   on the root group of a record of everything else read_checkpoint reads: every root and /fluid
//                     attribute (but "format", which must be exactly "lbsolid-checkpoint"), which
//                     groups exist, and each dataset's checksum (root_checksum), so a changed
//                     attribute, a lost group or a swapped dataset is caught too.
// Values are hashed as read (converted to native numbers), so a damaged stored type cannot pass.
// Private to io/storage.
#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "io/storage/checkpoint_file.h"

namespace lbsolid::server::storage {

inline constexpr const char* kChecksumAttribute = "sha256";

// Of a numeric dataset: its extent (rank, then each dimension) and its values, every number as
// 8 little-endian bytes whatever the machine.
std::string values_checksum(const std::vector<std::uint64_t>& dims, const double* values, std::size_t count);

// Of a string dataset: its bytes.
std::string text_checksum(std::string_view text);

// The checksum of each dataset, by path ("/fluid/populations").
using DatasetChecksums = std::map<std::string, std::string>;

// Of what the root's checksum covers. format_version is the one written or read.
std::string root_checksum(int format_version, const WriterInfo& writer, const CheckpointContents& contents,
                          const DatasetChecksums& datasets);

}  // namespace lbsolid::server::storage
