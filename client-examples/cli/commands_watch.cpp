// watch: one line per frame of a session's profiles or particles, until the session ends or
// --frames K frames have been printed.
#include "commands.h"
#include "daemon_placement.h"
#include "message_format.h"
#include "rpc_client.h"

namespace lbsolid::cli {
namespace {

// Reads the stream, printing each frame; after `limit` frames cancels it and drains what is
// in flight, which is how a client ends a server stream cleanly.
template <class Frame>
int print_frames(const CommandLine& line, const char* rpc, grpc::ClientContext& context,
                 grpc::ClientReader<Frame>& reader, std::optional<long> limit,
                 std::string (*json)(const Frame&), std::string (*text)(const Frame&)) {
  Frame frame;
  long frames = 0;
  bool cancelled = false;
  while (reader.Read(&frame)) {
    if (cancelled) continue;
    CommandResult result;
    result.command = line.command;
    result.session_id = line.positional.at(0);
    result.step = frame.step();
    emit(line, result.add("frame", json(frame)), text(frame));
    if (limit && ++frames >= *limit) {
      context.TryCancel();
      cancelled = true;
    }
  }
  const grpc::Status status = reader.Finish();
  if (!status.ok() && !(cancelled && status.error_code() == grpc::StatusCode::CANCELLED)) throw RpcError(rpc, status);
  return kExitOk;
}

}  // namespace

int cmd_watch(const CommandLine& line) {
  const WatchOptions options = watch_options(line);
  Daemon daemon(daemon_of_session(line.global, options.session_id));
  const auto delivery =
      options.lossless ? lbsolid::v1::DELIVERY_MODE_EVERY_FRAME : lbsolid::v1::DELIVERY_MODE_LATEST_FRAME;
  // No deadline: the stream lasts as long as the session runs; channel keepalive watches the link.
  grpc::ClientContext context;
  if (options.stream == WatchOptions::Stream::kProfiles) {
    lbsolid::v1::WatchProfilesRequest request;
    request.set_session_id(options.session_id);
    request.set_every(options.every);
    request.set_delivery(delivery);
    auto reader = daemon.stub().WatchProfiles(&context, request);
    return print_frames(line, "WatchProfiles", context, *reader, options.frames, &profile_frame_json,
                        &profile_frame_text);
  }
  lbsolid::v1::WatchParticlesRequest request;
  request.set_session_id(options.session_id);
  request.set_every(options.every);
  request.set_delivery(delivery);
  auto reader = daemon.stub().WatchParticles(&context, request);
  return print_frames(line, "WatchParticles", context, *reader, options.frames, &particle_frame_json,
                      &particle_frame_text);
}

}  // namespace lbsolid::cli
