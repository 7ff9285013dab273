#include "run_recording.h"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <filesystem>

#include "field_fetch.h"
#include "message_format.h"
#include "scenario_file.h"
#include "server/api/scenario_translation.h"
#include "server/recording/h5md_frames.h"
#include "server/storage/field_snapshot.h"

#ifndef LBSOLID_VERSION
#define LBSOLID_VERSION "unknown"
#endif

namespace lbsolid::cli {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;
using lbsolid::v1::ParticleFrame;
using lbsolid::v1::ProfileFrame;

constexpr const char* kParticlesFile = "particles.h5";
constexpr const char* kFieldsFile = "fields.h5";
constexpr const char* kStatusFile = "status.json";

// Records the first failure and its exit code; later ones are appended to the message.
struct Failures {
  std::string text;
  int exit_code = 0;
  void add(const std::string& what, int code) {
    text += (text.empty() ? "" : "; ") + what;
    if (exit_code == 0) exit_code = code;
  }
};

template <class Frame>
void collect(const char* rpc, StreamRecorder<Frame>& recorder, Failures& failures) {
  if (!recorder.error().empty()) failures.add(std::string(rpc) + ": " + recorder.error(), kExitBadInput);
  const auto& status = recorder.status();
  // CANCELLED is the recorder's own doing (idle after the end, a failed sink, or the run over).
  if (!status.ok() && status.error_code() != grpc::StatusCode::CANCELLED) {
    const RpcError error(rpc, status);
    failures.add(error.what(), error.exit_code());
  }
  if (recorder.idle_cancelled())
    std::fprintf(stderr, "lbsolid: %s did not end with the session; closed after %ld frames\n", rpc, recorder.frames());
}

}  // namespace

void prepare_output_directory(const std::string& dir) {
  std::error_code error;
  fs::create_directories(dir, error);
  if (error) throw CliError(kExitBadInput, dir + ": " + error.message());
  if (::access(dir.c_str(), W_OK) != 0) throw CliError(kExitBadInput, dir + ": " + std::strerror(errno));
}

RunRecording::RunRecording(Daemon& daemon, const lbsolid::v1::Session& session,
                           const lbsolid::v1::Scenario& scenario, const SubmitOptions& options)
    : daemon_(daemon), session_id_(session.id()), dir_(options.out_dir), fluid_(has_fluid(scenario)),
      dimension_(dimension(scenario)) {
  const bool record_streams = !is_final(session.state());
  try {
    fs::create_directories(dir_);
    const std::string xdmf = fs::path(lbsolid::server::storage::xdmf_path_for(kFieldsFile)).filename();
    std::vector<std::string> stale = {kFieldsFile, xdmf, kStatusFile};
    // A retry attaching to a finished run keeps the trajectory the first attempt recorded.
    if (record_streams) stale.push_back(kParticlesFile);
    for (const auto& name : stale) fs::remove(fs::path(dir_) / name);
  } catch (const fs::filesystem_error& e) {
    throw CliError(kExitBadInput, dir_ + ": " + e.code().message());
  }
  const bool want_particles = scenario.bodies_size() > 0, want_profiles = fluid_;
  if (!record_streams || !(want_particles || want_profiles)) return;

  try {
    writer_ = std::make_unique<lbsolid::server::storage::H5mdWriter>(
        (fs::path(dir_) / kParticlesFile).string(), LBSOLID_VERSION, lbsolid::server::scenario_to_text(scenario),
        lbsolid::server::recording::h5md_box(scenario));
  } catch (const std::exception& e) {
    throw CliError(kExitBadInput, e.what());
  }

  if (want_particles) {
    particles_ = std::make_unique<StreamRecorder<ParticleFrame>>(
        [this, every = options.particles_every](grpc::ClientContext* context) {
          lbsolid::v1::WatchParticlesRequest request;
          request.set_session_id(session_id_);
          request.set_every(every);
          request.set_delivery(lbsolid::v1::DELIVERY_MODE_EVERY_FRAME);
          return daemon_.stub().WatchParticles(context, request);
        },
        [this](const ParticleFrame& frame) {
          std::lock_guard lock(writer_mutex_);
          lbsolid::server::recording::append_particle_frame(*writer_, frame, dimension_);
        });
  }
  if (want_profiles) {
    profiles_ = std::make_unique<StreamRecorder<ProfileFrame>>(
        [this, every = options.profile_every](grpc::ClientContext* context) {
          lbsolid::v1::WatchProfilesRequest request;
          request.set_session_id(session_id_);
          request.set_every(every);
          request.set_delivery(lbsolid::v1::DELIVERY_MODE_EVERY_FRAME);
          return daemon_.stub().WatchProfiles(context, request);
        },
        [this](const ProfileFrame& frame) {
          std::lock_guard lock(writer_mutex_);
          lbsolid::server::recording::append_profile_frame(*writer_, frame);
        });
  }
}

RunRecording::~RunRecording() {
  // Streams first: their threads use the writer.
  particles_.reset();
  profiles_.reset();
}

void RunRecording::wait_streams_registered() {
  const auto deadline = std::chrono::steady_clock::now() + 1s;
  auto left = [&] {
    return std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
  };
  if (particles_) particles_->wait_first_frame(std::max(left(), 0ms));
  if (profiles_) profiles_->wait_first_frame(std::max(left(), 0ms));
}

RunRecord RunRecording::finish(const lbsolid::v1::Session& last, const std::string& error, int exit_code) {
  Failures failures;
  if (!error.empty()) failures.add(error, exit_code);
  failures.exit_code = exit_code;  // the run's outcome comes first, even when it is 0 with a note

  // A final session ends the streams by themselves, after the last frames; otherwise nothing more
  // will come and they are cancelled now.
  const bool final = is_final(last.state());
  const auto idle = std::max(std::chrono::milliseconds(2s),
                             std::chrono::milliseconds(static_cast<long>(daemon_.options().timeout_s * 1000)));
  if (particles_) {
    final ? particles_->finish(idle) : particles_->stop();
    collect("WatchParticles", *particles_, failures);
  }
  if (profiles_) {
    final ? profiles_->finish(idle) : profiles_->stop();
    collect("WatchProfiles", *profiles_, failures);
  }
  if (writer_) {
    try {
      writer_->close();
    } catch (const std::exception& e) {
      failures.add(e.what(), kExitBadInput);
    }
  }

  if (fluid_) {
    try {
      write_field_snapshot((fs::path(dir_) / kFieldsFile).string(), fetch_fields(daemon_, session_id_));
    } catch (const RpcError& e) {
      failures.add(e.what(), e.exit_code());
    } catch (const CliError& e) {
      failures.add(e.what(), e.exit_code);
    }
  }

  RunRecord record;
  record.session_id = session_id_;
  record.state = state_name(last.state());
  record.step = last.step();
  record.target_step = last.target_step();
  record.message = last.message();
  try {
    const std::string xdmf = fs::path(lbsolid::server::storage::xdmf_path_for(kFieldsFile)).filename();
    record.files = describe_files(dir_, {kParticlesFile, kFieldsFile, xdmf});
  } catch (const std::exception& e) {
    failures.add(e.what(), kExitBadInput);
  }
  record.error = failures.text;
  record.exit_code = failures.exit_code;
  try {
    write_file_atomically((fs::path(dir_) / kStatusFile).string(), status_json(record) + "\n");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "lbsolid: %s\n", e.what());
    if (record.exit_code == 0) record.exit_code = kExitBadInput;
  }
  return record;
}

}  // namespace lbsolid::cli
