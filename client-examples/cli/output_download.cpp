#include "output_download.h"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "exit_codes.h"
#include "io/storage/sha256.h"

namespace lbsolid::cli {
namespace {

namespace fs = std::filesystem;
using lbsolid::v1::OutputFile;

constexpr int kAttempts = 5;  // a stream that breaks this often in one file is not transient
constexpr double kDownloadSeconds = 3600;  // a whole file: 1 GB at 0.3 MB/s
constexpr double kListingSeconds = 300;    // the least ListOutputs is given (see download_outputs)

std::string local_sha256(const fs::path& path) {
  std::error_code missing;
  if (!fs::is_regular_file(path, missing)) return "";
  return lbsolid::server::storage::sha256_file_hex(path.string());
}

// Appends the rest of `file` to `part` (which holds its first bytes), resuming after a broken stream.
void fetch_into(Daemon& daemon, const std::string& session_id, const OutputFile& file, const fs::path& part) {
  for (int attempt = 1;; ++attempt) {
    const long long have = static_cast<long long>(fs::exists(part) ? fs::file_size(part) : 0);
    lbsolid::v1::DownloadOutputRequest request;
    request.set_session_id(session_id);
    request.set_name(file.name());
    request.set_offset(have);
    request.set_sha256(file.sha256());
    request.set_chunk_bytes(3 << 20);
    grpc::ClientContext context;
    daemon.set_deadline(context, kDownloadSeconds);
    auto reader = daemon.stub().DownloadOutput(&context, request);
    std::ofstream out(part, std::ios::binary | std::ios::app);
    if (!out) throw CliError(kExitBadInput, part.string() + ": cannot write");
    lbsolid::v1::OutputChunk chunk;
    long long next = have;
    while (reader->Read(&chunk)) {
      if (chunk.offset() != next) {
        context.TryCancel();
        break;
      }
      out.write(chunk.data().data(), static_cast<std::streamsize>(chunk.data().size()));
      next += static_cast<long long>(chunk.data().size());
    }
    out.close();
    if (!out) throw CliError(kExitBadInput, part.string() + ": cannot write");
    const grpc::Status status = reader->Finish();
    if (status.ok() && next == file.bytes()) return;
    if (!status.ok() && (exit_code_for(status) != kExitTransient || attempt == kAttempts))
      throw RpcError("DownloadOutput", status);
    if (attempt == kAttempts) throw CliError(kExitTransient, file.name() + ": the download kept breaking off");
  }
}

}  // namespace

void prepare_output_directory(const std::string& dir) {
  std::error_code error;
  fs::create_directories(dir, error);
  if (error) throw CliError(kExitBadInput, dir + ": " + error.message());
  if (::access(dir.c_str(), W_OK) != 0) throw CliError(kExitBadInput, dir + ": " + std::strerror(errno));
}

std::vector<FileEntry> download_outputs(Daemon& daemon, const std::string& session_id, const std::string& dir,
                                        bool with_checkpoints) {
  lbsolid::v1::ListOutputsRequest list;
  list.set_session_id(session_id);
  // The daemon makes the files it lists from the run's logs first (an H5MD file of every frame, a
  // field file of every snapshot: seconds per GB), which --timeout's default 30 s does not always
  // cover: on a loaded machine a 300-step run of 60 bodies took longer. At least 300 s, as the
  // Python client's Session.outputs() allows.
  const auto listed = daemon.call("ListOutputs", &Stub::ListOutputs, list,
                                  std::max(daemon.options().timeout_s, kListingSeconds));
  // Parts left by an earlier attempt that was killed (their process ids are not this one's).
  std::error_code ignored;
  for (const auto& entry : fs::recursive_directory_iterator(dir, ignored))
    if (entry.path().filename().string().starts_with(".") &&
        entry.path().filename().string().find(".part-") != std::string::npos)
      fs::remove(entry.path(), ignored);
  std::vector<FileEntry> files;
  for (const auto& file : listed.files()) {
    if (!with_checkpoints && file.name().starts_with("checkpoints/")) continue;
    const fs::path target = fs::path(dir) / file.name();
    if (local_sha256(target) != file.sha256()) {
      fs::create_directories(target.parent_path());
      const fs::path part = target.parent_path() / ("." + target.filename().string() + ".part-" + std::to_string(getpid()));
      fs::remove(part);
      fetch_into(daemon, session_id, file, part);
      if (local_sha256(part) != file.sha256()) {
        fs::remove(part);
        throw CliError(kExitTransient, file.name() + ": the copy does not match the daemon's SHA-256");
      }
      fs::rename(part, target);
    }
    files.push_back({file.name(), static_cast<std::uintmax_t>(file.bytes()), file.sha256()});
  }
  return files;
}

}  // namespace lbsolid::cli
