#pragma once
// The one JSON object every command prints with --json (one per line for watch, one for an error)
// and that `submit --out` writes to DIR/status.json. Schema version 3 (README, "--json"):
//   {"version": 3, "command", "session_id", "state", "step", "target_step", "message",
//    "files": [{"name", "bytes", "sha256"}], "checksum",
//    "error": {"code", "rpc", "message", "exit_code"}, "exit_code", then what the command adds}
// Every key up to exit_code is always there, null where the command has no such value (list has
// no session, an answer without a failure has "error": null). What commands add, each under one
// key: "session" (the whole Session), "sessions", "server", "checkpoint", "validation", "frame",
// "fields", "deleted".
// checksum is the SHA-256 of the files' sha256 hex strings concatenated in name order, so one
// value says whether a whole result directory is unchanged; null for commands that write no files.
// version 2 (status.json only): the same first keys with "error" a string and no "command".
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace lbsolid::cli {

inline constexpr int kResultSchemaVersion = 3;

struct FileEntry {
  std::string name;  // relative to the directory
  std::uintmax_t bytes = 0;
  std::string sha256;
};

// A failure: code is the gRPC code's name ("NOT_FOUND") for a failed call (rpc names the call),
// else USAGE, BAD_INPUT, TRANSIENT or INTERNAL (what failed on the client's side).
struct ResultError {
  std::string code, rpc, message;
  int exit_code = 0;
};

struct CommandResult {
  std::string command;  // "submit", "status", ...; empty (null) when the command line did not parse
  std::optional<std::string> session_id, state, message;
  std::optional<long long> step, target_step;
  std::vector<FileEntry> files;
  bool wrote_files = false;  // the command writes files: checksum is printed (for none too)
  std::optional<ResultError> error;
  int exit_code = 0;
  std::vector<std::pair<std::string, std::string>> extras;  // key, valid JSON

  CommandResult& add(std::string key, std::string json) {
    extras.emplace_back(std::move(key), std::move(json));
    return *this;
  }
};

std::string result_json(const CommandResult& result);

// The entries of the named files that exist in `dir`, sorted by name. Throws std::runtime_error.
std::vector<FileEntry> describe_files(const std::string& dir, const std::vector<std::string>& names);
std::string combined_checksum(std::vector<FileEntry> files);

// Writes `path` through "<path>.tmp" and a rename, so a reader never sees half a file.
// Throws std::runtime_error naming the path and the cause.
void write_file_atomically(const std::string& path, const std::string& content);

}  // namespace lbsolid::cli
