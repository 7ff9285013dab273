#include "io/recording/frame_log.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <bit>
#include <fstream>
#include <limits>
#include <stdexcept>
#include <vector>

namespace lbsolid::server::recording {
namespace {

constexpr char kMagic[4] = {'L', 'B', 'F', 'R'};
constexpr std::size_t kHeaderBytes = 4 + 4 + 8 + 8;
constexpr std::size_t kTrailerBytes = 8;
constexpr std::uint64_t kMaxPayloadBytes = 1ULL << 40;

std::uint64_t fnv1a(std::string_view bytes, std::uint64_t hash = 14695981039346656037ULL) {
  for (const unsigned char c : bytes) {
    hash ^= c;
    hash *= 1099511628211ULL;
  }
  return hash;
}

template <class T>
void put(std::string& out, T value) {
  static_assert(std::endian::native == std::endian::little, "records are written as the machine stores them");
  out.append(reinterpret_cast<const char*>(&value), sizeof value);
}

template <class T>
T get(const char* at) {
  T value;
  std::memcpy(&value, at, sizeof value);
  return value;
}

std::runtime_error failure(const std::string& path, const std::string& what) {
  return std::runtime_error(path + ": " + what + ": " + std::strerror(errno));
}

struct Scan {
  std::uint64_t valid = 0;  // bytes of whole records kept
  bool damaged = false;     // a record failed its checksum (not merely cut short)
};

// Reads the records of the first `size` bytes of `path` one at a time (a record's payload is the
// only thing in memory); stops at the first that is incomplete, damaged, or past `through`.
Scan scan(const std::string& path, std::uint64_t size, long through,
          const std::function<void(const LogRecord&)>& visit) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw failure(path, "cannot open the frame log");
  Scan result;
  std::string record;
  while (size - result.valid >= kHeaderBytes + kTrailerBytes) {
    record.resize(kHeaderBytes);
    if (!in.read(record.data(), kHeaderBytes)) break;
    if (std::memcmp(record.data(), kMagic, 4) != 0) {
      result.damaged = true;
      break;
    }
    const auto kind = get<std::uint32_t>(record.data() + 4);
    const auto step = get<std::int64_t>(record.data() + 8);
    const auto bytes = get<std::uint64_t>(record.data() + 16);
    if (bytes > kMaxPayloadBytes || bytes > size - result.valid - kHeaderBytes - kTrailerBytes) break;  // cut short
    record.resize(kHeaderBytes + bytes + kTrailerBytes);
    if (!in.read(record.data() + kHeaderBytes, static_cast<std::streamsize>(bytes + kTrailerBytes))) break;
    const std::string_view whole(record.data(), kHeaderBytes + bytes);
    if (fnv1a(whole) != get<std::uint64_t>(record.data() + kHeaderBytes + bytes) || kind < 1 || kind > 3) {
      result.damaged = true;
      break;
    }
    if (step > through) break;
    if (visit) visit({static_cast<RecordKind>(kind), static_cast<long>(step), whole.substr(kHeaderBytes)});
    result.valid += record.size();
  }
  return result;
}

}  // namespace

FrameLog::FrameLog(std::string path, long keep_through_step) : path_(std::move(path)) {
  fd_ = ::open(path_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd_ < 0) throw failure(path_, "cannot open the frame log");
  const off_t end = ::lseek(fd_, 0, SEEK_END);
  if (end < 0) throw failure(path_, "cannot size the frame log");
  size_ = scan(path_, static_cast<std::uint64_t>(end), keep_through_step, nullptr).valid;
  if (::ftruncate(fd_, static_cast<off_t>(size_)) != 0 || ::lseek(fd_, static_cast<off_t>(size_), SEEK_SET) < 0)
    throw failure(path_, "cannot cut the frame log");
}

FrameLog::~FrameLog() {
  if (fd_ >= 0) ::close(fd_);
}

void FrameLog::append(RecordKind kind, long step, std::string_view payload) {
  std::string record;
  record.reserve(kHeaderBytes + payload.size() + kTrailerBytes);
  record.append(kMagic, 4);
  put(record, static_cast<std::uint32_t>(kind));
  put(record, static_cast<std::int64_t>(step));
  put(record, static_cast<std::uint64_t>(payload.size()));
  record.append(payload);
  put(record, fnv1a(record));
  std::lock_guard lock(mutex_);
  std::size_t written = 0;
  while (written < record.size()) {
    const ssize_t n = ::write(fd_, record.data() + written, record.size() - written);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const auto error = failure(path_, "cannot append to the frame log");
      // Cut back to the last whole record, so that the next append starts at a record boundary.
      if (::ftruncate(fd_, static_cast<off_t>(size_)) != 0 || ::lseek(fd_, static_cast<off_t>(size_), SEEK_SET) < 0)
        throw failure(path_, "cannot cut the frame log after a failed append");
      throw error;
    }
    written += static_cast<std::size_t>(n);
  }
  size_ += record.size();
}

void FrameLog::sync() {
  if (::fsync(fd_) != 0) throw failure(path_, "cannot sync the frame log");
}

std::uint64_t FrameLog::size() const {
  std::lock_guard lock(mutex_);
  return size_;
}

void read_frame_log(const std::string& path, std::uint64_t size, const std::function<void(const LogRecord&)>& visit) {
  const Scan result = scan(path, size, std::numeric_limits<long>::max(), visit);
  if (result.damaged || result.valid != size)
    throw std::runtime_error(path + ": damaged record at byte " + std::to_string(result.valid));
}

}  // namespace lbsolid::server::recording
