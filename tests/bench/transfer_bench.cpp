// lbsolid-transfer-bench: what a client gets out of a daemon on loopback. Starts a private
// lbsolidd, records field snapshots of a large session until its fields.h5 passes --mib (default
// 1024), then measures:
//   - DownloadOutput of that file, whole, in 3 MiB chunks: GB/s, best of --repeats;
//   - the same download interrupted twice and resumed from the bytes received (naming the
//     version), with the SHA-256 of what arrived checked against the daemon's;
//   - GetField of the live session (density and velocity), GB/s, best of --repeats.
//   lbsolid-transfer-bench [--mib 1024] [--nx 2048] [--repeats 3]
#include <chrono>
#include <iostream>
#include <string>

#include "server/storage/sha256.h"
#include "service/daemon_process.h"
#include "service/test_scenarios.h"

namespace {

using namespace lbsolid::testing;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

}  // namespace

int main(int argc, char** argv) {
  long mib = 1024, nx = 2048;
  int repeats = 3;
  for (int k = 1; k + 1 < argc; k += 2) {
    const std::string flag = argv[k];
    if (flag == "--mib") mib = std::stol(argv[k + 1]);
    else if (flag == "--nx") nx = std::stol(argv[k + 1]);
    else if (flag == "--repeats") repeats = std::stoi(argv[k + 1]);
    else {
      std::cerr << "usage: lbsolid-transfer-bench [--mib N] [--nx N] [--repeats N]\n";
      return 2;
    }
  }
  const ScopedDirectory dir("lbsolid-transfer-bench");
  DaemonProcess daemon(dir.path, {"--autosave_interval=0"});
  auto stub = daemon.stub();
  auto scenario = small_channel_with_disk(static_cast<int>(nx), static_cast<int>(nx));
  scenario.mutable_bodies()->Clear();
  const long snapshot_bytes = nx * nx * 4 * 8;  // density and three velocity components, float64
  const long snapshots = std::max(1L, (mib << 20) / snapshot_bytes + 1);
  scenario.mutable_outputs()->set_fields_every(1);
  v1::Session session;
  if (!create_session(*stub, scenario, &session).ok() || !run_session(*stub, session.id(), snapshots - 1).ok() ||
      !wait_for_state(*stub, session.id(), v1::SESSION_STATE_DONE, 600)) {
    std::cerr << "cannot run the session\n";
    return 1;
  }
  const auto listed_at = Clock::now();
  std::string whole;
  v1::OutputFile file;
  if (!download_output(*stub, session.id(), "fields.h5", 0, "", &whole, &file, 3 << 20, 0).ok()) {
    std::cerr << "cannot list fields.h5\n";
    return 1;
  }
  std::cout << nx << " x " << nx << " D2Q9 session, " << snapshots << " snapshots: fields.h5 " << file.bytes()
            << " bytes (made from the frame log and listed in " << seconds_since(listed_at) << " s)\n";

  double best = 0;
  for (int r = 0; r < repeats; ++r) {
    std::string bytes;  // a fresh buffer each time, as GetField's reader below has
    const auto start = Clock::now();
    if (!download_output(*stub, session.id(), "fields.h5", 0, file.sha256(), &bytes, &file, 3 << 20).ok()) return 1;
    best = std::max(best, static_cast<double>(bytes.size()) / seconds_since(start) / 1e9);
  }
  std::cout << "DownloadOutput, whole file in 3 MiB chunks: best " << best << " GB/s of " << repeats << "\n";

  std::string resumed;
  v1::OutputFile again;
  const int chunks = static_cast<int>(file.bytes() / (3 << 20) / 3) + 1;
  bool ok = download_output(*stub, session.id(), "fields.h5", 0, "", &resumed, &again, 3 << 20, chunks).ok();
  ok = ok && download_output(*stub, session.id(), "fields.h5", static_cast<long>(resumed.size()), file.sha256(),
                             &resumed, &again, 3 << 20, chunks).ok();
  ok = ok && download_output(*stub, session.id(), "fields.h5", static_cast<long>(resumed.size()), file.sha256(),
                             &resumed, &again, 3 << 20).ok();
  const bool same = ok && lbsolid::server::storage::sha256_hex(resumed) == file.sha256();
  std::cout << "interrupted twice and resumed: " << resumed.size() << " bytes, SHA-256 "
            << (same ? "matches" : "DOES NOT MATCH") << " the daemon's\n";

  best = 0;
  for (int r = 0; r < repeats; ++r) {
    FieldBytes fields;
    const auto start = Clock::now();
    if (!read_fields(*stub, session.id(), &fields, 3 << 20).ok()) return 1;
    const double bytes = static_cast<double>(fields.bytes["density"].size() + fields.bytes["velocity"].size());
    best = std::max(best, bytes / seconds_since(start) / 1e9);
  }
  std::cout << "GetField, density and velocity in 3 MiB chunks: best " << best << " GB/s of " << repeats << "\n";
  return same ? 0 : 1;
}
