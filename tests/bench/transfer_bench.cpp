// lbsolid-transfer-bench: what a client gets out of a daemon on loopback. Starts a private
// lbsolidd, records field snapshots of a large session until its fields.h5 passes --mib (default
// 1024), then measures:
//   - DownloadOutput of that file, whole, in 3 MiB chunks: GB/s over --repeats calls, to a client
//     that only reads the stream and to one that keeps it in fresh memory (see Sink);
//   - the same download interrupted twice and resumed from the bytes received (naming the
//     version), with the SHA-256 of what arrived checked against the daemon's;
//   - GetField of the session (density and velocity), GB/s, the same two ways: read again at one
//     step, and each after a step (whose fields the daemon has not computed yet).
//   lbsolid-transfer-bench [--mib 1024] [--nx 2048] [--repeats 5] [--fields-only 1]
// --fields-only 1 records nothing and measures GetField alone (to profile it).
#include <chrono>
#include <functional>
#include <iostream>
#include <string>

#include "io/storage/sha256.h"
#include "service/daemon_process.h"
#include "service/test_scenarios.h"

namespace {

using namespace lbsolid::testing;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// What a client does with the bytes: kStream reads every chunk, checks that the chunks follow each
// other and keeps nothing (what the RPC delivers, as to a client that writes each chunk on or
// hands it to another thread); kFreshMemory keeps them all in a buffer allocated for the call
// (its size known from the first message), whose pages the client then has to fault in.
enum class Sink { kStream, kFreshMemory };

const char* sink_name(Sink sink) { return sink == Sink::kStream ? "stream" : "into fresh memory"; }

// Bytes read and whether the call ended OK with the chunks in order.
struct Transfer {
  long bytes = 0;
  bool ok = false;
};

// Reads the stream to its end, handing each message to take(message, kept, bytes so far), which
// returns whether the message followed the ones before; kept is null for Sink::kStream.
template <class Message, class Take>
Transfer drain(grpc::ClientReader<Message>& reader, Sink sink, Take take) {
  Message message;
  std::string kept;
  Transfer t;
  bool in_order = true;
  while (reader.Read(&message)) in_order = take(message, sink == Sink::kFreshMemory ? &kept : nullptr, t.bytes) && in_order;
  t.ok = reader.Finish().ok() && in_order;
  return t;
}

Transfer download(v1::Simulation::Stub& stub, const std::string& session_id, const std::string& sha256, Sink sink) {
  v1::DownloadOutputRequest request;
  request.set_session_id(session_id);
  request.set_name("fields.h5");
  request.set_sha256(sha256);
  request.set_chunk_bytes(3 << 20);
  auto context = deadline_context(120);
  auto reader = stub.DownloadOutput(context.get(), request);
  return drain(*reader, sink, [](const v1::OutputChunk& chunk, std::string* kept, long& bytes) {
    if (chunk.has_file() && kept) kept->reserve(static_cast<std::size_t>(chunk.file().bytes()));
    const bool in_order = chunk.offset() == bytes;
    bytes += static_cast<long>(chunk.data().size());
    if (kept) *kept += chunk.data();
    return in_order;
  });
}

Transfer get_field(v1::Simulation::Stub& stub, const std::string& session_id, Sink sink) {
  v1::GetFieldRequest request;
  request.set_session_id(session_id);
  request.set_chunk_bytes(3 << 20);
  auto context = deadline_context(120);
  auto reader = stub.GetField(context.get(), request);
  long field_offset = 0;  // where the next chunk of the current field starts
  return drain(*reader, sink, [&](const v1::FieldMessage& message, std::string* kept, long& bytes) {
    if (message.has_header()) {
      field_offset = 0;
      if (kept) kept->reserve(kept->size() + static_cast<std::size_t>(message.header().total_bytes()));
      return true;
    }
    const bool in_order = message.chunk().offset() == field_offset;
    field_offset += static_cast<long>(message.chunk().data().size());
    bytes += static_cast<long>(message.chunk().data().size());
    if (kept) *kept += message.chunk().data();
    return in_order;
  });
}

// GB/s of `repeats` calls, the first one apart (on a connection that has not carried this much
// yet, whose HTTP/2 flow-control window is still growing); `before_each` runs before each call,
// untimed. False if a call failed.
template <class Call>
bool report_rate(const std::string& what, int repeats, Call call, const std::function<bool()>& before_each = [] { return true; }) {
  double first = 0, best = 0, worst = 1e300;
  for (int r = 0; r <= repeats; ++r) {
    if (!before_each()) {
      std::cerr << what << ": the preparation failed\n";
      return false;
    }
    const auto start = Clock::now();
    const Transfer t = call();
    if (!t.ok || t.bytes == 0) {
      std::cerr << what << ": the call failed\n";
      return false;
    }
    const double gbps = static_cast<double>(t.bytes) / seconds_since(start) / 1e9;
    if (r == 0) {
      first = gbps;
      continue;
    }
    best = std::max(best, gbps);
    worst = std::min(worst, gbps);
  }
  std::cout << what << ": " << worst << "-" << best << " GB/s over " << repeats << " calls (the first call before them: "
            << first << ")\n";
  return true;
}

// DownloadOutput of fields.h5, whole in 3 MiB chunks, then interrupted twice and resumed. False if
// a call failed or the resumed bytes do not have the daemon's SHA-256.
bool measure_downloads(v1::Simulation::Stub& stub, const std::string& session_id, int repeats) {
  const auto listed_at = Clock::now();
  std::string whole;
  v1::OutputFile file;
  if (!download_output(stub, session_id, "fields.h5", 0, "", &whole, &file, 3 << 20, 0).ok()) {
    std::cerr << "cannot list fields.h5\n";
    return false;
  }
  std::cout << "fields.h5: " << file.bytes() << " bytes (made from the frame log and listed in "
            << seconds_since(listed_at) << " s)\n";
  for (Sink sink : {Sink::kStream, Sink::kFreshMemory})
    if (!report_rate(std::string("DownloadOutput, ") + sink_name(sink), repeats,
                     [&] { return download(stub, session_id, file.sha256(), sink); }))
      return false;

  std::string resumed;
  v1::OutputFile again;
  const int chunks = static_cast<int>(file.bytes() / (3 << 20) / 3) + 1;
  bool ok = download_output(stub, session_id, "fields.h5", 0, "", &resumed, &again, 3 << 20, chunks).ok();
  ok = ok && download_output(stub, session_id, "fields.h5", static_cast<long>(resumed.size()), file.sha256(),
                             &resumed, &again, 3 << 20, chunks).ok();
  ok = ok && download_output(stub, session_id, "fields.h5", static_cast<long>(resumed.size()), file.sha256(),
                             &resumed, &again, 3 << 20).ok();
  const bool same = ok && lbsolid::server::storage::sha256_hex(resumed) == file.sha256();
  std::cout << "interrupted twice and resumed: " << resumed.size() << " bytes, SHA-256 "
            << (same ? "matches" : "DOES NOT MATCH") << " the daemon's\n";
  return same;
}

// GetField of the session (density and velocity) in 3 MiB chunks: read again at one step (the
// daemon computes the fields once and sends them again), then each after a step of the session
// (untimed), which the daemon must compute the fields for.
bool measure_get_field(v1::Simulation::Stub& stub, const std::string& session_id, int repeats) {
  for (Sink sink : {Sink::kStream, Sink::kFreshMemory})
    if (!report_rate(std::string("GetField, again at one step, ") + sink_name(sink), repeats,
                     [&] { return get_field(stub, session_id, sink); }))
      return false;
  const auto step = [&] {
    v1::StepRequest request;
    request.set_session_id(session_id);
    request.set_steps(1);
    v1::StepResponse response;
    return stub.Step(deadline_context(120).get(), request, &response).ok() && response.steps_taken() == 1;
  };
  for (Sink sink : {Sink::kStream, Sink::kFreshMemory})
    if (!report_rate(std::string("GetField, each after a step, ") + sink_name(sink), repeats,
                     [&] { return get_field(stub, session_id, sink); }, step))
      return false;
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  long mib = 1024, nx = 2048;
  int repeats = 5;
  bool fields_only = false;
  for (int k = 1; k + 1 < argc; k += 2) {
    const std::string flag = argv[k];
    if (flag == "--mib") mib = std::stol(argv[k + 1]);
    else if (flag == "--nx") nx = std::stol(argv[k + 1]);
    else if (flag == "--repeats") repeats = std::stoi(argv[k + 1]);
    else if (flag == "--fields-only") fields_only = std::stoi(argv[k + 1]) != 0;
    else {
      std::cerr << "usage: lbsolid-transfer-bench [--mib N] [--nx N] [--repeats N] [--fields-only 0|1]\n";
      return 2;
    }
  }
  const ScopedDirectory dir("lbsolid-transfer-bench");
  DaemonProcess daemon(dir.path, {"--autosave_interval=0"});
  auto stub = daemon.stub();
  auto scenario = small_channel_with_disk(static_cast<int>(nx), static_cast<int>(nx));
  scenario.mutable_bodies()->Clear();
  const long snapshot_bytes = nx * nx * 4 * 8;  // density and three velocity components, float64
  const long snapshots = fields_only ? 1 : std::max(1L, (mib << 20) / snapshot_bytes + 1);
  if (!fields_only) scenario.mutable_outputs()->set_fields_every(1);
  v1::Session session;
  if (!create_session(*stub, scenario, &session).ok() || !run_session(*stub, session.id(), std::max(1L, snapshots - 1)).ok() ||
      !wait_for_state(*stub, session.id(), v1::SESSION_STATE_DONE, 600)) {
    std::cerr << "cannot run the session\n";
    return 1;
  }
  std::cout << nx << " x " << nx << " D2Q9 session, " << snapshots << " field snapshots recorded\n";
  if (!fields_only && !measure_downloads(*stub, session.id(), repeats)) return 1;
  return measure_get_field(*stub, session.id(), repeats) ? 0 : 1;
}
