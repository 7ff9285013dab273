#pragma once
// Small scenarios for the end-to-end tests: quick to step, with every stage the daemon handles.
// Also a few one-line RPC helpers the service tests share (create, run, read the fields, compare a
// status with the code and the field it must name).
#include <grpcpp/generic/generic_stub.h>  // grpc::GenericStub, used by service_basics_test.cpp
#include <gtest/gtest.h>

#include <filesystem>
#include <algorithm>
#include <map>
#include <string>

#include "lbsolid/v1/scenario.pb.h"
#include "service/daemon_process.h"

namespace lbsolid::testing {

// A D2Q9 channel (walls at y) of nx x ny nodes driven by a body force, with a disk named "disk".
inline lbsolid::v1::Scenario small_channel_with_disk(int nx = 32, int ny = 16) {
  lbsolid::v1::Scenario s;
  s.set_name("small channel with disk");
  s.set_lattice(lbsolid::v1::LATTICE_D2Q9);
  auto* d = s.mutable_domain();
  d->set_nx(nx);
  d->set_ny(ny);
  d->mutable_y_low()->set_kind(lbsolid::v1::WALL_KIND_BOUNCE_BACK);
  d->mutable_y_high()->set_kind(lbsolid::v1::WALL_KIND_BOUNCE_BACK);
  s.mutable_fluid()->set_omega(1.2);
  s.mutable_fluid()->mutable_body_force()->set_x(1e-5);
  auto* disk = s.add_bodies();
  disk->set_name("disk");
  disk->set_shape(lbsolid::v1::BODY_SHAPE_DISK);
  disk->set_radius(2);
  disk->mutable_centre()->set_x(nx / 3.0);
  disk->mutable_centre()->set_y(ny / 2.0);
  disk->mutable_load()->set_x(2e-5);
  return s;
}

// A fully periodic D2Q9 box (no walls, no bodies) pushed by a strong body force: the fluid
// accelerates uniformly by about `force` per step, so |u| / c_s passes the Mach limit of 0.3 after
// some 20 steps; the daemon checks every 10 steps.
inline lbsolid::v1::Scenario diverging_box(double force = 0.01, int nx = 32, int ny = 16) {
  lbsolid::v1::Scenario s;
  s.set_name("diverging box");
  s.set_lattice(lbsolid::v1::LATTICE_D2Q9);
  s.mutable_domain()->set_nx(nx);
  s.mutable_domain()->set_ny(ny);
  s.mutable_fluid()->mutable_body_force()->set_x(force);
  s.mutable_stability()->set_check_interval(10);
  s.mutable_stability()->set_max_mach(0.3);
  return s;
}

// ---- RPC helpers ---------------------------------------------------------------------------

// A stub on its own connection whose HTTP/2 receive window is as small as gRPC allows (no BDP
// probing, a 1-byte stream lookahead): the transport then holds about one frame in flight, so the
// frames a client has read and those the daemon has handed to gRPC differ by at most that one. With
// the default settings the window grows to megabytes on loopback and thousands of small frames sit
// in the transport, unseen by the daemon's delivery modes.
inline std::unique_ptr<v1::Simulation::Stub> tight_window_stub(const DaemonProcess& daemon) {
  grpc::ChannelArguments args;
  args.SetInt(GRPC_ARG_HTTP2_BDP_PROBE, 0);
  args.SetInt(GRPC_ARG_HTTP2_STREAM_LOOKAHEAD_BYTES, 1);
  args.SetInt(GRPC_ARG_USE_LOCAL_SUBCHANNEL_POOL, 1);  // a connection of its own
  return v1::Simulation::NewStub(grpc::CreateCustomChannel(daemon.address(), grpc::InsecureChannelCredentials(), args));
}

// Success, or the status's code and message; `fragment` must occur in the message.
inline ::testing::AssertionResult has_status(const grpc::Status& status, grpc::StatusCode code,
                                             const std::string& fragment = {}) {
  if (status.error_code() != code)
    return ::testing::AssertionFailure() << "status code " << status.error_code() << " (want " << code
                                         << "), message \"" << status.error_message() << "\"";
  if (status.error_message().find(fragment) == std::string::npos)
    return ::testing::AssertionFailure() << "message \"" << status.error_message() << "\" does not name \""
                                         << fragment << "\"";
  return ::testing::AssertionSuccess();
}

inline grpc::Status create_session(v1::Simulation::Stub& stub, const v1::Scenario& scenario, v1::Session* session,
                                   const std::string& request_id = {}) {
  v1::CreateSessionRequest request;
  *request.mutable_scenario() = scenario;
  request.set_request_id(request_id);
  auto context = deadline_context();
  return stub.CreateSession(context.get(), request, session);
}

inline grpc::Status run_session(v1::Simulation::Stub& stub, const std::string& id, long steps,
                                v1::Session* session = nullptr) {
  v1::RunRequest request;
  request.set_session_id(id);
  request.set_steps(steps);
  v1::Session ignored;
  auto context = deadline_context();
  return stub.Run(context.get(), request, session ? session : &ignored);
}

inline grpc::Status get_session(v1::Simulation::Stub& stub, const std::string& id, v1::Session* session) {
  v1::GetSessionRequest request;
  request.set_session_id(id);
  auto context = deadline_context();
  return stub.GetSession(context.get(), request, session);
}

// The raw bytes of each field GetField sends, keyed by name, with the step they belong to.
struct FieldBytes {
  long step = -1;
  std::map<std::string, std::string> bytes;
};

inline grpc::Status read_fields(v1::Simulation::Stub& stub, const std::string& id, FieldBytes* out,
                                long chunk_bytes = 0) {
  v1::GetFieldRequest request;
  request.set_session_id(id);
  request.set_chunk_bytes(chunk_bytes);
  auto context = deadline_context();
  auto reader = stub.GetField(context.get(), request);
  v1::FieldMessage message;
  std::string current;
  while (reader->Read(&message)) {
    if (message.has_header()) {
      current = message.header().name();
      out->step = message.header().step();
      out->bytes[current].clear();
      out->bytes[current].reserve(static_cast<std::size_t>(message.header().total_bytes()));  // as a client that knows the size
    } else if (message.has_chunk()) {
      out->bytes[current] += message.chunk().data();
    }
  }
  return reader->Finish();
}

// Every regular file under dir, relative to it.
inline std::vector<std::string> files_under(const std::filesystem::path& dir) {
  std::vector<std::string> out;
  if (!std::filesystem::exists(dir)) return out;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(dir))
    if (entry.is_regular_file()) out.push_back(std::filesystem::relative(entry.path(), dir).string());
  std::sort(out.begin(), out.end());
  return out;
}

// No temporary file of an interrupted or finished write stays behind.
inline ::testing::AssertionResult no_temporaries(const std::filesystem::path& dir) {
  for (const auto& name : files_under(dir))
    if (name.find(".tmp") != std::string::npos) return ::testing::AssertionFailure() << "left behind: " << dir / name;
  return ::testing::AssertionSuccess();
}

inline grpc::Status checkpoint(v1::Simulation::Stub& stub, const std::string& id, v1::CheckpointResponse* out) {
  v1::CheckpointRequest request;
  request.set_session_id(id);
  auto context = deadline_context();
  return stub.Checkpoint(context.get(), request, out);
}

inline grpc::Status restore(v1::Simulation::Stub& stub, const std::string& checkpoint_id, v1::Session* out,
                     const std::string& request_id = {}) {
  v1::RestoreRequest request;
  request.set_checkpoint_id(checkpoint_id);
  request.set_request_id(request_id);
  auto context = deadline_context();
  return stub.Restore(context.get(), request, out);
}

// grpc.health.v1.Health/Check with an empty request (service ""); `bytes`: the answer as sent,
// "\x08\x01" for HealthCheckResponse{status: SERVING} (field 1, varint 1).
// Through a completion queue that this thread drains, not the callback API: a callback runs on
// a gRPC thread, where its writes hand back to this one through gRPC's own (uninstrumented)
// synchronisation, which ThreadSanitizer cannot see and reported as a race in the test.
// grpc.health.v1.Health/Check for `service` ("" for the whole server); *bytes is the raw answer.
inline grpc::Status health_check(const std::shared_ptr<grpc::Channel>& channel, std::string* bytes,
                                 const std::string& service = "") {
  grpc::GenericStub generic(channel);
  // HealthCheckRequest{service = 1}: the field's tag, its length (one byte: names under 128) and the name.
  grpc::Slice message(service.empty() ? std::string() : std::string(1, '\x0a') + char(service.size()) + service);
  grpc::ByteBuffer request(&message, 1), response;
  auto context = deadline_context();
  grpc::CompletionQueue queue;
  auto call = generic.PrepareUnaryCall(context.get(), "/grpc.health.v1.Health/Check", request, &queue);
  call->StartCall();
  grpc::Status status;
  call->Finish(&response, &status, reinterpret_cast<void*>(1));
  void* tag = nullptr;
  bool ok = false;
  const bool got_event = queue.Next(&tag, &ok);
  queue.Shutdown();
  for (void* ignored_tag; queue.Next(&ignored_tag, &ok);) {
  }
  if (!got_event || tag != reinterpret_cast<void*>(1)) return grpc::Status(grpc::StatusCode::INTERNAL, "no answer");
  if (!status.ok()) return status;
  std::vector<grpc::Slice> slices;
  if (!response.Dump(&slices).ok()) return grpc::Status(grpc::StatusCode::INTERNAL, "unreadable answer");
  bytes->clear();
  for (const auto& slice : slices) bytes->append(reinterpret_cast<const char*>(slice.begin()), slice.size());
  return status;
}

// DownloadOutput of `name` from `offset` into *bytes (appended); *file gets the first message's
// description. With max_chunks >= 0 the client leaves after that many chunks (an interrupted
// download), and the answer is OK if it read them.
inline grpc::Status download_output(v1::Simulation::Stub& stub, const std::string& id, const std::string& name,
                                    long offset, const std::string& sha256, std::string* bytes, v1::OutputFile* file,
                                    long chunk_bytes = 0, int max_chunks = -1) {
  v1::DownloadOutputRequest request;
  request.set_session_id(id);
  request.set_name(name);
  request.set_offset(offset);
  request.set_sha256(sha256);
  request.set_chunk_bytes(chunk_bytes);
  auto context = deadline_context(30);
  auto reader = stub.DownloadOutput(context.get(), request);
  v1::OutputChunk chunk;
  int chunks = 0;
  long next = offset;  // where the next chunk must start: the chunks cover the file in order
  while (reader->Read(&chunk)) {
    if (chunk.has_file()) {
      *file = chunk.file();
      bytes->reserve(static_cast<std::size_t>(file->bytes()));  // as a client that knows the size
    }
    if (chunk.offset() != next) {
      context->TryCancel();
      reader->Finish();
      return grpc::Status(grpc::StatusCode::INTERNAL, "a chunk at offset " + std::to_string(chunk.offset()) +
                                                          ", expected " + std::to_string(next));
    }
    bytes->append(chunk.data());
    next += static_cast<long>(chunk.data().size());
    if (max_chunks >= 0 && ++chunks >= max_chunks) {
      context->TryCancel();
      reader->Finish();
      return grpc::Status::OK;
    }
  }
  return reader->Finish();
}

inline grpc::Status resume(v1::Simulation::Stub& stub, const std::string& id, v1::Session* out) {
  v1::ResumeRequest request;
  request.set_session_id(id);
  auto context = deadline_context();
  return stub.Resume(context.get(), request, out);
}

}  // namespace lbsolid::testing
