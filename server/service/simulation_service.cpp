#include "server/service/simulation_service.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <bit>
#include <chrono>
#include <cstring>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include "absl/strings/str_cat.h"
#include "io/api/error_summary.h"
#include "io/api/log_text.h"
#include "server/auth/caller.h"
#include "io/storage/sha256.h"

namespace lbsolid::server {

namespace {

using auth::caller_of;

using std::chrono::milliseconds;

constexpr long kDefaultChunkBytes = 1L << 20;
constexpr std::size_t kMaxListedBytes = 3 << 20;  // ValidateScenario's lists: under the 4 MiB message limit
constexpr long kMinChunkBytes = 1L << 10;
constexpr long kMaxChunkBytes = 3L << 20;  // leaves room under the 4 MiB message limit
constexpr double kMinProgressInterval = 0.05;  // seconds
constexpr double kMaxProgressInterval = 3600;  // an hour: past it, the milliseconds could overflow

// A status message travels as a header, which clients refuse past their metadata limit (8 KiB by
// default) as RESOURCE_EXHAUSTED, a code they retry: every message is cut to kMaxSummaryBytes
// (error_summary.h), whatever produced it.
grpc::Status to_grpc(const absl::Status& status) {
  if (status.ok()) return grpc::Status::OK;
  const std::string message(status.message());
  if (message.size() <= kMaxSummaryBytes)  // error_summary()'s lists, whole: their count of the rest included
    return grpc::Status(static_cast<grpc::StatusCode>(status.code()), message);
  std::string text = message.substr(0, utf8_prefix_size(message, kMaxSummaryBytes - 32));
  text += absl::StrCat("... (", message.size(), " bytes)");
  return grpc::Status(static_cast<grpc::StatusCode>(status.code()), text);
}

grpc::Status invalid(const std::string& message) { return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT, message); }

grpc::Status require_id(const std::string& id) {
  return id.empty() ? invalid("session_id: required") : grpc::Status::OK;
}

absl::StatusOr<Delivery> delivery_of(v1::DeliveryMode mode) {
  switch (mode) {
    case v1::DELIVERY_MODE_UNSPECIFIED:
    case v1::DELIVERY_MODE_LATEST_FRAME: return Delivery::kLatestFrame;
    case v1::DELIVERY_MODE_EVERY_FRAME: return Delivery::kEveryFrame;
    default: return absl::InvalidArgumentError(absl::StrCat("delivery: unknown mode ", static_cast<int>(mode)));
  }
}

// Sends what a channel yields until it ends, the client cancels or the daemon stops.
template <class Message, class Channel>
grpc::Status pump(grpc::ServerContext* context, Channel& channel, grpc::ServerWriter<Message>* writer) {
  bool finished = false;
  while (!context->IsCancelled()) {
    auto message = channel.next(milliseconds(100), &finished);
    if (message) {
      if (!writer->Write(*message)) break;
    } else if (finished) {
      return grpc::Status::OK;
    }
  }
  return grpc::Status(grpc::StatusCode::CANCELLED, "the stream was cancelled");
}

}  // namespace

absl::StatusOr<auth::Identity> SimulationService::admit(grpc::ServerContext& context) {
  auto caller = caller_of(context, *authenticator_);
  if (!caller.ok() || !call_limiter_.limits_calls()) return caller;
  std::chrono::milliseconds retry_after{0};
  if (auto charged = call_limiter_.charge(caller->owner, auth::CallRateLimiter::Clock::now(), &retry_after);
      !charged.ok()) {
    context.AddTrailingMetadata(std::string(kRetryAfterKey), std::to_string(retry_after.count()));
    return charged;
  }
  return caller;
}

template <class SessionId, class Body>
grpc::Status SimulationService::audited(grpc::ServerContext& context, const char* method,
                                        const SessionId& session_id, const Body& body) {
  const auto caller = admit(context);
  if (!caller.ok()) return to_grpc(caller.status());
  const grpc::Status status = body(*caller);
  if (authenticator_->authenticates()) {
    const std::string outcome = status.ok() ? "OK" : absl::StatusCodeToString(static_cast<absl::StatusCode>(status.error_code()));
    spdlog::info("audit: owner {} ({}) {} session {}: {}", caller->owner,
                 caller->role == auth::Role::kAdmin ? "admin" : "user", method, log_text(session_id(), 100), outcome);
  }
  return status;
}

grpc::Status SimulationService::CreateSession(grpc::ServerContext* context, const v1::CreateSessionRequest* request,
                                              v1::Session* response) {
  return audited(*context, "CreateSession", [&] { return response->id(); }, [&](const auth::Identity& caller) -> grpc::Status {
    if (!request->has_scenario()) return invalid("scenario: required");
    auto session = manager_.create(request->scenario(), request->request_id(), caller);
    if (!session.ok()) {
      spdlog::warn("CreateSession refused: {}", log_text(std::string(session.status().message()), 1000));
      return to_grpc(session.status());
    }
    *response = describe(**session);
    return grpc::Status::OK;
  });
}

grpc::Status SimulationService::ValidateScenario(grpc::ServerContext* context, const v1::ValidateScenarioRequest* request,
                                                 v1::ValidateScenarioResponse* response) {
  const auto caller = admit(*context);
  if (!caller.ok()) return to_grpc(caller.status());
  if (!request->has_scenario()) return invalid("scenario: required");
  const TranslatedScenario checked = manager_.validate(request->scenario());
  // Every problem and warning, as long as the answer stays under the message limit (a request of
  // up to 4 MiB can yield more text than that); the totals count them all.
  std::size_t bytes = 0;
  const auto fits = [&](const std::string& text) {
    bytes += text.size() + 8;  // with the field's tag and length
    return bytes <= kMaxListedBytes;
  };
  for (const auto& problem : checked.errors) {
    if (!fits(problem)) break;
    response->add_problems(problem);
  }
  for (const auto& warning : checked.warnings) {
    if (!fits(warning)) break;
    response->add_warnings(warning);
  }
  response->set_problems_total(static_cast<long>(checked.errors.size()));
  response->set_warnings_total(static_cast<long>(checked.warnings.size()));
  return grpc::Status::OK;
}

grpc::Status SimulationService::GetSession(grpc::ServerContext* context, const v1::GetSessionRequest* request,
                                           v1::Session* response) {
  const auto caller = admit(*context);
  if (!caller.ok()) return to_grpc(caller.status());
  if (auto s = require_id(request->session_id()); !s.ok()) return s;
  auto session = manager_.find(request->session_id(), *caller);
  if (!session.ok()) return to_grpc(session.status());
  *response = describe(**session);
  return grpc::Status::OK;
}

grpc::Status SimulationService::ListSessions(grpc::ServerContext* context, const v1::ListSessionsRequest*,
                                             v1::ListSessionsResponse* response) {
  const auto caller = admit(*context);
  if (!caller.ok()) return to_grpc(caller.status());
  std::vector<v1::Session> sessions;
  for (const auto& session : manager_.list(*caller)) sessions.push_back(describe(*session, /*with_scenario=*/false));
  std::stable_sort(sessions.begin(), sessions.end(),
                   [](const auto& a, const auto& b) { return a.created_unix_ms() < b.created_unix_ms(); });
  for (auto& session : sessions) *response->add_sessions() = std::move(session);
  return grpc::Status::OK;
}

grpc::Status SimulationService::DeleteSession(grpc::ServerContext* context, const v1::DeleteSessionRequest* request,
                                              v1::DeleteSessionResponse*) {
  return audited(*context, "DeleteSession", [&] { return request->session_id(); }, [&](const auth::Identity& caller) -> grpc::Status {
    if (auto s = require_id(request->session_id()); !s.ok()) return s;
    return to_grpc(manager_.remove(request->session_id(), caller));
  });
}

grpc::Status SimulationService::Run(grpc::ServerContext* context, const v1::RunRequest* request, v1::Session* response) {
  return audited(*context, "Run", [&] { return request->session_id(); }, [&](const auth::Identity& caller) -> grpc::Status {
    if (auto s = require_id(request->session_id()); !s.ok()) return s;
    if (request->steps() < 1) return invalid(absl::StrCat("steps: must be at least 1, got ", request->steps()));
    if (auto status = manager_.run(request->session_id(), request->steps(), caller); !status.ok()) return to_grpc(status);
    auto session = manager_.find(request->session_id(), caller);
    if (!session.ok()) return to_grpc(session.status());
    *response = describe(**session);
    return grpc::Status::OK;
  });
}

grpc::Status SimulationService::Step(grpc::ServerContext* context, const v1::StepRequest* request,
                                     v1::StepResponse* response) {
  return audited(*context, "Step", [&] { return request->session_id(); }, [&](const auth::Identity& caller) -> grpc::Status {
    if (auto s = require_id(request->session_id()); !s.ok()) return s;
    const long most = manager_.limits().max_sync_steps;
    if (request->steps() < 1 || request->steps() > most)
      return invalid(absl::StrCat("steps: must lie in [1, ", most, "] for Step (use Run for more), got ", request->steps()));
    auto session = manager_.find(request->session_id(), caller);
    if (!session.ok()) return to_grpc(session.status());
    auto result =
        (*session)->step_now(request->steps(), context->deadline(), [context] { return context->IsCancelled(); });
    if (!result.ok()) return to_grpc(result.status());
    manager_.settle(**session);  // it may have failed, or been cancelled meanwhile
    if (context->IsCancelled()) return grpc::Status(grpc::StatusCode::CANCELLED, "the call was cancelled");
    if (!manager_.find(request->session_id(), caller).ok())
      return grpc::Status(grpc::StatusCode::NOT_FOUND,
                          absl::StrCat("session_id: session ", request->session_id(), " was deleted during the Step"));
    response->set_steps_taken(result->steps_taken);
    response->set_deadline_reached(result->deadline_reached);
    response->set_interrupted(result->interrupted);
    *response->mutable_session() = describe(**session);
    return grpc::Status::OK;
  });
}

grpc::Status SimulationService::Pause(grpc::ServerContext* context, const v1::PauseRequest* request, v1::Session* response) {
  return audited(*context, "Pause", [&] { return request->session_id(); }, [&](const auth::Identity& caller) -> grpc::Status {
    return change_state(request->session_id(), caller, &Session::pause, response);
  });
}

grpc::Status SimulationService::Resume(grpc::ServerContext* context, const v1::ResumeRequest* request, v1::Session* response) {
  return audited(*context, "Resume", [&] { return request->session_id(); }, [&](const auth::Identity& caller) -> grpc::Status {
    if (auto s = require_id(request->session_id()); !s.ok()) return s;
    if (auto status = manager_.resume(request->session_id(), caller); !status.ok()) return to_grpc(status);
    return change_state(request->session_id(), caller, nullptr, response);
  });
}

grpc::Status SimulationService::Cancel(grpc::ServerContext* context, const v1::CancelRequest* request, v1::Session* response) {
  return audited(*context, "Cancel", [&] { return request->session_id(); }, [&](const auth::Identity& caller) -> grpc::Status {
    if (auto s = require_id(request->session_id()); !s.ok()) return s;
    if (auto status = manager_.cancel(request->session_id(), caller); !status.ok()) return to_grpc(status);
    return change_state(request->session_id(), caller, nullptr, response);
  });
}

grpc::Status SimulationService::change_state(const std::string& id, const auth::Identity& caller,
                                             absl::Status (Session::*change)(), v1::Session* response) {
  if (auto s = require_id(id); !s.ok()) return s;
  auto session = manager_.find(id, caller);
  if (!session.ok()) return to_grpc(session.status());
  if (change)
    if (auto status = ((**session).*change)(); !status.ok()) return to_grpc(status);
  *response = describe(**session);
  return grpc::Status::OK;
}

grpc::Status SimulationService::WatchSession(grpc::ServerContext* context, const v1::WatchSessionRequest* request,
                                             grpc::ServerWriter<v1::SessionEvent>* writer) {
  const auto caller = admit(*context);
  if (!caller.ok()) return to_grpc(caller.status());
  if (auto s = require_id(request->session_id()); !s.ok()) return s;
  double interval = request->progress_interval_s();
  if (interval == 0) interval = 1.0;
  if (!(interval >= kMinProgressInterval && interval <= kMaxProgressInterval))
    return invalid(absl::StrCat("progress_interval_s: must lie in [", kMinProgressInterval, ", ", kMaxProgressInterval,
                                "] seconds, got ", request->progress_interval_s()));
  auto session = manager_.find(request->session_id(), *caller);
  if (!session.ok()) return to_grpc(session.status());
  auto channel = (*session)->watch_events(milliseconds(static_cast<long>(interval * 1000)));
  return pump(context, *channel, writer);
}

grpc::Status SimulationService::WatchProfiles(grpc::ServerContext* context, const v1::WatchProfilesRequest* request,
                                              grpc::ServerWriter<v1::ProfileFrame>* writer) {
  const auto caller = admit(*context);
  if (!caller.ok()) return to_grpc(caller.status());
  if (auto s = require_id(request->session_id()); !s.ok()) return s;
  if (request->every() < 1) return invalid(absl::StrCat("every: must be at least 1, got ", request->every()));
  const auto delivery = delivery_of(request->delivery());
  if (!delivery.ok()) return to_grpc(delivery.status());
  auto session = manager_.find(request->session_id(), *caller);
  if (!session.ok()) return to_grpc(session.status());
  auto channel = (*session)->watch_profiles(request->every(), *delivery);
  if (!channel.ok()) return to_grpc(channel.status());
  const auto status = pump(context, **channel, writer);
  (*channel)->detach();
  return status;
}

grpc::Status SimulationService::WatchParticles(grpc::ServerContext* context, const v1::WatchParticlesRequest* request,
                                               grpc::ServerWriter<v1::ParticleFrame>* writer) {
  const auto caller = admit(*context);
  if (!caller.ok()) return to_grpc(caller.status());
  if (auto s = require_id(request->session_id()); !s.ok()) return s;
  if (request->every() < 1) return invalid(absl::StrCat("every: must be at least 1, got ", request->every()));
  const auto delivery = delivery_of(request->delivery());
  if (!delivery.ok()) return to_grpc(delivery.status());
  auto session = manager_.find(request->session_id(), *caller);
  if (!session.ok()) return to_grpc(session.status());
  const std::vector<std::string> bodies(request->bodies().begin(), request->bodies().end());
  auto channel = (*session)->watch_particles(request->every(), *delivery, bodies);
  if (!channel.ok()) return to_grpc(channel.status());
  const auto status = pump(context, **channel, writer);
  (*channel)->detach();
  return status;
}

grpc::Status SimulationService::GetField(grpc::ServerContext* context, const v1::GetFieldRequest* request,
                                         grpc::ServerWriter<v1::FieldMessage>* writer) {
  const auto caller = admit(*context);
  if (!caller.ok()) return to_grpc(caller.status());
  static_assert(std::endian::native == std::endian::little, "field chunks are sent as the machine stores them");
  if (auto s = require_id(request->session_id()); !s.ok()) return s;
  long chunk = request->chunk_bytes() == 0 ? kDefaultChunkBytes : request->chunk_bytes();
  if (chunk < kMinChunkBytes || chunk > kMaxChunkBytes)
    return invalid(absl::StrCat("chunk_bytes: must lie in [", kMinChunkBytes, ", ", kMaxChunkBytes, "], got ",
                                request->chunk_bytes()));
  std::vector<std::string> names(request->fields().begin(), request->fields().end());
  if (names.empty()) names = {"density", "velocity"};
  for (std::size_t k = 0; k < names.size(); ++k)
    if (names[k] != "density" && names[k] != "velocity")
      return invalid(absl::StrCat("fields[", k, "]: unknown field \"", names[k], "\"; use density or velocity"));
  auto session = manager_.find(request->session_id(), *caller);
  if (!session.ok()) return to_grpc(session.status());
  auto snapshot = (*session)->fields();
  if (!snapshot.ok()) return to_grpc(snapshot.status());
  const std::shared_ptr<const FieldData> data = *std::move(snapshot);
  const auto& shape = data->fields.shape;
  for (const auto& name : names) {
    const bool vector = name == "velocity";
    const auto& values = vector ? data->fields.velocity : data->fields.density;
    v1::FieldMessage header_message;
    auto* header = header_message.mutable_header();
    header->set_name(name);
    for (long extent : {static_cast<long>(shape[2]), static_cast<long>(shape[1]), static_cast<long>(shape[0])})
      header->add_shape(extent);
    if (vector) header->add_shape(3);
    header->set_dtype("float64");
    header->set_step(data->step);
    header->set_total_bytes(static_cast<long>(values.size() * sizeof(double)));
    header->mutable_spacing()->set_x(data->spacing[0]);
    header->mutable_spacing()->set_y(data->spacing[1]);
    header->mutable_spacing()->set_z(data->spacing[2]);
    if (!writer->Write(header_message)) return grpc::Status(grpc::StatusCode::CANCELLED, "the stream was cancelled");
    const auto* bytes = reinterpret_cast<const char*>(values.data());
    const long total = header->total_bytes();
    v1::FieldMessage message;  // one for every chunk: its buffer is reused, not allocated and faulted in each time
    for (long offset = 0; offset < total; offset += chunk) {
      if (context->IsCancelled()) return grpc::Status(grpc::StatusCode::CANCELLED, "the stream was cancelled");
      message.mutable_chunk()->set_offset(offset);
      message.mutable_chunk()->set_data(bytes + offset, std::min(chunk, total - offset));
      if (!writer->Write(message)) return grpc::Status(grpc::StatusCode::CANCELLED, "the stream was cancelled");
    }
  }
  return grpc::Status::OK;
}

grpc::Status SimulationService::ListOutputs(grpc::ServerContext* context, const v1::ListOutputsRequest* request,
                                            v1::ListOutputsResponse* response) {
  const auto caller = admit(*context);
  if (!caller.ok()) return to_grpc(caller.status());
  if (auto s = require_id(request->session_id()); !s.ok()) return s;
  auto session = manager_.find(request->session_id(), *caller);
  if (!session.ok()) return to_grpc(session.status());
  *response->mutable_session() = describe(**session, /*with_scenario=*/false);
  auto files = manager_.outputs(request->session_id(), *caller);
  if (!files.ok()) return to_grpc(files.status());
  for (const auto& file : *files) {
    auto* out = response->add_files();
    out->set_name(file.name);
    out->set_bytes(file.bytes);
    out->set_sha256(file.sha256);
  }
  return grpc::Status::OK;
}

grpc::Status SimulationService::DownloadOutput(grpc::ServerContext* context, const v1::DownloadOutputRequest* request,
                                               grpc::ServerWriter<v1::OutputChunk>* writer) {
  const auto caller = admit(*context);
  if (!caller.ok()) return to_grpc(caller.status());
  if (auto s = require_id(request->session_id()); !s.ok()) return s;
  if (request->name().empty()) return invalid("name: required (ListOutputs names the files)");
  const long chunk = request->chunk_bytes() == 0 ? kDefaultChunkBytes : request->chunk_bytes();
  if (chunk < kMinChunkBytes || chunk > kMaxChunkBytes)
    return invalid(absl::StrCat("chunk_bytes: must lie in [", kMinChunkBytes, ", ", kMaxChunkBytes, "], got ",
                                request->chunk_bytes()));
  auto files = manager_.outputs(request->session_id(), *caller);
  if (!files.ok()) return to_grpc(files.status());
  const auto file = std::find_if(files->begin(), files->end(), [&](const auto& f) { return f.name == request->name(); });
  if (file == files->end())
    return grpc::Status(grpc::StatusCode::NOT_FOUND,
                        absl::StrCat("name: session ", request->session_id(), " has no output \"",
                                     log_text(request->name(), 100), "\" (ListOutputs names them)"));
  if (!request->sha256().empty() && request->sha256() != file->sha256)
    return grpc::Status(grpc::StatusCode::FAILED_PRECONDITION,
                        absl::StrCat("sha256: ", file->name, " changed since that version (the session ran on); ",
                                     "download it again from offset 0"));
  if (request->offset() < 0 || request->offset() > file->bytes)
    return grpc::Status(grpc::StatusCode::OUT_OF_RANGE, absl::StrCat("offset: must lie in [0, ", file->bytes,
                                                                      "] for ", file->name, ", got ", request->offset()));
  // Opened once: a newer version renamed over it later does not change what this stream sends.
  const int fd = ::open(file->path.c_str(), O_RDONLY | O_CLOEXEC);
  struct stat info {};
  if (fd < 0 || ::fstat(fd, &info) != 0 || info.st_ino != file->inode) {
    if (fd >= 0) ::close(fd);
    return grpc::Status(grpc::StatusCode::ABORTED, absl::StrCat(file->name, ": replaced by a newer version while ",
                                                                "being opened; list the outputs again"));
  }
  grpc::Status status = grpc::Status::OK;
  v1::OutputChunk message;
  message.mutable_file()->set_name(file->name);
  message.mutable_file()->set_bytes(file->bytes);
  message.mutable_file()->set_sha256(file->sha256);
  std::string& data = *message.mutable_data();  // read into directly: its memory is reused for every chunk
  for (long long offset = request->offset();;) {
    data.resize(static_cast<std::size_t>(chunk));
    const ssize_t n = ::pread(fd, data.data(), data.size(), offset);
    if (n < 0) {
      status = grpc::Status(grpc::StatusCode::UNAVAILABLE, absl::StrCat(file->name, ": cannot read: ", std::strerror(errno)));
      break;
    }
    message.set_offset(offset);
    data.resize(static_cast<std::size_t>(n));
    if (context->IsCancelled() || !writer->Write(message)) {
      status = grpc::Status(grpc::StatusCode::CANCELLED, "the stream was cancelled");
      break;
    }
    offset += n;
    if (n == 0 || offset >= file->bytes) break;
    message.clear_file();
  }
  ::close(fd);
  return status;
}

grpc::Status SimulationService::Checkpoint(grpc::ServerContext* context, const v1::CheckpointRequest* request,
                                           v1::CheckpointResponse* response) {
  return audited(*context, "Checkpoint", [&] { return request->session_id(); }, [&](const auth::Identity& caller) -> grpc::Status {
    if (auto s = require_id(request->session_id()); !s.ok()) return s;
    auto info = manager_.checkpoint(request->session_id(), caller);
    if (!info.ok()) return to_grpc(info.status());
    response->set_checkpoint_id(info->checkpoint_id);
    response->set_path(info->path);
    response->set_step(info->step);
    response->set_bytes(info->bytes);
    return grpc::Status::OK;
  });
}

grpc::Status SimulationService::Restore(grpc::ServerContext* context, const v1::RestoreRequest* request, v1::Session* response) {
  return audited(*context, "Restore", [&] { return response->id(); }, [&](const auth::Identity& caller) -> grpc::Status {
    if (request->checkpoint_id().empty()) return invalid("checkpoint_id: required");
    auto session = manager_.restore(request->checkpoint_id(), request->request_id(), caller);
    if (!session.ok()) return to_grpc(session.status());
    *response = describe(**session);
    return grpc::Status::OK;
  });
}

namespace {

bool is_sha256_hex(const std::string& text) {
  return text.size() == 64 && std::all_of(text.begin(), text.end(), [](char c) {
           return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f');
         });
}

// The received bytes of an upload, in a file of its own under `dir`, removed with this object.
class UploadFile {
 public:
  explicit UploadFile(const std::string& dir) : path_(dir + "/upload-XXXXXX") {
    fd_ = ::mkstemp(path_.data());
  }
  ~UploadFile() {
    if (fd_ >= 0) ::close(fd_);
    ::unlink(path_.c_str());
  }
  bool ok() const { return fd_ >= 0; }
  const std::string& path() const { return path_; }
  bool append(const std::string& data) {
    for (std::size_t written = 0; written < data.size();) {
      const ssize_t n = ::write(fd_, data.data() + written, data.size() - written);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) return false;
      written += static_cast<std::size_t>(n);
    }
    return true;
  }

 private:
  std::string path_;
  int fd_ = -1;
};

}  // namespace

grpc::Status SimulationService::UploadCheckpoint(grpc::ServerContext* context,
                                                 grpc::ServerReader<v1::UploadCheckpointChunk>* reader,
                                                 v1::Session* response) {
  return audited(*context, "UploadCheckpoint", [&] { return response->id(); },
                 [&](const auth::Identity& caller) -> grpc::Status {
    v1::UploadCheckpointChunk chunk;
    if (!reader->Read(&chunk)) return invalid("bytes: the first message must name the file's size and sha256");
    const long long bytes = chunk.bytes();
    const std::string sha256 = chunk.sha256(), request_id = chunk.request_id();
    // A checkpoint holds the state a session keeps in memory: one the daemon could not hold is refused first.
    const long long most = manager_.limits().max_memory_bytes;
    if (bytes < 1) return invalid(absl::StrCat("bytes: the file's size, at least 1, got ", bytes));
    if (bytes > most)
      return grpc::Status(grpc::StatusCode::RESOURCE_EXHAUSTED,
                          absl::StrCat("bytes: ", bytes, " bytes, more than this daemon's ", most, " (--max_memory)"));
    if (!is_sha256_hex(sha256)) return invalid("sha256: must be the file's SHA-256 in 64 lowercase hex digits");
    UploadFile file(manager_.upload_dir());
    if (!file.ok())
      return grpc::Status(grpc::StatusCode::UNAVAILABLE, absl::StrCat("data: cannot store the upload: ", std::strerror(errno)));
    storage::Sha256 hash;
    long long received = 0;
    do {
      received += static_cast<long long>(chunk.data().size());
      if (received > bytes)
        return invalid(absl::StrCat("data: more than the ", bytes, " bytes the first message named"));
      hash.update(chunk.data());
      if (!file.append(chunk.data()))
        return grpc::Status(grpc::StatusCode::UNAVAILABLE,
                            absl::StrCat("data: cannot store the upload: ", std::strerror(errno)));
    } while (reader->Read(&chunk));
    if (context->IsCancelled()) return grpc::Status(grpc::StatusCode::CANCELLED, "the upload was cancelled");
    if (received != bytes)
      return invalid(absl::StrCat("data: ", received, " bytes arrived of the ", bytes, " named (cut short)"));
    if (const std::string got = hash.hex_digest(); got != sha256)
      return grpc::Status(grpc::StatusCode::DATA_LOSS,
                          absl::StrCat("data: the bytes received have SHA-256 ", got, ", not the ", sha256, " named"));
    auto session = manager_.restore_upload(file.path(), request_id, caller);
    if (!session.ok()) return to_grpc(session.status());
    *response = describe(**session);
    return grpc::Status::OK;
  });
}

grpc::Status SimulationService::GetServerInfo(grpc::ServerContext* context, const v1::GetServerInfoRequest*,
                                              v1::ServerInfo* response) {
  const auto caller = admit(*context);
  if (!caller.ok()) return to_grpc(caller.status());
  const auto& limits = manager_.limits();
  response->set_version(manager_.writer().version);
  response->set_git_revision(manager_.writer().git_revision);
  response->set_api_version("lbsolid.v1");
  for (const char* capability :
       {"lattice:D2Q9", "lattice:D2Q7", "lattice:D3Q19", "precision:double", "precision:float", "collision:bgk",
        "collision:trt", "collision:regularized", "exchange:common-velocity", "exchange:pairwise", "stream:profiles",
        "stream:particles", "field:density", "field:velocity", "checkpoint:hdf5"})
    response->add_capabilities(capability);
  response->set_workers(limits.workers);
  response->set_max_sessions(limits.max_sessions);
  response->set_max_cells(limits.max_cells);
  response->set_max_sync_steps(limits.max_sync_steps);
  response->set_max_message_bytes(4L << 20);
  response->set_sessions(static_cast<long>(manager_.list(*caller).size()));  // the caller's
  response->set_running_sessions(manager_.running_count());
  response->set_endpoint(endpoint_);
  return grpc::Status::OK;
}

v1::Session SimulationService::describe(const Session& session, bool with_scenario) const {
  v1::Session described = session.describe(with_scenario);
  described.set_endpoint(endpoint_);
  return described;
}

}  // namespace lbsolid::server
