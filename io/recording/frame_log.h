#pragma once
// The append-only log in which the daemon records a session's outputs as they happen: one record
// per frame (a serialized ParticleFrame or ProfileFrame, or a field snapshot), in step order, each
// with its own checksum. It is the durable copy: the HDF5 files a client downloads are made from
// it (output_files.h), so a crash never leaves a half-written HDF5 file, and a session recovered
// at an earlier save drops the records past it and records those steps again, once.
//
// Record: "LBFR", kind (u32), step (i64), payload size (u64), payload, FNV-1a 64 of all before
// it (u64), little-endian. A torn or damaged tail ends the log: opening it cuts it there.
#include <cstdint>
#include <functional>
#include <mutex>
#include <string>
#include <string_view>

namespace lbsolid::server::recording {

enum class RecordKind : std::uint32_t { kParticles = 1, kProfile = 2, kFields = 3 };

class FrameLog {
 public:
  // Opens `path` (creating it) and keeps its valid records with step <= keep_through_step; the
  // rest is cut off. Throws std::runtime_error naming the path and the cause.
  FrameLog(std::string path, long keep_through_step);
  ~FrameLog();
  FrameLog(const FrameLog&) = delete;
  FrameLog& operator=(const FrameLog&) = delete;

  // Appends one record (into the page cache: no fsync). Throws std::runtime_error on a failed
  // write, the log then cut back to its last whole record.
  void append(RecordKind kind, long step, std::string_view payload);
  // Makes every record appended so far durable (fsync).
  void sync();
  // Bytes of whole records: what a reader may read.
  std::uint64_t size() const;
  const std::string& path() const { return path_; }

 private:
  const std::string path_;
  int fd_ = -1;
  mutable std::mutex mutex_;
  std::uint64_t size_ = 0;
};

struct LogRecord {
  RecordKind kind;
  long step;
  std::string_view payload;
};

// Calls `visit` for each whole record in the first `size` bytes of the log at `path`, in order.
// Throws std::runtime_error if the file cannot be read or a record there is damaged.
void read_frame_log(const std::string& path, std::uint64_t size, const std::function<void(const LogRecord&)>& visit);

}  // namespace lbsolid::server::recording
