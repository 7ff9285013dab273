#pragma once
// A session's own recording (scenario.outputs): the thread that steps the session appends each
// due frame to the session's frame log (recording/frame_log.h) right after its step; the files a
// client downloads (particles.h5 in H5MD with particles.xdmf, fields.h5 with fields.xdmf) are made from the log when
// a client lists or downloads them and the log has grown since, each written to a temporary
// directory and renamed into place. Checkpoints taken every checkpoint_every steps are listed with
// them. Everything lives in data_dir/outputs/<session id>/ until the session is deleted.
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "lbsolid/v1/simulation.pb.h"
#include "scene/simulation.h"
#include "io/api/scenario_translation.h"
#include "io/recording/frame_log.h"

namespace lbsolid::server {

struct OutputFile {
  std::string name;  // "particles.h5", "particles.xdmf", "fields.h5", "fields.xdmf", "checkpoints/step-000000100.h5"
  std::string path;
  long long bytes = 0;
  std::string sha256;  // of the whole file, lowercase hex
  // The file's identity when it was hashed: a reader that opens `path` and finds another inode
  // has a newer version than this entry describes.
  std::uint64_t inode = 0;
};

class OutputRecorder {
 public:
  // Opens the log in `dir` (created), keeping what it recorded through `keep_through_step` (the
  // step the session starts from; later records are dropped and recorded again). Throws
  // std::runtime_error naming the path.
  OutputRecorder(std::string dir, OutputPlan plan, lbsolid::v1::Scenario scenario, std::string writer_version,
                 long keep_through_step);

  const OutputPlan& plan() const { return plan_; }
  // What is due at `step` and not recorded yet (target_reached: the step ends a run).
  bool particles_due(long step) const { return due(plan_.particles_every, last_particles_, step); }
  long last_particles_step() const { return last_particles_; }  // -1 before the first record
  bool profile_due(long step) const { return due(plan_.profile_every, last_profile_, step); }
  bool fields_due(long step, bool target_reached) const;
  bool anything_due(long step, bool target_reached) const {
    return particles_due(step) || profile_due(step) || fields_due(step, target_reached);
  }

  // On the stepping thread, under the simulation lock. Throw std::runtime_error on a failed write.
  void record_particles(const lbsolid::v1::ParticleFrame& frame);
  void record_profile(const lbsolid::v1::ProfileFrame& frame);
  void record_fields(long step, const scene::FluidFields& fields, const std::array<double, 3>& spacing);
  // Every record appended so far is durable (before a save claims the step it reached).
  void sync() { log_.sync(); }

  // The files as of everything recorded so far (made from the log if it grew since).
  // UNAVAILABLE naming the cause if a file cannot be made.
  absl::StatusOr<std::vector<OutputFile>> files();

 private:
  static bool due(long every, long last, long step) { return every > 0 && step % every == 0 && step > last; }
  void materialize();  // under files_mutex_

  const std::string dir_;
  const OutputPlan plan_;
  const lbsolid::v1::Scenario scenario_;
  const std::string writer_version_;
  recording::FrameLog log_;
  long last_particles_ = -1, last_profile_ = -1, last_fields_ = -1;  // steps of the last records

  std::mutex files_mutex_;
  std::uint64_t materialized_size_ = 0;  // log bytes the made files hold; 0: none made yet
  std::vector<OutputFile> made_;
};

// The checkpoints in `dir` (a session's), as "checkpoints/<file>", oldest first. `known` keeps
// each one's SHA-256 between calls, hashed again only if the file was replaced (a second
// checkpoint at the same step).
std::vector<OutputFile> list_checkpoints(const std::string& dir, std::map<std::string, OutputFile>& known);

}  // namespace lbsolid::server
