// Checkpoint layout (format_version 1):
//   /                 attrs format = "lbsolid-checkpoint", format_version, lbsolid_version,
//                     git_revision, session_id, session_name, request_id, done, target_step, step
//   /scenario         string dataset: the scenario text, byte for byte
//   /fluid            (with a fluid) attrs steps, current, pulled, stepped, buffers, cells;
//   /fluid/populations  float64 [buffers * Q * cells], exactly FluidRawState::populations
//   /solid            (with bodies) positions [n][3], incoming [m][3], momentum [n][3], float64
// Booleans are int32 0/1. Strings are fixed-length and exact (hdf5_io.h).
#include "server/storage/checkpoint_file.h"

#include <filesystem>
#include <stdexcept>

#include "server/storage/file_replace.h"
#include "server/storage/hdf5_handles.h"
#include "server/storage/hdf5_io.h"

namespace lbsolid::server::storage {
namespace {

constexpr const char* kFormatName = "lbsolid-checkpoint";

using Vec3List = std::vector<solid::Vec3>;
static_assert(sizeof(solid::Vec3) == 3 * sizeof(double), "Vec3 lists are written as [n][3] doubles");

void write_vec3_list(hid_t group, const std::string& name, const Vec3List& values) {
  h5::write_dataset<double>(group, name, {values.size(), 3}, values.empty() ? nullptr : values[0].data());
}

Vec3List read_vec3_list(hid_t group, const std::string& name) {
  const h5::DatasetValues<double> data = h5::read_dataset<double>(group, name);
  if (data.dims.size() != 2 || data.dims[1] != 3)
    throw std::runtime_error("dataset /solid/" + name + " is not an [n][3] array");
  Vec3List values(data.dims[0]);
  for (std::size_t i = 0; i < values.size(); ++i)
    for (int k = 0; k < 3; ++k) values[i][k] = data.values[3 * i + k];
  return values;
}

void write_fluid(hid_t file, const fluid::FluidRawState& fluid) {
  const h5::Group group = h5::create_group(file, "fluid");
  h5::write_attribute(group.get(), "steps", fluid.steps);
  h5::write_attribute(group.get(), "current", fluid.current);
  h5::write_attribute(group.get(), "pulled", static_cast<int>(fluid.pulled));
  h5::write_attribute(group.get(), "stepped", static_cast<int>(fluid.stepped));
  h5::write_attribute(group.get(), "buffers", fluid.buffers);
  h5::write_attribute(group.get(), "cells", fluid.cells);
  h5::write_dataset<double>(group.get(), "populations", {fluid.populations.size()}, fluid.populations.data());
}

fluid::FluidRawState read_fluid(hid_t file) {
  const h5::Group group = h5::open_group(file, "fluid");
  fluid::FluidRawState fluid;
  fluid.steps = h5::read_attribute<long>(group.get(), "steps");
  fluid.current = h5::read_attribute<int>(group.get(), "current");
  fluid.pulled = h5::read_attribute<int>(group.get(), "pulled") != 0;
  fluid.stepped = h5::read_attribute<int>(group.get(), "stepped") != 0;
  fluid.buffers = h5::read_attribute<int>(group.get(), "buffers");
  fluid.cells = h5::read_attribute<long>(group.get(), "cells");
  h5::DatasetValues<double> populations = h5::read_dataset<double>(group.get(), "populations");
  if (populations.dims.size() != 1) throw std::runtime_error("dataset /fluid/populations is not 1-D");
  // Q is the lattice's business; the count must at least be whole populations of every cell.
  const long per_population = static_cast<long>(fluid.buffers) * fluid.cells;
  const long count = static_cast<long>(populations.values.size());
  if (fluid.buffers < 0 || fluid.cells < 0 || (per_population > 0 && count % per_population != 0) ||
      (per_population == 0 && count != 0))
    throw std::runtime_error("dataset /fluid/populations holds " + std::to_string(count) +
                             " values, not a multiple of buffers (" + std::to_string(fluid.buffers) +
                             ") x cells (" + std::to_string(fluid.cells) + ")");
  fluid.populations = std::move(populations.values);
  return fluid;
}

void write_solid(hid_t file, const solid::SolidState& solid) {
  const h5::Group group = h5::create_group(file, "solid");
  write_vec3_list(group.get(), "positions", solid.positions);
  write_vec3_list(group.get(), "incoming", solid.incoming);
  write_vec3_list(group.get(), "momentum", solid.momentum);
}

solid::SolidState read_solid(hid_t file) {
  const h5::Group group = h5::open_group(file, "solid");
  solid::SolidState solid;
  solid.positions = read_vec3_list(group.get(), "positions");
  solid.incoming = read_vec3_list(group.get(), "incoming");
  solid.momentum = read_vec3_list(group.get(), "momentum");
  const std::size_t n = solid.positions.size();
  if (solid.momentum.size() != n)
    throw std::runtime_error("/solid has " + std::to_string(n) + " positions but " +
                             std::to_string(solid.momentum.size()) + " momenta");
  if ((n == 0 && !solid.incoming.empty()) || (n > 0 && solid.incoming.size() % n != 0))
    throw std::runtime_error("/solid/incoming holds " + std::to_string(solid.incoming.size()) +
                             " links, not a multiple of the " + std::to_string(n) + " particles");
  return solid;
}

// Refused before anything is written, so a bad state never replaces a good checkpoint.
void check_writable(const scene::SimulationState& state) {
  if (state.has_solid && state.solid.momentum.size() != state.solid.positions.size())
    throw std::runtime_error("solid state has " + std::to_string(state.solid.positions.size()) + " positions but " +
                             std::to_string(state.solid.momentum.size()) + " momenta");
}

void write_contents(const std::string& file_path, const CheckpointContents& contents, const WriterInfo& writer) {
  const h5::PropertyList creation = h5::file_creation();
  h5::File file(h5::check(H5Fcreate(file_path.c_str(), H5F_ACC_TRUNC, creation.get(), H5P_DEFAULT),
                          "cannot create " + file_path));
  const hid_t root = file.get();
  h5::write_string_attribute(root, "format", kFormatName);
  h5::write_attribute(root, "format_version", kCheckpointFormatVersion);
  h5::write_string_attribute(root, "lbsolid_version", writer.version);
  h5::write_string_attribute(root, "git_revision", writer.git_revision);
  h5::write_string_attribute(root, "session_id", contents.session_id);
  h5::write_string_attribute(root, "session_name", contents.session_name);
  h5::write_string_attribute(root, "request_id", contents.request_id);
  h5::write_attribute(root, "done", static_cast<int>(contents.done));
  h5::write_attribute(root, "target_step", contents.target_step);
  h5::write_attribute(root, "step", contents.state.step);
  h5::write_string_dataset(root, "scenario", contents.scenario_text);
  if (contents.state.has_fluid) write_fluid(root, contents.state.fluid);
  if (contents.state.has_solid) write_solid(root, contents.state.solid);
  h5::check_status(H5Fflush(root, H5F_SCOPE_GLOBAL), "cannot flush " + file_path);
  // Closing writes the remaining metadata: its failure is a failed checkpoint.
  h5::check_status(file.close(), "cannot close " + file_path);
}

void check_format(hid_t root) {
  if (H5Aexists(root, "format") <= 0 || h5::read_string_attribute(root, "format") != kFormatName)
    throw std::runtime_error(std::string("not an lbsolid checkpoint (no format attribute \"") + kFormatName + "\")");
  const int version = h5::read_attribute<int>(root, "format_version");
  if (version > kCheckpointFormatVersion)
    throw std::runtime_error("checkpoint format version " + std::to_string(version) +
                             " is newer than this build reads (version " + std::to_string(kCheckpointFormatVersion) +
                             " and older)");
  if (version < 1) throw std::runtime_error("invalid checkpoint format version " + std::to_string(version));
}

CheckpointContents read_contents(const std::string& path) {
  if (!std::filesystem::exists(path)) throw std::runtime_error("no such file");
  if (H5Fis_hdf5(path.c_str()) <= 0) {
    h5::take_error_cause();
    throw std::runtime_error("not an HDF5 file");
  }
  h5::File file(h5::check(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), "cannot open"));
  const hid_t root = file.get();
  check_format(root);
  CheckpointContents contents;
  contents.session_id = h5::read_string_attribute(root, "session_id");
  contents.session_name = h5::read_string_attribute(root, "session_name");
  contents.request_id = h5::read_string_attribute(root, "request_id");
  contents.done = h5::read_attribute<int>(root, "done") != 0;
  contents.target_step = h5::read_attribute<long>(root, "target_step");
  contents.scenario_text = h5::read_string_dataset(root, "scenario");
  contents.state.step = h5::read_attribute<long>(root, "step");
  contents.state.has_fluid = h5::has_link(root, "fluid");
  if (contents.state.has_fluid) contents.state.fluid = read_fluid(root);
  contents.state.has_solid = h5::has_link(root, "solid");
  if (contents.state.has_solid) contents.state.solid = read_solid(root);
  return contents;
}

}  // namespace

void write_checkpoint(const std::string& path, const CheckpointContents& contents, const WriterInfo& writer) {
  h5::with_context("cannot write checkpoint " + path, [&] {
    check_writable(contents.state);
    const std::string temporary = temporary_path_for(path);
    try {
      write_contents(temporary, contents, writer);
      replace_durably(temporary, path);
    } catch (...) {
      remove_quietly(temporary);  // the target was not touched
      throw;
    }
  });
}

CheckpointContents read_checkpoint(const std::string& path) {
  return h5::with_context("cannot read checkpoint " + path, [&] { return read_contents(path); });
}

}  // namespace lbsolid::server::storage
