#include "result_writer.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <stdexcept>

#include "json_writer.h"
#include "io/storage/sha256.h"

namespace lbsolid::cli {

using server::storage::Sha256;
using server::storage::sha256_file_hex;

std::vector<FileEntry> describe_files(const std::string& dir, const std::vector<std::string>& names) {
  std::vector<FileEntry> files;
  for (const auto& name : names) {
    const std::filesystem::path path = std::filesystem::path(dir) / name;
    std::error_code error;
    if (!std::filesystem::is_regular_file(path, error)) continue;
    files.push_back({name, std::filesystem::file_size(path), sha256_file_hex(path.string())});
  }
  std::sort(files.begin(), files.end(), [](const auto& a, const auto& b) { return a.name < b.name; });
  return files;
}

std::string combined_checksum(std::vector<FileEntry> files) {
  std::sort(files.begin(), files.end(), [](const auto& a, const auto& b) { return a.name < b.name; });
  Sha256 hash;
  for (const auto& f : files) hash.update(f.sha256);
  return hash.hex_digest();
}

namespace {

template <class T, class Write>
void optional_value(JsonObject& o, std::string_view key, const std::optional<T>& value, Write write) {
  if (value)
    write(o, key, *value);
  else
    o.null(key);
}

void optional_string(JsonObject& o, std::string_view key, const std::optional<std::string>& value) {
  optional_value(o, key, value, [](JsonObject& j, std::string_view k, const std::string& v) { j.string(k, v); });
}

void optional_integer(JsonObject& o, std::string_view key, const std::optional<long long>& value) {
  optional_value(o, key, value, [](JsonObject& j, std::string_view k, long long v) { j.integer(k, v); });
}

}  // namespace

std::string result_json(const CommandResult& r) {
  std::vector<std::string> files;
  for (const auto& f : r.files)
    files.push_back(JsonObject()
                        .string("name", f.name)
                        .integer("bytes", static_cast<long long>(f.bytes))
                        .string("sha256", f.sha256)
                        .str());
  JsonObject o;
  o.integer("version", kResultSchemaVersion);
  optional_string(o, "command", r.command.empty() ? std::nullopt : std::optional(r.command));
  optional_string(o, "session_id", r.session_id);
  optional_string(o, "state", r.state);
  optional_integer(o, "step", r.step);
  optional_integer(o, "target_step", r.target_step);
  optional_string(o, "message", r.message);
  o.raw("files", json_array(files));
  optional_string(o, "checksum", r.wrote_files ? std::optional(combined_checksum(r.files)) : std::nullopt);
  if (r.error) {
    JsonObject error;
    error.string("code", r.error->code);
    optional_string(error, "rpc", r.error->rpc.empty() ? std::nullopt : std::optional(r.error->rpc));
    error.string("message", r.error->message).integer("exit_code", r.error->exit_code);
    o.raw("error", error.str());
  } else {
    o.null("error");
  }
  o.integer("exit_code", r.exit_code);
  for (const auto& [key, json] : r.extras) o.raw(key, json);
  return o.str();
}

void write_file_atomically(const std::string& path, const std::string& content) {
  const std::string temporary = path + ".tmp";
  const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  if (fd < 0) throw std::runtime_error(temporary + ": cannot create: " + std::strerror(errno));
  std::size_t written = 0;
  while (written < content.size()) {
    const ssize_t n = ::write(fd, content.data() + written, content.size() - written);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      const std::string cause = std::strerror(errno);
      ::close(fd);
      std::remove(temporary.c_str());
      throw std::runtime_error(temporary + ": write failed: " + cause);
    }
    written += static_cast<std::size_t>(n);
  }
  // fsync before the rename: after a crash the name holds either the old file or all of the new one.
  const bool synced = ::fsync(fd) == 0;
  const bool closed = ::close(fd) == 0;
  if (!synced || !closed || std::rename(temporary.c_str(), path.c_str()) != 0) {
    const std::string cause = std::strerror(errno);
    std::remove(temporary.c_str());
    throw std::runtime_error(path + ": cannot write: " + cause);
  }
}

}  // namespace lbsolid::cli
