#pragma once
// What the daemon keeps of its sessions on disk, under data_dir:
//   checkpoints/<session id>/step-<step>.h5   taken by Checkpoint calls (kept after deletion)
//   sessions/<session id>/session.h5          the session's last save (autosave, shutdown)
//   sessions/<session id>/progress            the last step a worker reached ("steps lost")
//   outputs/<session id>/                     what scenario.outputs records (output_recorder.h),
//                                             kept until the session is deleted
//   uploads/                                  UploadCheckpoint's files while they arrive (emptied at start)
// Every file is written to a temporary file of its own, fsync'ed and renamed (storage/). Writes
// of one session are serialised (Session::lock_saves). Paths are built only from validated ids.
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "server/session/session.h"
#include "io/storage/checkpoint_file.h"

namespace lbsolid::server {

struct CheckpointInfo {
  std::string checkpoint_id;  // "<session id>/step-<step>"
  std::string path;
  long step = 0;
  long bytes = 0;
};

// A session saved by an earlier daemon.
struct SavedSession {
  storage::CheckpointContents contents;  // its session_id is valid and names its directory
  long steps_lost = 0;                   // steps its worker had reached past the save
};

class SessionStore {
 public:
  // Creates the directories and removes temporary files left by a daemon killed mid-write.
  // Throws std::filesystem::filesystem_error if data_dir cannot be used.
  SessionStore(std::string data_dir, storage::WriterInfo writer);

  const storage::WriterInfo& writer() const { return writer_; }

  absl::StatusOr<CheckpointInfo> checkpoint(const Session& session) const;
  // NOT_FOUND, INVALID_ARGUMENT (malformed id) or DATA_LOSS (unreadable, corrupt, checksum).
  absl::StatusOr<storage::CheckpointContents> read_checkpoint(const std::string& checkpoint_id) const;
  // An uploaded checkpoint file (under upload_dir()): DATA_LOSS naming what failed.
  absl::StatusOr<storage::CheckpointContents> read_checkpoint_file(const std::string& path) const;
  std::string upload_dir() const;

  // Writes the session's state for the next start, unless it is FAILED or CANCELLED (those are
  // not kept: their saved state is removed). Returns the step saved.
  absl::StatusOr<long> save(const Session& session) const;
  // Removes the session's saved state (deleted, failed or cancelled): it never comes back.
  void forget(const Session& session) const;
  // Removes what the session recorded (it is deleted).
  void forget_outputs(const Session& session) const;
  // Removes the outputs of sessions that did not come back (FAILED or CANCELLED before a restart,
  // or lost before their first save): no call can reach them any more. Returns how many.
  int remove_orphan_outputs(const std::vector<std::string>& kept_ids) const;
  std::string outputs_dir(const std::string& id) const;
  std::string checkpoint_dir(const std::string& id) const;
  // Records that the session reached `step` (cheap; for the steps-lost figure after a crash).
  void note_progress(const Session& session, long step) const;

  // Every session an earlier daemon saved; those that cannot be read are logged and skipped.
  std::vector<SavedSession> saved_sessions() const;

 private:
  std::string session_dir(const std::string& id) const;
  void remove_partial_writes() const;

  const std::string data_dir_;
  const storage::WriterInfo writer_;
};

}  // namespace lbsolid::server
