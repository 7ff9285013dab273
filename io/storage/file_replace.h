#pragma once
// Replacing a file so that a crash leaves either the old content or the new, never a mix: write a
// temporary file beside the target, fsync it, rename it over the target (atomic within one file
// system), then fsync the directory so the rename itself is on disk. Each write has a temporary
// file of its own, so simultaneous writes of one target never write into one another's file: the
// target ends as exactly one of them.
#include <string>
#include <string_view>

namespace lbsolid::server::storage {

// In every temporary file's name: a daemon that starts removes leftover files whose name holds it
// (a write interrupted by a crash), so nothing else in the data directory may carry it.
inline constexpr std::string_view kTemporaryMarker = ".tmp-";

// A new, empty file "<target>.tmp-<pid>-<count>-<random>" beside target (same directory, so same
// file system), created exclusively (O_EXCL): no other write, in this process or another, has it.
// Removed by the destructor unless replace_target() moved it over the target.
class TemporaryFile {
 public:
  // Throws std::runtime_error naming the file and the cause.
  explicit TemporaryFile(std::string target);
  ~TemporaryFile();
  TemporaryFile(const TemporaryFile&) = delete;
  TemporaryFile& operator=(const TemporaryFile&) = delete;

  const std::string& path() const { return path_; }
  // Writes all of data through the open descriptor. Throws std::runtime_error naming the file.
  void write(std::string_view data);
  // Closes the descriptor (checked), for a writer that opens the file by name (HDF5).
  void close_descriptor();
  // fsync, rename over the target, fsync the directory. Throws std::runtime_error naming the step
  // that failed: before the rename the target is untouched; after it (the directory sync) the
  // target is already the new file, only its durability is unknown.
  void replace_target();

 private:
  std::string target_;
  std::string path_;
  int fd_ = -1;
  bool moved_ = false;
};

// The directory holding path ("." for a bare name).
std::string directory_of(const std::string& path);

// Moves the finished file `temporary` over path durably (the steps of replace_target()). Throws
// std::runtime_error; the temporary file is left for the caller to remove.
void replace_durably(const std::string& temporary, const std::string& path);

void remove_quietly(const std::string& path);

// Writes text to path through a temporary file of its own. Throws std::runtime_error naming the
// path; the old file, if any, is then untouched.
void write_text_file_replacing(const std::string& path, const std::string& text);

}  // namespace lbsolid::server::storage
