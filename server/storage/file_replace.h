#pragma once
// Replacing a file so that a crash leaves either the old content or the new, never a mix: write a
// temporary file beside the target, fsync it, rename it over the target (atomic within one file
// system), then fsync the directory so the rename itself is on disk.
#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

namespace lbsolid::server::storage {

// Beside the target (same directory, so same file system) and unique per process.
inline std::string temporary_path_for(const std::string& path) {
  return path + ".tmp-" + std::to_string(static_cast<long>(::getpid()));
}

inline std::string directory_of(const std::string& path) {
  const std::filesystem::path parent = std::filesystem::path(path).parent_path();
  return parent.empty() ? "." : parent.string();
}

[[noreturn]] inline void fail_errno(const std::string& what, int error) {
  throw std::runtime_error(what + ": " + std::strerror(error));
}

inline void fsync_path(const std::string& path, bool directory) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | (directory ? O_DIRECTORY : 0));
  if (fd < 0) fail_errno("cannot open " + path + " to sync it", errno);
  const int result = ::fsync(fd);
  const int error = errno;
  ::close(fd);
  // Some file systems cannot sync a directory (EINVAL): the rename is then as durable as they allow.
  if (result != 0 && !(directory && error == EINVAL)) fail_errno("cannot sync " + path, error);
}

// Moves the finished temporary file over path durably. Throws std::runtime_error; the temporary
// file is left for the caller to remove.
inline void replace_durably(const std::string& temporary, const std::string& path) {
  fsync_path(temporary, false);
  if (std::rename(temporary.c_str(), path.c_str()) != 0)
    fail_errno("cannot rename " + temporary + " to " + path, errno);
  fsync_path(directory_of(path), true);
}

inline void remove_quietly(const std::string& path) {
  std::error_code ignored;
  std::filesystem::remove(path, ignored);
}

// Writes text to path through a temporary file. Throws std::runtime_error naming the path.
inline void write_text_file_replacing(const std::string& path, const std::string& text) {
  const std::string temporary = temporary_path_for(path);
  try {
    {
      std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
      if (!out) fail_errno("cannot create " + temporary, errno);
      out << text;
      out.close();
      if (!out) throw std::runtime_error("cannot write " + temporary);
    }
    replace_durably(temporary, path);
  } catch (...) {
    remove_quietly(temporary);
    throw;
  }
}

}  // namespace lbsolid::server::storage
