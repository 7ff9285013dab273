#include "server/session/output_recorder.h"

#include <sys/stat.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <cstring>
#include <filesystem>

#include "absl/strings/str_cat.h"
#include "lbsolid/v1/simulation.pb.h"
#include "io/recording/h5md_frames.h"
#include "io/recording/scenario_geometry.h"
#include "io/storage/field_snapshot.h"
#include "io/storage/h5md_file.h"
#include "io/storage/sha256.h"

namespace lbsolid::server {

namespace {

namespace fs = std::filesystem;
using recording::RecordKind;

constexpr char kLogFile[] = "frames.log";
constexpr char kParticlesFile[] = "particles.h5";
constexpr char kFieldsFile[] = "fields.h5";

// A field snapshot's record: nx, ny, nz (int64), spacing x, y, z (float64), density, velocity.
std::string encode_fields(const scene::FluidFields& fields, const std::array<double, 3>& spacing) {
  static_assert(std::endian::native == std::endian::little, "records are written as the machine stores them");
  std::string out;
  for (const int n : fields.shape) {
    const std::int64_t value = n;
    out.append(reinterpret_cast<const char*>(&value), sizeof value);
  }
  out.append(reinterpret_cast<const char*>(spacing.data()), sizeof(double) * 3);
  out.append(reinterpret_cast<const char*>(fields.density.data()), sizeof(double) * fields.density.size());
  out.append(reinterpret_cast<const char*>(fields.velocity.data()), sizeof(double) * fields.velocity.size());
  return out;
}

void decode_fields(std::string_view in, scene::FluidFields& fields, std::array<double, 3>& spacing) {
  constexpr std::size_t kHead = 3 * sizeof(std::int64_t) + 3 * sizeof(double);
  if (in.size() < kHead) throw std::runtime_error("a field record is too short");
  long long nodes = 1;
  for (int a = 0; a < 3; ++a) {
    std::int64_t n = 0;
    std::memcpy(&n, in.data() + a * sizeof n, sizeof n);
    if (n < 1 || n > (1LL << 31)) throw std::runtime_error("a field record has an impossible shape");
    fields.shape[a] = static_cast<int>(n);
    nodes *= n;
  }
  std::memcpy(spacing.data(), in.data() + 3 * sizeof(std::int64_t), sizeof(double) * 3);
  if (in.size() != kHead + 4 * sizeof(double) * static_cast<std::size_t>(nodes))
    throw std::runtime_error("a field record's size does not match its shape");
  fields.density.resize(nodes);
  fields.velocity.resize(3 * nodes);
  std::memcpy(fields.density.data(), in.data() + kHead, sizeof(double) * nodes);
  std::memcpy(fields.velocity.data(), in.data() + kHead + sizeof(double) * nodes, sizeof(double) * 3 * nodes);
}

std::uint64_t inode_of(const fs::path& path) {
  struct stat info {};
  if (::stat(path.c_str(), &info) != 0) throw std::runtime_error(path.string() + ": cannot stat");
  return info.st_ino;
}

OutputFile describe(const std::string& name, const fs::path& path) {
  const std::uint64_t inode = inode_of(path);  // before hashing: a newer file would then differ
  return {name, path.string(), static_cast<long long>(fs::file_size(path)), storage::sha256_file_hex(path.string()),
          inode};
}

}  // namespace

OutputRecorder::OutputRecorder(std::string dir, OutputPlan plan, lbsolid::v1::Scenario scenario,
                               std::string writer_version, long keep_through_step)
    : dir_(std::move(dir)),
      plan_(std::move(plan)),
      scenario_(std::move(scenario)),
      writer_version_(std::move(writer_version)),
      log_((fs::create_directories(dir_), (fs::path(dir_) / kLogFile).string()), keep_through_step) {
  recording::read_frame_log(log_.path(), log_.size(), [&](const recording::LogRecord& r) {
    long& last = r.kind == RecordKind::kParticles ? last_particles_
                 : r.kind == RecordKind::kProfile ? last_profile_
                                                  : last_fields_;
    last = std::max(last, r.step);
  });
}

bool OutputRecorder::fields_due(long step, bool target_reached) const {
  if (step <= last_fields_) return false;
  return (plan_.fields_every > 0 && step % plan_.fields_every == 0) || (plan_.final_fields && target_reached);
}

void OutputRecorder::record_particles(const lbsolid::v1::ParticleFrame& frame) {
  log_.append(RecordKind::kParticles, frame.step(), frame.SerializeAsString());
  last_particles_ = frame.step();
}

void OutputRecorder::record_profile(const lbsolid::v1::ProfileFrame& frame) {
  log_.append(RecordKind::kProfile, frame.step(), frame.SerializeAsString());
  last_profile_ = frame.step();
}

void OutputRecorder::record_fields(long step, const scene::FluidFields& fields, const std::array<double, 3>& spacing) {
  log_.append(RecordKind::kFields, step, encode_fields(fields, spacing));
  last_fields_ = step;
}

void OutputRecorder::materialize() {
  static std::atomic<long> builds{0};
  const std::uint64_t size = log_.size();
  const fs::path build = fs::path(dir_) / absl::StrCat(".build-", builds++);
  fs::remove_all(build);
  fs::create_directories(build);
  struct RemoveOnExit {
    fs::path dir;
    ~RemoveOnExit() {
      std::error_code ignored;
      fs::remove_all(dir, ignored);
    }
  } cleanup{build};
  const int dimension = recording::dimension(scenario_);
  std::unique_ptr<storage::H5mdWriter> h5md;
  bool fields = false;
  recording::read_frame_log(log_.path(), size, [&](const recording::LogRecord& r) {
    if (r.kind == RecordKind::kFields) {
      scene::FluidFields snapshot;
      storage::SnapshotGeometry geometry;
      decode_fields(r.payload, snapshot, geometry.spacing);
      storage::append_field_snapshot((build / kFieldsFile).string(), snapshot, r.step, geometry);
      fields = true;
      return;
    }
    if (!h5md)
      h5md = std::make_unique<storage::H5mdWriter>((build / kParticlesFile).string(), writer_version_,
                                                   scenario_to_text(scenario_), recording::h5md_box(scenario_));
    if (r.kind == RecordKind::kParticles) {
      lbsolid::v1::ParticleFrame frame;
      if (!frame.ParseFromArray(r.payload.data(), static_cast<int>(r.payload.size())))
        throw std::runtime_error("a particle record does not parse");
      recording::append_particle_frame(*h5md, frame, dimension);
    } else {
      lbsolid::v1::ProfileFrame frame;
      if (!frame.ParseFromArray(r.payload.data(), static_cast<int>(r.payload.size())))
        throw std::runtime_error("a profile record does not parse");
      recording::append_profile_frame(*h5md, frame);
    }
  });
  if (h5md) h5md->close();
  std::vector<std::string> names;
  if (h5md) {
    names.push_back(kParticlesFile);
    const std::string xdmf = fs::path(storage::xdmf_path_for(kParticlesFile)).filename().string();
    if (fs::exists(build / xdmf)) names.push_back(xdmf);  // written when there were particles
  }
  if (fields) {
    names.push_back(kFieldsFile);
    names.push_back(fs::path(storage::xdmf_path_for(kFieldsFile)).filename().string());
  }
  std::vector<OutputFile> made;
  for (const auto& name : names) {
    fs::rename(build / name, fs::path(dir_) / name);  // each file whole, old or new
    made.push_back(describe(name, fs::path(dir_) / name));
  }
  made_ = std::move(made);
  materialized_size_ = size;
}

absl::StatusOr<std::vector<OutputFile>> OutputRecorder::files() {
  std::lock_guard lock(files_mutex_);
  try {
    if (log_.size() != materialized_size_) materialize();
    return made_;
  } catch (const std::exception& e) {
    return absl::UnavailableError(absl::StrCat("outputs: cannot make the files: ", e.what()));
  }
}

std::vector<OutputFile> list_checkpoints(const std::string& dir, std::map<std::string, OutputFile>& known) {
  std::vector<fs::path> found;
  std::error_code missing;
  for (const auto& entry : fs::directory_iterator(dir, missing))
    if (entry.is_regular_file() && entry.path().extension() == ".h5" &&
        entry.path().filename().string().find(".tmp-") == std::string::npos)
      found.push_back(entry.path());
  std::sort(found.begin(), found.end());
  std::vector<OutputFile> out;
  for (const auto& path : found) {
    const std::string name = "checkpoints/" + path.filename().string();
    const auto it = known.find(name);
    if (it == known.end() || it->second.inode != inode_of(path)) known[name] = describe(name, path);
    out.push_back(known.at(name));
  }
  return out;
}

}  // namespace lbsolid::server
