#pragma once
// DIR/status.json, the record of a `submit --out` run that scripts check:
//   {"version", "session_id", "state", "step", "target_step", "message", "error", "files": [{"name",
//    "bytes", "sha256"}], "checksum", "exit_code"}
// version 2: the files are the daemon's recorded outputs (version 1, without the field: the CLI's
// own recording of the streams).
// checksum is the SHA-256 of the files' sha256 hex strings concatenated in name order, so one
// value says whether a whole result directory is unchanged.
#include <cstdint>
#include <string>
#include <vector>

namespace lbsolid::cli {

inline constexpr int kStatusVersion = 2;

struct FileEntry {
  std::string name;  // relative to the directory
  std::uintmax_t bytes = 0;
  std::string sha256;
};

struct RunRecord {
  std::string session_id, state, message;
  long long step = 0, target_step = 0;
  std::string error;  // what went wrong on the client's side (empty when nothing did)
  std::vector<FileEntry> files;
  int exit_code = 0;
};

// The entries of the named files that exist in `dir`, sorted by name. Throws std::runtime_error.
std::vector<FileEntry> describe_files(const std::string& dir, const std::vector<std::string>& names);
std::string combined_checksum(std::vector<FileEntry> files);
std::string status_json(const RunRecord& record);

// Writes `path` through "<path>.tmp" and a rename, so a reader never sees half a file.
// Throws std::runtime_error naming the path and the cause.
void write_file_atomically(const std::string& path, const std::string& content);

}  // namespace lbsolid::cli
