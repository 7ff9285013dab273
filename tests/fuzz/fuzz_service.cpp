// libFuzzer target: the daemon's request handling without the network. Each input makes a fresh
// SessionManager (one worker, small limits, no autosave, a private data directory emptied after the
// input) and a SimulationService over it, then calls the service's unary methods directly, each
// with a default grpc::ServerContext and a request parsed from the input (format: service_calls.h),
// so a sequence can create a session, step it, checkpoint, restore, delete, ...
//
// Session ids are 128 random bits, which no fuzzer guesses, so a request can refer to what earlier
// calls of the same input answered: a session_id "$" followed by a byte b and any tail is replaced
// by the (b mod n)-th of the n session ids answered so far, followed by the tail; a checkpoint_id
// "$" b tail likewise by a checkpoint id answered so far (with no id answered yet, it stays as it
// is, an invalid id like any other).
//
// State is bounded: at most kMaxCalls calls, 4 sessions of at most 8192 nodes and 2^14 particles,
// 256 MiB of estimated memory, Step of at most 4 steps; a Run goes on in the background only until
// the input ends and the manager stops its worker.
//
// Oracles: nothing crashes or trips a sanitizer, no call answers UNKNOWN, INTERNAL, DATA_LOSS or
// UNIMPLEMENTED, and every answer serializes.
#include <grpc/grpc.h>
#include <grpcpp/server_context.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include <unistd.h>

#include "fuzz/fuzz_logging.h"
#include "fuzz/service_calls.h"
#include "server/service/simulation_service.h"
#include "server/session/session_manager.h"

namespace {

namespace fs = std::filesystem;
namespace pb = google::protobuf;
namespace v1 = lbsolid::v1;
using lbsolid::fuzz::Method;

fs::path data_dir;

void remove_data_dir() {
  std::error_code ignored;
  fs::remove_all(data_dir, ignored);
}

// LBSOLID_FUZZ_TRACE=1 prints each call and its answer (for reading a regression input).
const bool trace = std::getenv("LBSOLID_FUZZ_TRACE") != nullptr;

// UNKNOWN (an exception escaped), INTERNAL (something the daemon did itself failed, e.g. writing a
// checkpoint into its own healthy data directory), DATA_LOSS (a file the daemon wrote in this very
// input does not read back: nothing else writes to this data directory) and UNIMPLEMENTED are
// bugs; the other codes are answers the API documents.
void check_status(const grpc::Status& status, int method) {
  switch (status.error_code()) {
    case grpc::StatusCode::UNKNOWN:
    case grpc::StatusCode::INTERNAL:
    case grpc::StatusCode::DATA_LOSS:
    case grpc::StatusCode::UNIMPLEMENTED:
      std::fprintf(stderr, "fuzz oracle failed: method %d answered code %d: %s\n", method,
                   static_cast<int>(status.error_code()), status.error_message().c_str());
      std::abort();
    default:
      return;
  }
}

// The ids answered so far in this input.
struct Answered {
  std::vector<std::string> sessions;
  std::vector<std::string> checkpoints;

  // Each id once, in the order first answered: the first session created is "$\0".
  void note(const pb::Message& response) {
    if (const auto* s = dynamic_cast<const v1::Session*>(&response)) add(sessions, s->id());
    if (const auto* s = dynamic_cast<const v1::StepResponse*>(&response)) add(sessions, s->session().id());
    if (const auto* c = dynamic_cast<const v1::CheckpointResponse*>(&response)) add(checkpoints, c->checkpoint_id());
  }
  static void add(std::vector<std::string>& ids, const std::string& id) {
    if (!id.empty() && std::find(ids.begin(), ids.end(), id) == ids.end()) ids.push_back(id);
  }

  // "$" b tail -> ids[b mod n] + tail, in the request's session_id or checkpoint_id.
  void resolve(pb::Message& request) const {
    const pb::Descriptor* type = request.GetDescriptor();
    const pb::Reflection* reflection = request.GetReflection();
    for (const char* name : {"session_id", "checkpoint_id"}) {
      const pb::FieldDescriptor* field = type->FindFieldByName(name);
      if (!field) continue;
      const auto& ids = std::string(name) == "session_id" ? sessions : checkpoints;
      const std::string value = reflection->GetString(request, field);
      if (value.size() < 2 || value[0] != '$' || ids.empty()) continue;
      const std::string& id = ids[static_cast<unsigned char>(value[1]) % ids.size()];
      reflection->SetString(&request, field, id + value.substr(2));
    }
  }
};

template <typename Request, typename Response, typename Call>
void call(const std::string& payload, int method, Answered& answered, Call&& invoke) {
  Request request;
  if (!request.ParseFromString(payload)) return;
  answered.resolve(request);
  Response response;
  grpc::ServerContext context;
  const grpc::Status status = invoke(&context, &request, &response);
  if (trace)
    std::fprintf(stderr, "call %s {%s} -> %d %s {%s}\n", Request::descriptor()->name().c_str(),
                 request.ShortDebugString().substr(0, 300).c_str(), static_cast<int>(status.error_code()),
                 status.error_message().c_str(), response.ShortDebugString().substr(0, 300).c_str());
  check_status(status, method);
  std::string wire;
  if (!response.SerializeToString(&wire)) {
    std::fprintf(stderr, "fuzz oracle failed: method %d's answer does not serialize\n", method);
    std::abort();
  }
  if (status.ok()) answered.note(response);
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  lbsolid::fuzz::quiet_logging();
  grpc_init();
  data_dir = fs::temp_directory_path() / ("lbsolid-fuzz-service-" + std::to_string(getpid()));
  remove_data_dir();
  std::atexit(remove_data_dir);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (data_dir.empty()) LLVMFuzzerInitialize(nullptr, nullptr);  // drivers that skip the hook
  lbsolid::server::ManagerLimits limits;
  limits.workers = 1;
  limits.max_sessions = 4;
  limits.max_cells = 8192;
  limits.max_sync_steps = 4;
  limits.max_memory_bytes = 256LL << 20;
  limits.max_particles = 1LL << 14;
  limits.max_fluid_threads = 2;
  limits.autosave_interval = std::chrono::milliseconds(0);  // off: the input alone decides what happens
  {
    lbsolid::server::SessionManager manager(data_dir.string(), limits, {"fuzz", "fuzz"});
    // No tokens, no client certificates: every call is the local admin's, as on a loopback daemon.
    lbsolid::server::SimulationService service(
        manager, std::make_shared<const lbsolid::server::auth::Authenticator>(nullptr, false));
    using S = lbsolid::server::SimulationService;
    Answered answered;
    std::size_t at = 0;
    for (int calls = 0; calls < lbsolid::fuzz::kMaxCalls && at + 3 <= size; ++calls) {
      const int method = data[at] % lbsolid::fuzz::kMethodCount;
      const std::size_t length = data[at + 1] | (std::size_t{data[at + 2]} << 8);
      at += 3;
      if (at + length > size) break;
      const std::string payload(reinterpret_cast<const char*>(data + at), length);
      at += length;
      auto bind = [&service](auto member) {
        return [&service, member](auto* context, auto* request, auto* response) {
          return (service.*member)(context, request, response);
        };
      };
      switch (static_cast<Method>(method)) {
        case Method::kCreateSession:
          call<v1::CreateSessionRequest, v1::Session>(payload, method, answered, bind(&S::CreateSession));
          break;
        case Method::kGetSession:
          call<v1::GetSessionRequest, v1::Session>(payload, method, answered, bind(&S::GetSession));
          break;
        case Method::kListSessions:
          call<v1::ListSessionsRequest, v1::ListSessionsResponse>(payload, method, answered, bind(&S::ListSessions));
          break;
        case Method::kDeleteSession:
          call<v1::DeleteSessionRequest, v1::DeleteSessionResponse>(payload, method, answered,
                                                                    bind(&S::DeleteSession));
          break;
        case Method::kRun:
          call<v1::RunRequest, v1::Session>(payload, method, answered, bind(&S::Run));
          break;
        case Method::kStep:
          call<v1::StepRequest, v1::StepResponse>(payload, method, answered, bind(&S::Step));
          break;
        case Method::kPause:
          call<v1::PauseRequest, v1::Session>(payload, method, answered, bind(&S::Pause));
          break;
        case Method::kResume:
          call<v1::ResumeRequest, v1::Session>(payload, method, answered, bind(&S::Resume));
          break;
        case Method::kCancel:
          call<v1::CancelRequest, v1::Session>(payload, method, answered, bind(&S::Cancel));
          break;
        case Method::kCheckpoint:
          call<v1::CheckpointRequest, v1::CheckpointResponse>(payload, method, answered, bind(&S::Checkpoint));
          break;
        case Method::kRestore:
          call<v1::RestoreRequest, v1::Session>(payload, method, answered, bind(&S::Restore));
          break;
        case Method::kGetServerInfo:
          call<v1::GetServerInfoRequest, v1::ServerInfo>(payload, method, answered, bind(&S::GetServerInfo));
          break;
        case Method::kValidateScenario:
          call<v1::ValidateScenarioRequest, v1::ValidateScenarioResponse>(payload, method, answered,
                                                                          bind(&S::ValidateScenario));
          break;
        case Method::kListOutputs:  // makes the recorded files of scenario.outputs from the frame log
          call<v1::ListOutputsRequest, v1::ListOutputsResponse>(payload, method, answered, bind(&S::ListOutputs));
          break;
      }
    }
  }  // the manager stops its worker here
  remove_data_dir();
  return 0;
}
