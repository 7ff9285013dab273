#include "io/storage/file_replace.h"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <random>
#include <stdexcept>
#include <string>
#include <utility>

namespace lbsolid::server::storage {
namespace {

[[noreturn]] void fail_errno(const std::string& what, int error) {
  throw std::runtime_error(what + ": " + std::strerror(error));
}

void fsync_path(const std::string& path, bool directory) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | (directory ? O_DIRECTORY : 0));
  if (fd < 0) fail_errno("cannot open " + path + " to sync it", errno);
  const int result = ::fsync(fd);
  const int error = errno;
  ::close(fd);
  // Some file systems cannot sync a directory (EINVAL): the rename is then as durable as they allow.
  if (result != 0 && !(directory && error == EINVAL)) fail_errno("cannot sync " + path, error);
}

// The pid tells processes apart, the count the writes of one process; the random part keeps a
// name left by an earlier process with the same pid from being met again and again.
std::string candidate_name(const std::string& target) {
  static std::atomic<unsigned long> count{0};
  char random_part[9];
  std::snprintf(random_part, sizeof random_part, "%08x", static_cast<unsigned>(std::random_device{}()));
  return target + std::string(kTemporaryMarker) + std::to_string(static_cast<long>(::getpid())) + "-" +
         std::to_string(count++) + "-" + random_part;
}

}  // namespace

TemporaryFile::TemporaryFile(std::string target) : target_(std::move(target)) {
  constexpr int kAttempts = 100;
  for (int attempt = 0; attempt < kAttempts; ++attempt) {
    path_ = candidate_name(target_);
    // 0666 as for any new file: the umask decides, as it did before this file was temporary.
    fd_ = ::open(path_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd_ >= 0) return;
    if (errno != EEXIST) fail_errno("cannot create " + path_, errno);
  }
  throw std::runtime_error("cannot create a temporary file beside " + target_ + ": " + std::to_string(kAttempts) +
                           " names were all taken");
}

TemporaryFile::~TemporaryFile() {
  if (fd_ >= 0) ::close(fd_);
  if (!moved_) remove_quietly(path_);
}

void TemporaryFile::write(std::string_view data) {
  if (fd_ < 0) throw std::logic_error("TemporaryFile::write after close_descriptor");
  while (!data.empty()) {
    const ssize_t written = ::write(fd_, data.data(), data.size());
    if (written < 0) {
      if (errno == EINTR) continue;
      fail_errno("cannot write " + path_, errno);
    }
    data.remove_prefix(static_cast<std::size_t>(written));
  }
}

void TemporaryFile::close_descriptor() {
  if (fd_ < 0) return;
  // close() can report a failed write (NFS, quotas): that is a failed file, not a detail.
  const int result = ::close(fd_);
  fd_ = -1;
  if (result != 0) fail_errno("cannot close " + path_, errno);
}

void TemporaryFile::replace_target() {
  close_descriptor();
  replace_durably(path_, target_);
  moved_ = true;
}

std::string directory_of(const std::string& path) {
  const std::filesystem::path parent = std::filesystem::path(path).parent_path();
  return parent.empty() ? "." : parent.string();
}

void replace_durably(const std::string& temporary, const std::string& path) {
  fsync_path(temporary, false);
  if (std::rename(temporary.c_str(), path.c_str()) != 0)
    fail_errno("cannot rename " + temporary + " to " + path, errno);
  fsync_path(directory_of(path), true);
}

void remove_quietly(const std::string& path) {
  std::error_code ignored;
  std::filesystem::remove(path, ignored);
}

void write_text_file_replacing(const std::string& path, const std::string& text) {
  TemporaryFile temporary(path);
  temporary.write(text);
  temporary.replace_target();
}

}  // namespace lbsolid::server::storage
