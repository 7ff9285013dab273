#pragma once
// What `submit --out DIR` records around a run:
//   DIR/particles.h5   H5MD: every body's particles and mean motion (WatchParticles) and the
//                      velocity profile (WatchProfiles), both lossless, each on its own thread
//   DIR/fields.h5      the final density and velocity (GetField), with DIR/fields.xdmf
//   DIR/status.json    the outcome, the files with their sizes and SHA-256 (result_writer.h)
// The files are written whatever the outcome: a FAILED run keeps what was received.
#include <memory>
#include <mutex>
#include <string>

#include "cli_options.h"
#include "lbsolid/v1/simulation.pb.h"
#include "result_writer.h"
#include "rpc_client.h"
#include "server/storage/h5md_file.h"
#include "stream_recorder.h"

namespace lbsolid::cli {

// Creates DIR if needed and checks it can be written: called before the session is created, so a
// bad --out fails without leaving a session behind. Throws CliError (exit 2).
void prepare_output_directory(const std::string& dir);

class RunRecording {
 public:
  // Creates DIR (replacing earlier outputs of these names) and, unless `session` is final
  // already (a retried submit attaching to a finished run), opens the H5MD file and the streams
  // the scenario needs: profiles if it has a fluid, particles if it has bodies.
  // Throws CliError (exit 2) if DIR or the H5MD file cannot be created.
  RunRecording(Daemon& daemon, const lbsolid::v1::Session& session, const lbsolid::v1::Scenario& scenario,
               const SubmitOptions& options);
  ~RunRecording();

  // Gives the daemon up to a second to register the streams (it may send a first frame at once)
  // before the run starts, so the first frames are not missed.
  void wait_streams_registered();

  // After the run (`last` is the last known session; `error`/`exit_code` the run's outcome): ends
  // the streams, closes the H5MD file, fetches the fields, writes DIR/status.json. Never throws:
  // every failure is recorded in the returned record and status.json.
  RunRecord finish(const lbsolid::v1::Session& last, const std::string& error, int exit_code);

 private:
  Daemon& daemon_;
  std::string session_id_, dir_;
  bool fluid_ = false;
  int dimension_ = 2;
  std::mutex writer_mutex_;  // both stream threads append; HDF5 is not thread-safe
  std::unique_ptr<lbsolid::server::storage::H5mdWriter> writer_;
  std::unique_ptr<StreamRecorder<lbsolid::v1::ParticleFrame>> particles_;
  std::unique_ptr<StreamRecorder<lbsolid::v1::ProfileFrame>> profiles_;
};

}  // namespace lbsolid::cli
