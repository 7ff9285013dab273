#include "server/session/session_store.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <filesystem>
#include <vector>
#include <fstream>

#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "io/api/log_text.h"
#include "server/session/session_id.h"
#include "io/storage/file_replace.h"

namespace lbsolid::server {

namespace fs = std::filesystem;

namespace {

constexpr const char* kSavedFile = "session.h5";
constexpr const char* kProgressFile = "progress";

// The step in a progress file, or -1 if it is missing or not a number.
long read_progress(const fs::path& file) {
  std::ifstream in(file);
  std::string text;
  long step = -1;
  if (!(in >> text) || !absl::SimpleAtoi(text, &step) || step < 0) return -1;
  return step;
}

}  // namespace

SessionStore::SessionStore(std::string data_dir, storage::WriterInfo writer)
    : data_dir_(std::move(data_dir)), writer_(std::move(writer)) {
  fs::create_directories(fs::path(data_dir_) / "sessions");
  fs::create_directories(fs::path(data_dir_) / "checkpoints");
  fs::create_directories(fs::path(data_dir_) / "outputs");
  fs::remove_all(upload_dir());  // uploads a killed daemon was receiving: their clients retry
  fs::create_directories(upload_dir());
  remove_partial_writes();
}

std::string SessionStore::session_dir(const std::string& id) const {
  if (!valid_session_id(id)) throw std::logic_error("invalid session id reached the store");
  return (fs::path(data_dir_) / "sessions" / id).string();
}

std::string SessionStore::outputs_dir(const std::string& id) const {
  if (!valid_session_id(id)) throw std::logic_error("invalid session id reached the store");
  return (fs::path(data_dir_) / "outputs" / id).string();
}

std::string SessionStore::checkpoint_dir(const std::string& id) const {
  if (!valid_session_id(id)) throw std::logic_error("invalid session id reached the store");
  return (fs::path(data_dir_) / "checkpoints" / id).string();
}

int SessionStore::remove_orphan_outputs(const std::vector<std::string>& kept_ids) const {
  std::vector<fs::path> orphans;
  std::error_code ignored;
  for (const auto& entry : fs::directory_iterator(fs::path(data_dir_) / "outputs", ignored))
    if (std::find(kept_ids.begin(), kept_ids.end(), entry.path().filename().string()) == kept_ids.end())
      orphans.push_back(entry.path());
  for (const auto& path : orphans) {
    fs::remove_all(path, ignored);
    spdlog::info("removed {}: the outputs of a session that did not come back", log_text(path.string(), 500));
  }
  return static_cast<int>(orphans.size());
}

void SessionStore::forget_outputs(const Session& session) const {
  std::error_code ignored;
  fs::remove_all(outputs_dir(session.id()), ignored);
}

// Every file is written as <file>.tmp-<unique> and renamed; a daemon killed mid-write leaves the
// temporary file behind (the old file is intact). Nothing else writes such names: remove them.
// Outputs are made in outputs/<id>/.build-<n>/ and renamed out of it: such a directory is one too.
void SessionStore::remove_partial_writes() const {
  std::vector<fs::path> partial;
  for (const auto& entry : fs::recursive_directory_iterator(data_dir_)) {
    const std::string name = entry.path().filename().string();
    if ((entry.is_regular_file() && name.find(".tmp-") != std::string::npos) ||
        (entry.is_directory() && name.starts_with(".build-")))
      partial.push_back(entry.path());
  }
  for (const auto& path : partial) {
    std::error_code ignored;
    fs::remove_all(path, ignored);
    spdlog::warn("removed {}: a write interrupted by an earlier daemon", log_text(path.string(), 500));
  }
}

absl::StatusOr<CheckpointInfo> SessionStore::checkpoint(const Session& session) const {
  const auto saves = session.lock_saves();  // concurrent Checkpoint calls: one at a time
  const auto contents = session.checkpoint_contents();
  CheckpointInfo info;
  info.step = contents.state.step;
  info.checkpoint_id = absl::StrFormat("%s/step-%09d", session.id(), info.step);
  const fs::path path = fs::path(data_dir_) / "checkpoints" / (info.checkpoint_id + ".h5");
  try {
    fs::create_directories(path.parent_path());
    storage::write_checkpoint(path.string(), contents, writer_);
    info.path = path.string();
    info.bytes = static_cast<long>(fs::file_size(path));
  } catch (const std::exception& e) {
    spdlog::error("session {}: checkpoint failed: {}", session.id(), log_text(e.what(), 1000));
    return absl::UnavailableError(absl::StrCat("checkpoint: not written (the session is unaffected): ", e.what()));
  }
  spdlog::info("session {}: checkpoint {} ({} bytes)", session.id(), info.checkpoint_id, info.bytes);
  return info;
}

absl::StatusOr<storage::CheckpointContents> SessionStore::read_checkpoint(const std::string& checkpoint_id) const {
  if (!valid_checkpoint_id(checkpoint_id))
    return absl::InvalidArgumentError(absl::StrCat("checkpoint_id: \"", checkpoint_id.substr(0, 100),
                                                   "\" is not of the form <session id>/step-<step>"));
  const fs::path path = fs::path(data_dir_) / "checkpoints" / (checkpoint_id + ".h5");
  if (!fs::exists(path)) return absl::NotFoundError(absl::StrCat("checkpoint_id: no checkpoint \"", checkpoint_id, "\""));
  try {
    return storage::read_checkpoint(path.string());
  } catch (const std::exception& e) {
    return absl::DataLossError(absl::StrCat("checkpoint_id: ", e.what()));
  }
}

absl::StatusOr<storage::CheckpointContents> SessionStore::read_checkpoint_file(const std::string& path) const {
  try {
    return storage::read_checkpoint(path);
  } catch (const std::exception& e) {
    return absl::DataLossError(absl::StrCat("data: the uploaded checkpoint: ", e.what()));
  }
}

std::string SessionStore::upload_dir() const { return (fs::path(data_dir_) / "uploads").string(); }

absl::StatusOr<long> SessionStore::save(const Session& session) const {
  const auto saves = session.lock_saves();
  const fs::path dir = session_dir(session.id());
  if (is_final(session.state())) {
    std::error_code ignored;
    fs::remove_all(dir, ignored);
    return absl::FailedPreconditionError(absl::StrCat("save: the session is ", v1::SessionState_Name(session.state()),
                                                      " and is not kept"));
  }
  const auto contents = session.checkpoint_contents();  // a copy, under the simulation lock
  try {
    session.sync_outputs();  // the frames through the saved step are on disk first
    fs::create_directories(dir);
    storage::write_checkpoint((dir / kSavedFile).string(), contents, writer_);
  } catch (const std::exception& e) {
    return absl::UnavailableError(absl::StrCat("save: ", e.what()));
  }
  return contents.state.step;
}

void SessionStore::forget(const Session& session) const {
  const auto saves = session.lock_saves();  // after any save in progress, so none comes back
  std::error_code ignored;
  fs::remove_all(session_dir(session.id()), ignored);
}

void SessionStore::note_progress(const Session& session, long step) const {
  // A worker calls this: it never waits for a save in progress (try_lock), it skips a note.
  std::unique_lock saves(session.saves_mutex(), std::try_to_lock);
  if (!saves.owns_lock() || is_final(session.state())) return;
  try {
    const fs::path dir = session_dir(session.id());
    fs::create_directories(dir);
    // Renamed into place but not fsync'ed: it survives a killed daemon (the kernel holds it), and
    // after a power loss an older figure only understates the steps lost. Several a second are cheap.
    const std::string target = (dir / kProgressFile).string();
    storage::TemporaryFile temporary(target);
    temporary.write(absl::StrCat(step, "\n"));
    temporary.close_descriptor();
    fs::rename(temporary.path(), target);
  } catch (const std::exception& e) {
    spdlog::warn("session {}: progress not recorded: {}", session.id(), log_text(e.what(), 1000));
  }
}

std::vector<SavedSession> SessionStore::saved_sessions() const {
  std::vector<SavedSession> saved;
  for (const auto& entry : fs::directory_iterator(fs::path(data_dir_) / "sessions")) {
    const std::string name = entry.path().filename().string();
    const fs::path file = entry.path() / kSavedFile;
    if (!valid_session_id(name)) {
      spdlog::error("{}: ignored: not a session directory (its name is not a session id)",
                    log_text(entry.path().string()));
      continue;
    }
    if (!fs::exists(file)) {
      spdlog::error("session {}: lost: it was never saved before the daemon stopped", log_text(name));
      std::error_code ignored;
      fs::remove_all(entry.path(), ignored);
      continue;
    }
    try {
      SavedSession s;
      s.contents = storage::read_checkpoint(file.string());
      if (s.contents.session_id != name)
        throw std::runtime_error("its session_id attribute does not name its directory");
      const long reached = read_progress(entry.path() / kProgressFile);
      s.steps_lost = std::max(0L, reached - s.contents.state.step);
      saved.push_back(std::move(s));
    } catch (const std::exception& e) {
      spdlog::error("{}: not recovered: {}", log_text(file.string(), 500), log_text(e.what(), 1000));
    }
  }
  return saved;
}

}  // namespace lbsolid::server
