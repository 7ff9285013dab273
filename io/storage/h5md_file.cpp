// H5MD 1.1 writer (layout in h5md_file.h). Each time series is a group with three datasets that
// grow together: step int64 [frame], time float64 [frame] and value float64 [frame][...], chunked
// along the unlimited frame axis and written a chunk's worth of frames at a time. The file is
// opened with the 1.8 object format so the scenario text may exceed the 64 KiB attribute limit of
// the oldest format.
#include "io/storage/h5md_file.h"

#include <pwd.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <stdexcept>

#include "io/storage/file_replace.h"
#include "io/storage/hdf5_handles.h"
#include "io/storage/hdf5_io.h"
#include "io/storage/xdmf_text.h"

namespace lbsolid::server::storage {
namespace {

constexpr hsize_t kChunkBytes = 64 * 1024;  // frames per chunk chosen to fill about this much
constexpr hsize_t kMaxFramesPerChunk = 128;  // short runs stay small on disk
constexpr const char* kProfileName = "velocity_profile";

// Creates every missing group along an absolute path, each without time stamps (intermediate
// groups made by HDF5 itself would carry them).
h5::Group ensure_group(hid_t file, const std::string& path) {
  h5::Group group(h5::check(H5Gopen2(file, "/", H5P_DEFAULT), "cannot open /"));
  std::size_t begin = 1;
  while (begin < path.size()) {
    const std::size_t end = std::min(path.find('/', begin), path.size());
    group = h5::open_or_create_group(group.get(), path.substr(begin, end - begin));
    begin = end + 1;
  }
  return group;
}

hsize_t frames_per_chunk(const std::vector<hsize_t>& frame_shape) {
  const hsize_t frame_bytes = 8 * h5::element_count(frame_shape);
  return std::clamp<hsize_t>(kChunkBytes / frame_bytes, 1, kMaxFramesPerChunk);
}

h5::Dataset create_growing_dataset(hid_t group, const std::string& name, hid_t file_type,
                                   const std::vector<hsize_t>& frame_shape) {
  std::vector<hsize_t> dims{0}, max_dims{H5S_UNLIMITED}, chunk{frames_per_chunk(frame_shape)};
  for (hsize_t d : frame_shape) {
    dims.push_back(d);
    max_dims.push_back(d);
    chunk.push_back(d);
  }
  const h5::Dataspace space = h5::simple_space(dims, max_dims);
  const h5::PropertyList creation = h5::dataset_creation();
  h5::check_status(H5Pset_chunk(creation.get(), static_cast<int>(chunk.size()), chunk.data()), "cannot chunk " + name);
  return h5::Dataset(h5::check(H5Dcreate2(group, name.c_str(), file_type, space.get(), H5P_DEFAULT, creation.get(),
                                          H5P_DEFAULT),
                               "cannot create dataset " + name));
}

// Grows dataset by `frames` frames, from index `first`, and writes them.
void append_frames(hid_t dataset, hsize_t first, hsize_t frames, const std::vector<hsize_t>& frame_shape,
                   hid_t memory_type, const void* values, const std::string& name) {
  std::vector<hsize_t> dims{first + frames}, start{first}, count{frames};
  for (hsize_t d : frame_shape) {
    dims.push_back(d);
    start.push_back(0);
    count.push_back(d);
  }
  h5::check_status(H5Dset_extent(dataset, dims.data()), "cannot extend " + name);
  const h5::Dataspace file_space(h5::check(H5Dget_space(dataset), "cannot extend " + name));
  h5::check_status(H5Sselect_hyperslab(file_space.get(), H5S_SELECT_SET, start.data(), nullptr, count.data(), nullptr),
                   "cannot select frames of " + name);
  const h5::Dataspace memory_space = h5::simple_space(count);
  h5::check_status(H5Dwrite(dataset, memory_type, memory_space.get(), file_space.get(), H5P_DEFAULT, values),
                   "cannot write frames of " + name);
}

// One time series. Frames wait in memory until a chunk's worth (or a flush) and are then written
// in one extend-and-write per dataset: one call per frame and dataset made a 60-body, 300-frame
// file cost about 216,000 HDF5 writes.
struct Series {
  std::string group_path;
  std::vector<hsize_t> frame_shape;
  hsize_t frame_values = 0;      // doubles per frame
  hsize_t frames_per_write = 1;  // the value dataset's frames per chunk
  hsize_t frames = 0;            // frames in the file
  h5::Dataset step, time, value;
  std::vector<long> pending_steps;
  std::vector<double> pending_values;  // pending_steps.size() frames of frame_values each

  void add(long frame_step, const double* values) {
    pending_steps.push_back(frame_step);
    pending_values.insert(pending_values.end(), values, values + frame_values);
    if (pending_steps.size() >= frames_per_write) write_pending();
  }

  void write_pending() {
    const hsize_t count = pending_steps.size();
    if (count == 0) return;
    // lattice time: one unit per step
    const std::vector<double> times(pending_steps.begin(), pending_steps.end());
    append_frames(step.get(), frames, count, {}, H5T_NATIVE_LONG, pending_steps.data(), group_path + "/step");
    append_frames(time.get(), frames, count, {}, H5T_NATIVE_DOUBLE, times.data(), group_path + "/time");
    append_frames(value.get(), frames, count, frame_shape, H5T_NATIVE_DOUBLE, pending_values.data(),
                  group_path + "/value");
    frames += count;
    pending_steps.clear();
    pending_values.clear();
  }
};

void check_body_name(const std::string& body) {
  if (body.empty() || body == "." || body == ".." || body.find('/') != std::string::npos || body == kProfileName ||
      body == std::string(kProfileName) + "_y")
    throw std::invalid_argument("invalid body name \"" + body + "\" for an H5MD group");
}

// H5MD wants the person who ran the simulation; the daemon only knows its user account.
std::string author_name() {
  for (const char* variable : {"USER", "LOGNAME"})
    if (const char* name = std::getenv(variable); name != nullptr && *name != '\0') return name;
  passwd entry{};
  passwd* found = nullptr;
  std::array<char, 4096> buffer{};
  if (::getpwuid_r(::getuid(), &entry, buffer.data(), buffer.size(), &found) == 0 && found != nullptr)
    return found->pw_name;
  return "unknown";
}

}  // namespace

struct H5mdWriter::Impl {
  std::string path;
  std::string partial;
  H5mdBox box;
  h5::File file;  // declared before the series: closed after their datasets
  std::map<std::string, Series> series;         // by group path
  std::map<std::string, H5mdParticleSeries> particles;  // each body's particle count and frame steps
  std::vector<double> profile_y;
  bool closed = false;

  std::string context() const { return "H5MD file " + path; }

  void check_open() const {
    if (closed) throw std::logic_error(context() + ": already closed");
  }

  Series& series_at(const std::string& group_path, const std::vector<hsize_t>& frame_shape) {
    auto found = series.find(group_path);
    if (found != series.end()) return found->second;
    const h5::Group group = ensure_group(file.get(), group_path);
    Series s;
    s.group_path = group_path;
    s.frame_shape = frame_shape;
    s.frame_values = h5::element_count(frame_shape);
    s.frames_per_write = frames_per_chunk(frame_shape);
    s.step = create_growing_dataset(group.get(), "step", H5T_STD_I64LE, {});
    s.time = create_growing_dataset(group.get(), "time", H5T_IEEE_F64LE, {});
    s.value = create_growing_dataset(group.get(), "value", H5T_IEEE_F64LE, frame_shape);
    return series.emplace(group_path, std::move(s)).first->second;
  }

  void append(const std::string& group_path, const std::vector<hsize_t>& frame_shape, long step, const double* values) {
    series_at(group_path, frame_shape).add(step, values);
  }

  void write_pending() {
    for (auto& [path, s] : series) s.write_pending();
  }

  void write_header(const std::string& creator_version, const std::string& scenario_text) {
    const h5::Group h5md = ensure_group(file.get(), "/h5md");
    h5::write_attribute(h5md.get(), "version", std::vector<int>{1, 1});
    h5::write_string_attribute(ensure_group(file.get(), "/h5md/author").get(), "name", author_name());
    const h5::Group creator = ensure_group(file.get(), "/h5md/creator");
    h5::write_string_attribute(creator.get(), "name", "lbsolid");
    h5::write_string_attribute(creator.get(), "version", creator_version);
    h5::write_string_attribute(ensure_group(file.get(), "/parameters").get(), "scenario", scenario_text);
  }

  void write_box(const std::string& body) {
    const h5::Group group = ensure_group(file.get(), "/particles/" + body + "/box");
    h5::write_attribute(group.get(), "dimension", box.dimension);
    std::vector<std::string> boundary;
    for (int axis = 0; axis < box.dimension; ++axis) boundary.push_back(box.periodic[axis] ? "periodic" : "none");
    h5::write_string_array_attribute(group.get(), "boundary", boundary);
    h5::write_dataset<double>(group.get(), "edges", {hsize_t(box.dimension)}, box.edges.data());
  }

  void close_file() {
    closed = true;  // a failed close is not retried by the destructor: the .partial stays for inspection
    write_pending();
    h5::check_status(H5Fflush(file.get(), H5F_SCOPE_GLOBAL), "cannot flush");
    series.clear();
    h5::check_status(file.close(), "cannot close");
    replace_durably(partial, path);
    // ParaView's way in (xdmf_text.h); written only once the file it describes is in place.
    if (!particles.empty())
      write_text_file_replacing(xdmf_path_for(path),
                                h5md_particles_xdmf(std::filesystem::path(path).filename().string(), box.dimension,
                                                    particles));
  }
};

H5mdWriter::H5mdWriter(const std::string& path, const std::string& creator_version, const std::string& scenario_text,
                       const H5mdBox& box)
    : impl_(std::make_unique<Impl>()) {
  if (box.dimension != 2 && box.dimension != 3)
    throw std::invalid_argument("H5MD file " + path + ": box dimension " + std::to_string(box.dimension) +
                                " is not 2 or 3");
  impl_->path = path;
  // A name of this writer's own, created exclusively: two writers of one path (two runs recording
  // into one directory) never write into the same file; the last to close gives the path its file.
  static std::atomic<long> writers{0};
  impl_->partial = path + ".partial-" + std::to_string(::getpid()) + "-" + std::to_string(writers++);
  impl_->box = box;
  h5::with_context(impl_->context(), [&] {
    try {
      const h5::PropertyList creation = h5::file_creation();
      const h5::PropertyList access = h5::file_access_v18();
      impl_->file = h5::File(h5::check(H5Fcreate(impl_->partial.c_str(), H5F_ACC_EXCL, creation.get(), access.get()),
                                       "cannot create " + impl_->partial));
      impl_->write_header(creator_version, scenario_text);
    } catch (...) {
      impl_->file.close();
      remove_quietly(impl_->partial);
      throw;
    }
  });
}

H5mdWriter::~H5mdWriter() {
  if (impl_ == nullptr || impl_->closed) return;
  try {
    close();
  } catch (...) {
    // A destructor must not throw; the data stays in <path>.partial-<pid>-<n>.
  }
}

void H5mdWriter::append_particles(const std::string& body, long step, const std::vector<double>& positions,
                                  const std::vector<double>& velocities) {
  impl_->check_open();
  check_body_name(body);
  const std::size_t dimension = impl_->box.dimension;
  if (positions.empty() || positions.size() % dimension != 0 || velocities.size() != positions.size())
    throw std::invalid_argument(impl_->context() + ": body " + body + " needs " + std::to_string(dimension) +
                                " position and velocity values per particle, got " + std::to_string(positions.size()) +
                                " and " + std::to_string(velocities.size()));
  const std::size_t count = positions.size() / dimension;
  const auto known = impl_->particles.find(body);
  if (known != impl_->particles.end() && known->second.particles != count)
    throw std::invalid_argument(impl_->context() + ": body " + body + " has " + std::to_string(count) +
                                " particles, earlier frames had " + std::to_string(known->second.particles));
  h5::with_context(impl_->context(), [&] {
    if (known == impl_->particles.end()) {
      impl_->write_box(body);
      impl_->particles[body].particles = count;
    }
    const std::vector<hsize_t> shape{count, dimension};
    impl_->append("/particles/" + body + "/position", shape, step, positions.data());
    impl_->append("/particles/" + body + "/velocity", shape, step, velocities.data());
    impl_->particles[body].steps.push_back(step);
  });
}

void H5mdWriter::append_body(const std::string& body, long step, const std::array<double, 3>& centre_of_mass,
                             const std::array<double, 3>& velocity) {
  impl_->check_open();
  check_body_name(body);
  const std::vector<hsize_t> shape{hsize_t(impl_->box.dimension)};
  h5::with_context(impl_->context(), [&] {
    impl_->append("/observables/" + body + "/centre_of_mass", shape, step, centre_of_mass.data());
    impl_->append("/observables/" + body + "/velocity", shape, step, velocity.data());
  });
}

void H5mdWriter::append_rotation(const std::string& body, long step, const std::array<double, 3>& angular_momentum,
                                 const std::array<double, 3>& angular_velocity, double orientation,
                                 const std::array<double, 4>& orientation_quaternion,
                                 const std::array<double, 3>& torque) {
  impl_->check_open();
  check_body_name(body);
  h5::with_context(impl_->context(), [&] {
    impl_->append("/observables/" + body + "/angular_momentum", {3}, step, angular_momentum.data());
    impl_->append("/observables/" + body + "/angular_velocity", {3}, step, angular_velocity.data());
    impl_->append("/observables/" + body + "/orientation", {1}, step, &orientation);
    impl_->append("/observables/" + body + "/orientation_quaternion", {4}, step, orientation_quaternion.data());
    impl_->append("/observables/" + body + "/torque", {3}, step, torque.data());
  });
}

void H5mdWriter::append_anchor_force(const std::string& body, long step, const std::array<double, 3>& force) {
  impl_->check_open();
  check_body_name(body);
  h5::with_context(impl_->context(), [&] { impl_->append("/observables/" + body + "/anchor_force", {3}, step, force.data()); });
}

void H5mdWriter::append_broken_link_count(const std::string& body, long step, long count) {
  impl_->check_open();
  check_body_name(body);
  const double value = static_cast<double>(count);
  h5::with_context(impl_->context(), [&] { impl_->append("/observables/" + body + "/broken_link_count", {1}, step, &value); });
}

void H5mdWriter::append_broken_link(const std::string& body, long step, int particle, int link,
                                    const std::array<double, 3>& position) {
  impl_->check_open();
  check_body_name(body);
  const double row[5] = {static_cast<double>(particle), static_cast<double>(link), position[0], position[1], position[2]};
  h5::with_context(impl_->context(), [&] { impl_->append("/observables/" + body + "/broken_links", {5}, step, row); });
}

void H5mdWriter::append_profile(long step, const std::vector<double>& y, const std::vector<double>& u_x) {
  impl_->check_open();
  if (y.empty() || y.size() != u_x.size())
    throw std::invalid_argument(impl_->context() + ": a velocity profile needs as many u_x as y values (got " +
                                std::to_string(u_x.size()) + " and " + std::to_string(y.size()) + ")");
  if (!impl_->profile_y.empty() && impl_->profile_y != y)
    throw std::invalid_argument(impl_->context() + ": the velocity profile's y values changed between frames");
  h5::with_context(impl_->context(), [&] {
    if (impl_->profile_y.empty()) {
      const h5::Group observables = ensure_group(impl_->file.get(), "/observables");
      h5::write_dataset<double>(observables.get(), std::string(kProfileName) + "_y", {y.size()}, y.data());
      impl_->profile_y = y;
    }
    impl_->append(std::string("/observables/") + kProfileName, {y.size()}, step, u_x.data());
  });
}

void H5mdWriter::flush() {
  impl_->check_open();
  h5::with_context(impl_->context(), [&] {
    impl_->write_pending();
    h5::check_status(H5Fflush(impl_->file.get(), H5F_SCOPE_GLOBAL), "cannot flush");
  });
}

void H5mdWriter::close() {
  if (impl_->closed) return;
  h5::with_context(impl_->context(), [&] { impl_->close_file(); });
}

H5mdSeries read_h5md_series(const std::string& path, const std::string& group_path) {
  return h5::with_context("H5MD file " + path + ", series " + group_path, [&] {
    h5::File file(h5::check(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), "cannot open"));
    const h5::Group group = h5::open_group(file.get(), group_path);
    H5mdSeries result;
    const h5::DatasetValues<long> step = h5::read_dataset<long>(group.get(), "step");
    const h5::DatasetValues<double> time = h5::read_dataset<double>(group.get(), "time");
    h5::DatasetValues<double> value = h5::read_dataset<double>(group.get(), "value");
    if (value.dims.empty() || step.values.size() != value.dims[0] || time.values.size() != value.dims[0])
      throw std::runtime_error("step, time and value do not hold the same number of frames");
    result.step = step.values;
    result.time = time.values;
    result.value_shape.assign(value.dims.begin() + 1, value.dims.end());
    result.value = std::move(value.values);
    return result;
  });
}

}  // namespace lbsolid::server::storage
