// The daemon on a network (issue 13): TLS and mutual TLS with throwaway certificates made at test
// time, bearer tokens checked before a call reaches a session (right, wrong, missing, revoked by a
// reload on SIGHUP), safe defaults (no plaintext and no unauthenticated callers off loopback
// unless --allow_insecure), Unix sockets, audit lines without secrets, and owners that cannot
// reach each other's sessions through any RPC.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <thread>

#include "service/coreutils_sha256.h"
#include "service/daemon_process.h"
#include "service/refused_start.h"
#include "service/test_certificates.h"
#include "reflection.grpc.pb.h"
#include "service/test_scenarios.h"

namespace lbsolid::testing {
namespace {

using namespace std::chrono_literals;

// Tokens and the lines of a tokens file for them (hashes by coreutils' sha256sum).
std::string token_line(const std::string& token, const std::string& owner, const std::string& role) {
  return coreutils_sha256(token) + " " + owner + " " + role + "\n";
}

// What a client brings: the CA it trusts, and a bearer token or a client certificate.
struct Tls {
  std::string root;
  std::string token;
  std::string cert, key;
};

Tls with_token(const std::string& root, const std::string& token = "") { return {root, token, "", ""}; }
Tls with_certificate(const std::string& root, const std::string& cert, const std::string& key) {
  return {root, "", cert, key};
}

std::shared_ptr<grpc::ChannelCredentials> credentials_for(const Tls& tls) {
  grpc::SslCredentialsOptions ssl;
  ssl.pem_root_certs = file_text(tls.root);
  if (!tls.cert.empty()) {
    ssl.pem_cert_chain = file_text(tls.cert);
    ssl.pem_private_key = file_text(tls.key);
  }
  auto channel = grpc::SslCredentials(ssl);
  if (tls.token.empty()) return channel;
  return grpc::CompositeChannelCredentials(channel, grpc::AccessTokenCredentials(tls.token));
}

std::shared_ptr<grpc::Channel> channel_for(const DaemonProcess& daemon, const Tls& tls) {
  grpc::ChannelArguments args;
  args.SetInt(GRPC_ARG_USE_LOCAL_SUBCHANNEL_POOL, 1);  // a connection (and handshake) of its own
  return grpc::CreateCustomChannel(daemon.address(), credentials_for(tls), args);
}

std::unique_ptr<v1::Simulation::Stub> stub_for(const DaemonProcess& daemon, const Tls& tls) {
  return v1::Simulation::NewStub(channel_for(daemon, tls));
}

grpc::Status server_info(v1::Simulation::Stub& stub) {
  v1::ServerInfo info;
  auto context = deadline_context(5);
  return stub.GetServerInfo(context.get(), {}, &info);
}

std::string log_of(const std::string& path) { return file_text(path); }

// How a server stream ends when it sends nothing: its final status (a frame read is an error).
template <class Frame, class Request, class Open>
grpc::Status stream_status(v1::Simulation::Stub& stub, Open open, const Request& request) {
  auto context = deadline_context();
  auto reader = (stub.*open)(context.get(), request);
  Frame frame;
  if (reader->Read(&frame)) {
    context->TryCancel();
    reader->Finish();
    return grpc::Status(grpc::StatusCode::INTERNAL, "the stream sent a frame");
  }
  return reader->Finish();
}

class RemoteAccess : public ::testing::Test {
 protected:
  RemoteAccess() : dir_("lbsolid-remote"), certs_(make_test_certificates(dir_.path)) {
    write_tokens(token_line("alice-secret", "alice", "user") + token_line("bob-secret", "bob", "user") +
                 token_line("root-secret", "ops", "admin"));
  }
  void write_tokens(const std::string& text) { std::ofstream(tokens_) << text; }
  std::vector<std::string> tls_flags(const std::string& cert, const std::string& key) const {
    return {"--tls_cert=" + cert, "--tls_key=" + key, "--tokens_file=" + tokens_, "--log_level=info"};
  }
  ScopedDirectory dir_;
  TestCertificates certs_;
  const std::string tokens_ = dir_.path + "/tokens";
  const std::string log_ = dir_.path + "/daemon.log";
};

TEST_F(RemoteAccess, OffLoopbackPlaintextOrUnauthenticatedCallersAreRefusedUnlessAllowed) {
  expect_refused_start({"--listen=0.0.0.0:0"}, "--listen: 0.0.0.0:0 is not loopback or a Unix socket");
  expect_refused_start({"--listen=0.0.0.0:0", "--tls_cert=" + certs_.server_cert, "--tls_key=" + certs_.server_key},
                       "give --tokens_file or --tls_client_ca");
  expect_refused_start({"--tls_cert=" + certs_.server_cert}, "--tls_cert, --tls_key: give both or neither");
  expect_refused_start({"--tls_client_ca=" + certs_.ca}, "--tls_client_ca: needs --tls_cert and --tls_key");
  expect_refused_start({"--tls_cert=" + dir_.path + "/absent.pem", "--tls_key=" + certs_.server_key},
                       "--tls_cert: cannot read");
  expect_refused_start({"--tokens_file=" + dir_.path + "/absent"}, "--tokens_file: cannot read");

  DaemonProcess allowed(dir_.path + "/data", {"--listen=0.0.0.0:0", "--allow_insecure"}, {}, {nullptr, log_});
  EXPECT_TRUE(server_info(*allowed.stub()).ok());
  EXPECT_NE(log_of(log_).find("serving plaintext on 0.0.0.0:0"), std::string::npos) << log_of(log_);
  EXPECT_NE(log_of(log_).find("acts as admin"), std::string::npos) << log_of(log_);
}

// A loopback port that was free a moment ago (the kernel's pick for port 0).
int free_loopback_port() {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  socklen_t length = sizeof address;
  const bool ok = bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) == 0 &&
                  getsockname(fd, reinterpret_cast<sockaddr*>(&address), &length) == 0;
  close(fd);
  return ok ? ntohs(address.sin_port) : 0;
}

// Kubernetes' gRPC probes speak no TLS: --health_listen serves the health service alone, in
// plaintext, on a second address beside the TLS API. There it answers SERVING by both names, and
// nothing else is served (the API and reflection are UNIMPLEMENTED, so a caller who reaches the
// probes' port reaches no session and not even the API's shape).
TEST_F(RemoteAccess, AHealthAddressAnswersProbesInPlaintextAndNothingElse) {
  const int port = free_loopback_port();
  ASSERT_GT(port, 0);
  const std::string health = "127.0.0.1:" + std::to_string(port);
  auto flags = tls_flags(certs_.server_cert, certs_.server_key);
  flags.push_back("--health_listen=" + health);
  const Tls alice = with_token(certs_.ca, "alice-secret");
  DaemonProcess daemon(dir_.path + "/data", flags, {}, {credentials_for(alice), log_});
  EXPECT_TRUE(server_info(*stub_for(daemon, alice)).ok());

  const auto plain = grpc::CreateChannel(health, grpc::InsecureChannelCredentials());
  for (const char* service : {"", "lbsolid.v1.Simulation"}) {
    std::string bytes;
    const grpc::Status status = health_check(plain, &bytes, service);
    ASSERT_TRUE(status.ok()) << service << ": " << status.error_message();
    EXPECT_EQ(bytes, std::string("\x08\x01", 2)) << service;  // SERVING
  }
  EXPECT_TRUE(has_status(server_info(*v1::Simulation::NewStub(plain)), grpc::StatusCode::UNIMPLEMENTED));
  auto reflection = grpc::reflection::v1alpha::ServerReflection::NewStub(plain);
  auto context = deadline_context();
  auto stream = reflection->ServerReflectionInfo(context.get());
  grpc::reflection::v1alpha::ServerReflectionRequest list;
  list.set_list_services("");
  stream->Write(list);
  stream->WritesDone();
  grpc::reflection::v1alpha::ServerReflectionResponse ignored;
  while (stream->Read(&ignored)) {
  }
  EXPECT_EQ(stream->Finish().error_code(), grpc::StatusCode::UNIMPLEMENTED);
  EXPECT_NE(log_of(log_).find("health alone on " + health + " (plaintext)"), std::string::npos) << log_of(log_);
  EXPECT_EQ(daemon.stop(SIGTERM), 0);
}

TEST_F(RemoteAccess, TlsWithTokensAuthenticatesEveryCallBeforeItReachesASession) {
  const Tls alice = with_token(certs_.ca, "alice-secret");
  DaemonProcess daemon(dir_.path + "/data", tls_flags(certs_.server_cert, certs_.server_key), {},
                       {credentials_for(alice), log_});
  auto as_alice = stub_for(daemon, alice);
  v1::Session session;
  ASSERT_TRUE(create_session(*as_alice, small_channel_with_disk(24, 12), &session).ok());
  EXPECT_EQ(session.owner(), "alice");

  EXPECT_TRUE(has_status(server_info(*stub_for(daemon, with_token(certs_.ca))), grpc::StatusCode::UNAUTHENTICATED,
                         "authorization: missing"));
  EXPECT_TRUE(has_status(server_info(*stub_for(daemon, with_token(certs_.ca, "guessed"))), grpc::StatusCode::UNAUTHENTICATED,
                         "unknown or revoked token"));
  // A client that trusts another CA does not talk to this daemon at all.
  EXPECT_TRUE(has_status(server_info(*stub_for(daemon, with_token(certs_.other_ca, "alice-secret"))),
                         grpc::StatusCode::UNAVAILABLE));

  // Health needs no credentials (probes), and reveals no session.
  std::string health;
  EXPECT_TRUE(health_check(channel_for(daemon, with_token(certs_.ca)), &health).ok());
  EXPECT_EQ(health, std::string("\x08\x01", 2));

  // Revoked by a reload: alice's token goes, dave's comes; a reload that fails keeps them.
  write_tokens(token_line("dave-secret", "dave", "user"));
  ASSERT_EQ(kill(daemon.pid(), SIGHUP), 0);
  const auto give_up = std::chrono::steady_clock::now() + 10s;
  while (server_info(*stub_for(daemon, alice)).ok() && std::chrono::steady_clock::now() < give_up)
    std::this_thread::sleep_for(20ms);
  EXPECT_TRUE(has_status(server_info(*stub_for(daemon, alice)), grpc::StatusCode::UNAUTHENTICATED));
  EXPECT_TRUE(server_info(*stub_for(daemon, with_token(certs_.ca, "dave-secret"))).ok());
  write_tokens("not a tokens file\n");
  ASSERT_EQ(kill(daemon.pid(), SIGHUP), 0);
  std::this_thread::sleep_for(300ms);
  EXPECT_TRUE(server_info(*stub_for(daemon, with_token(certs_.ca, "dave-secret"))).ok());
  EXPECT_EQ(daemon.stop(SIGTERM), 0);

  const std::string log = log_of(log_);
  EXPECT_NE(log.find("audit: owner alice (user) CreateSession session \"" + session.id() + "\": OK"), std::string::npos)
      << log;
  EXPECT_NE(log.find("SIGHUP: the tokens in force stay"), std::string::npos) << log;
  for (const char* secret : {"alice-secret", "bob-secret", "root-secret", "dave-secret", "guessed"})
    EXPECT_EQ(log.find(secret), std::string::npos) << secret << " in the log";
}

// An operator renews the daemon's certificate in place (here: one signed by another CA, so that
// which one is served shows): within the reload interval new connections get the new one, with
// no restart; the running daemon keeps its sessions.
TEST_F(RemoteAccess, ARenewedCertificateIsServedWithoutARestart) {
  const std::string cert = dir_.path + "/live.pem", key = dir_.path + "/live.key";
  std::filesystem::copy_file(certs_.server_cert, cert);
  std::filesystem::copy_file(certs_.server_key, key);
  const Tls old_ca = with_token(certs_.ca, "alice-secret"), new_ca = with_token(certs_.other_ca, "alice-secret");
  auto flags = tls_flags(cert, key);
  flags.push_back("--tls_reload_interval=1s");
  DaemonProcess daemon(dir_.path + "/data", flags, {}, {credentials_for(old_ca), log_});
  v1::Session session;
  ASSERT_TRUE(create_session(*stub_for(daemon, old_ca), small_channel_with_disk(24, 12), &session).ok());
  EXPECT_TRUE(has_status(server_info(*stub_for(daemon, new_ca)), grpc::StatusCode::UNAVAILABLE));

  // Renewed as operators do: each file written beside and renamed over the old one.
  std::filesystem::copy_file(certs_.renewed_key, key + ".new");
  std::filesystem::copy_file(certs_.renewed_cert, cert + ".new");
  std::filesystem::rename(key + ".new", key);
  std::filesystem::rename(cert + ".new", cert);
  const auto give_up = std::chrono::steady_clock::now() + 15s;
  while (!server_info(*stub_for(daemon, new_ca)).ok() && std::chrono::steady_clock::now() < give_up)
    std::this_thread::sleep_for(100ms);
  EXPECT_TRUE(server_info(*stub_for(daemon, new_ca)).ok()) << log_of(log_);
  EXPECT_TRUE(has_status(server_info(*stub_for(daemon, old_ca)), grpc::StatusCode::UNAVAILABLE));
  v1::Session same;
  EXPECT_TRUE(get_session(*stub_for(daemon, new_ca), session.id(), &same).ok());
}

TEST_F(RemoteAccess, AClientRefusesAnExpiredServerCertificate) {
  const Tls alice = with_token(certs_.ca, "alice-secret");
  DaemonProcess daemon(dir_.path + "/data", tls_flags(certs_.expired_cert, certs_.expired_key), {},
                       {nullptr, log_, /*connect=*/false});
  // Started (the daemon serves what it is given), but no client that checks certificates connects.
  EXPECT_TRUE(has_status(server_info(*stub_for(daemon, alice)), grpc::StatusCode::UNAVAILABLE));
}

TEST_F(RemoteAccess, MutualTlsTakesTheOwnerFromAVerifiedClientCertificate) {
  const Tls carol = with_certificate(certs_.ca, certs_.client_cert, certs_.client_key);
  DaemonProcess daemon(dir_.path + "/data",
                       {"--tls_cert=" + certs_.server_cert, "--tls_key=" + certs_.server_key,
                        "--tls_client_ca=" + certs_.ca},
                       {}, {credentials_for(carol), log_});
  v1::Session session;
  ASSERT_TRUE(create_session(*stub_for(daemon, carol), small_channel_with_disk(24, 12), &session).ok());
  EXPECT_EQ(session.owner(), certs_.client_name);
  // No certificate, or one from another CA with the same name: no connection.
  EXPECT_TRUE(has_status(server_info(*stub_for(daemon, with_token(certs_.ca))), grpc::StatusCode::UNAVAILABLE));
  EXPECT_TRUE(has_status(server_info(*stub_for(daemon, with_certificate(certs_.ca, certs_.stranger_cert, certs_.stranger_key))),
                         grpc::StatusCode::UNAVAILABLE));
}

TEST_F(RemoteAccess, AUnixSocketServesPlaintextCalls) {
  const std::string socket = dir_.path + "/lbsolidd.sock";
  DaemonProcess daemon(dir_.path + "/data", {"--listen=unix:" + socket});
  EXPECT_EQ(daemon.address(), "unix:" + socket);
  v1::Session session;
  ASSERT_TRUE(create_session(*daemon.stub(), small_channel_with_disk(24, 12), &session).ok());
  EXPECT_EQ(session.owner(), "local");  // nobody is authenticated: the local admin
}

TEST_F(RemoteAccess, TokensWorkOverPlaintextLoopbackToo) {
  DaemonProcess daemon(dir_.path + "/data", {"--tokens_file=" + tokens_});
  auto stub = daemon.stub();
  EXPECT_TRUE(has_status(server_info(*stub), grpc::StatusCode::UNAUTHENTICATED, "authorization: missing"));
  v1::ServerInfo info;
  auto context = deadline_context();
  context->AddMetadata("authorization", "Bearer bob-secret");
  EXPECT_TRUE(stub->GetServerInfo(context.get(), {}, &info).ok());
}

// --owner_call_rate: an owner past the rate gets RESOURCE_EXHAUSTED naming the limit, with the
// wait in trailing metadata, before the call does anything; another owner's calls pass; after the
// wait the owner's calls pass again. Burst 3 at 2 a second: the 4th quick call is refused (the
// calls take well under the 500 ms a token needs on any machine that runs these tests).
TEST_F(RemoteAccess, AnOwnerPastTheCallRateIsToldToWaitAndOthersAreNot) {
  DaemonProcess daemon(dir_.path + "/data",
                       {"--tokens_file=" + tokens_, "--owner_call_rate=2", "--owner_call_burst=3"});
  auto stub = daemon.stub();
  const auto info_as = [&](const std::string& token, std::string* retry_after = nullptr) {
    v1::ServerInfo info;
    auto context = deadline_context();
    context->AddMetadata("authorization", "Bearer " + token);
    const grpc::Status status = stub->GetServerInfo(context.get(), {}, &info);
    if (retry_after) {
      const auto& trailers = context->GetServerTrailingMetadata();
      const auto at = trailers.find("lbsolid-retry-after-ms");
      *retry_after = at == trailers.end() ? "" : std::string(at->second.data(), at->second.size());
    }
    return status;
  };
  for (int i = 0; i < 3; ++i) EXPECT_TRUE(info_as("alice-secret").ok()) << i;
  std::string retry_after;
  const grpc::Status refused = info_as("alice-secret", &retry_after);
  EXPECT_TRUE(has_status(refused, grpc::StatusCode::RESOURCE_EXHAUSTED, "--owner_call_rate")) << refused.error_message();
  ASSERT_FALSE(retry_after.empty());
  const long wait_ms = std::stol(retry_after);
  EXPECT_GT(wait_ms, 0);
  EXPECT_LE(wait_ms, 500);  // one token at 2 a second
  EXPECT_TRUE(info_as("bob-secret").ok());
  std::this_thread::sleep_for(std::chrono::milliseconds(wait_ms + 20));
  EXPECT_TRUE(info_as("alice-secret").ok());
}

// Every RPC that names a session or checkpoint, made by bob on alice's: NOT_FOUND each time, and
// alice's session is as she left it. The admin sees and reaches it.
TEST_F(RemoteAccess, NoRpcLetsOneUserSeeOrTouchAnothersSession) {
  const Tls alice = with_token(certs_.ca, "alice-secret"), bob = with_token(certs_.ca, "bob-secret"),
            admin = with_token(certs_.ca, "root-secret");
  DaemonProcess daemon(dir_.path + "/data", tls_flags(certs_.server_cert, certs_.server_key), {},
                       {credentials_for(alice), log_});
  auto as_alice = stub_for(daemon, alice);
  auto as_bob = stub_for(daemon, bob);
  v1::Session session;
  ASSERT_TRUE(create_session(*as_alice, small_channel_with_disk(24, 12), &session, "job-1").ok());
  const std::string id = session.id();
  v1::CheckpointResponse saved;
  ASSERT_TRUE(checkpoint(*as_alice, id, &saved).ok());

  const auto not_found = [](const grpc::Status& status) { return has_status(status, grpc::StatusCode::NOT_FOUND); };
  v1::Session out;
  EXPECT_TRUE(not_found(get_session(*as_bob, id, &out)));
  EXPECT_TRUE(not_found(run_session(*as_bob, id, 10)));
  EXPECT_TRUE(not_found(resume(*as_bob, id, &out)));
  EXPECT_TRUE(not_found(checkpoint(*as_bob, id, &saved)));
  EXPECT_TRUE(not_found(restore(*as_bob, saved.checkpoint_id(), &out)));
  FieldBytes fields;
  EXPECT_TRUE(not_found(read_fields(*as_bob, id, &fields)));
  {
    v1::StepRequest r;
    r.set_session_id(id);
    r.set_steps(1);
    v1::StepResponse s;
    EXPECT_TRUE(not_found(as_bob->Step(deadline_context().get(), r, &s)));
  }
  {
    v1::PauseRequest r;
    r.set_session_id(id);
    EXPECT_TRUE(not_found(as_bob->Pause(deadline_context().get(), r, &out)));
  }
  {
    v1::CancelRequest r;
    r.set_session_id(id);
    EXPECT_TRUE(not_found(as_bob->Cancel(deadline_context().get(), r, &out)));
  }
  {
    v1::DeleteSessionRequest r;
    r.set_session_id(id);
    v1::DeleteSessionResponse s;
    EXPECT_TRUE(not_found(as_bob->DeleteSession(deadline_context().get(), r, &s)));
  }
  {
    v1::ListOutputsRequest r;
    r.set_session_id(id);
    v1::ListOutputsResponse s;
    EXPECT_TRUE(not_found(as_bob->ListOutputs(deadline_context().get(), r, &s)));
    std::string bytes;
    v1::OutputFile file;
    EXPECT_TRUE(not_found(download_output(*as_bob, id, "checkpoints/step-000000000.h5", 0, "", &bytes, &file)));
    EXPECT_TRUE(bytes.empty());
  }
  v1::WatchSessionRequest watch;
  watch.set_session_id(id);
  EXPECT_TRUE(not_found(stream_status<v1::SessionEvent>(*as_bob, &v1::Simulation::Stub::WatchSession, watch)));
  v1::WatchProfilesRequest profiles;
  profiles.set_session_id(id);
  profiles.set_every(1);
  EXPECT_TRUE(not_found(stream_status<v1::ProfileFrame>(*as_bob, &v1::Simulation::Stub::WatchProfiles, profiles)));
  v1::WatchParticlesRequest particles;
  particles.set_session_id(id);
  particles.set_every(1);
  EXPECT_TRUE(not_found(stream_status<v1::ParticleFrame>(*as_bob, &v1::Simulation::Stub::WatchParticles, particles)));
  v1::ListSessionsResponse listed;
  ASSERT_TRUE(as_bob->ListSessions(deadline_context().get(), {}, &listed).ok());
  EXPECT_EQ(listed.sessions_size(), 0);
  v1::Session bobs;  // his request id of the same name is his own job
  ASSERT_TRUE(create_session(*as_bob, small_channel_with_disk(24, 12), &bobs, "job-1").ok());
  EXPECT_NE(bobs.id(), id);
  v1::ServerInfo info;
  ASSERT_TRUE(as_bob->GetServerInfo(deadline_context().get(), {}, &info).ok());
  EXPECT_EQ(info.sessions(), 1);  // his own

  ASSERT_TRUE(get_session(*as_alice, id, &out).ok());
  EXPECT_EQ(out.state(), v1::SESSION_STATE_CREATED);
  EXPECT_EQ(out.step(), 0);
  ASSERT_TRUE(stub_for(daemon, admin)->ListSessions(deadline_context().get(), {}, &listed).ok());
  EXPECT_EQ(listed.sessions_size(), 2);
  EXPECT_TRUE(run_session(*stub_for(daemon, admin), id, 10).ok());
}

}  // namespace
}  // namespace lbsolid::testing
