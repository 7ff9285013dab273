#pragma once
// The lbsolid.v1.Simulation service: checks each request's fields (naming the field in every
// INVALID_ARGUMENT), hands the work to the SessionManager and its sessions, and pumps stream
// frames to clients until the session ends, the client cancels, or the daemon stops.
#include <memory>
#include <string>
#include <string_view>

#include "lbsolid/v1/simulation.grpc.pb.h"
#include "server/auth/authenticator.h"
#include "server/auth/call_rate_limiter.h"
#include "server/session/session_manager.h"

namespace lbsolid::server {

// A call refused by the per-owner call rate carries, in this trailing metadata key, the
// milliseconds until a call would pass.
inline constexpr std::string_view kRetryAfterKey = "lbsolid-retry-after-ms";

class SimulationService final : public v1::Simulation::Service {
 public:
  // endpoint: where clients reach this daemon (--advertise_address), told in every Session and
  // in ServerInfo; empty when the daemon does not advertise one.
  SimulationService(SessionManager& manager, std::shared_ptr<const auth::Authenticator> authenticator,
                    auth::CallRateLimits call_limits = {}, std::string endpoint = "")
      : manager_(manager),
        authenticator_(std::move(authenticator)),
        call_limiter_(call_limits),
        endpoint_(std::move(endpoint)) {}

  grpc::Status CreateSession(grpc::ServerContext*, const v1::CreateSessionRequest*, v1::Session*) override;
  grpc::Status ValidateScenario(grpc::ServerContext*, const v1::ValidateScenarioRequest*,
                                v1::ValidateScenarioResponse*) override;
  grpc::Status GetSession(grpc::ServerContext*, const v1::GetSessionRequest*, v1::Session*) override;
  grpc::Status ListSessions(grpc::ServerContext*, const v1::ListSessionsRequest*, v1::ListSessionsResponse*) override;
  grpc::Status UploadCheckpoint(grpc::ServerContext*, grpc::ServerReader<v1::UploadCheckpointChunk>*,
                                v1::Session*) override;
  grpc::Status ListOutputs(grpc::ServerContext*, const v1::ListOutputsRequest*, v1::ListOutputsResponse*) override;
  grpc::Status DownloadOutput(grpc::ServerContext*, const v1::DownloadOutputRequest*,
                              grpc::ServerWriter<v1::OutputChunk>*) override;
  grpc::Status DeleteSession(grpc::ServerContext*, const v1::DeleteSessionRequest*, v1::DeleteSessionResponse*) override;
  grpc::Status Run(grpc::ServerContext*, const v1::RunRequest*, v1::Session*) override;
  grpc::Status Step(grpc::ServerContext*, const v1::StepRequest*, v1::StepResponse*) override;
  grpc::Status Pause(grpc::ServerContext*, const v1::PauseRequest*, v1::Session*) override;
  grpc::Status Resume(grpc::ServerContext*, const v1::ResumeRequest*, v1::Session*) override;
  grpc::Status Cancel(grpc::ServerContext*, const v1::CancelRequest*, v1::Session*) override;
  grpc::Status WatchSession(grpc::ServerContext*, const v1::WatchSessionRequest*,
                            grpc::ServerWriter<v1::SessionEvent>*) override;
  grpc::Status WatchProfiles(grpc::ServerContext*, const v1::WatchProfilesRequest*,
                             grpc::ServerWriter<v1::ProfileFrame>*) override;
  grpc::Status WatchParticles(grpc::ServerContext*, const v1::WatchParticlesRequest*,
                              grpc::ServerWriter<v1::ParticleFrame>*) override;
  grpc::Status GetField(grpc::ServerContext*, const v1::GetFieldRequest*, grpc::ServerWriter<v1::FieldMessage>*) override;
  grpc::Status Checkpoint(grpc::ServerContext*, const v1::CheckpointRequest*, v1::CheckpointResponse*) override;
  grpc::Status Restore(grpc::ServerContext*, const v1::RestoreRequest*, v1::Session*) override;
  grpc::Status GetServerInfo(grpc::ServerContext*, const v1::GetServerInfoRequest*, v1::ServerInfo*) override;

 private:
  // Applies `change` (if any) to the session and answers with its description.
  grpc::Status change_state(const std::string& id, const auth::Identity& caller, absl::Status (Session::*change)(),
                            v1::Session* response);
  // Every call's first step: who makes it (UNAUTHENTICATED if nobody known), charged to the
  // owner's call rate (RESOURCE_EXHAUSTED, with kRetryAfterKey, past it).
  absl::StatusOr<auth::Identity> admit(grpc::ServerContext& context);
  // For the methods that change state: admits the call, runs `body` as its caller and, on a
  // daemon that authenticates callers, logs one audit line (owner, method, session, outcome).
  template <class SessionId, class Body>
  grpc::Status audited(grpc::ServerContext& context, const char* method, const SessionId& session_id,
                       const Body& body);

  // The session's description as clients get it: with this daemon's endpoint.
  v1::Session describe(const Session& session, bool with_scenario = true) const;

  SessionManager& manager_;
  const std::shared_ptr<const auth::Authenticator> authenticator_;
  auth::CallRateLimiter call_limiter_;
  const std::string endpoint_;
};

}  // namespace lbsolid::server
