#include "io/storage/checkpoint_layout.h"

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <stdexcept>
#include <vector>

#include "io/storage/checkpoint_checksum.h"
#include "io/storage/hdf5_handles.h"
#include "io/storage/hdf5_io.h"

namespace lbsolid::server::storage {
namespace {

constexpr const char* kFormatName = "lbsolid-checkpoint";

using Vec3List = std::vector<solid::Vec3>;

// Fracture (format 4), each present only when not empty: the broken links as rows of step,
// particle, link, x, y, z (float64, so integers are exact up to 2^53), the shed momentum per body.
constexpr const char* kBrokenLinks = "/solid/broken_links";
constexpr const char* kShedMomentum = "/solid/shed_momentum";
constexpr std::uint64_t kBrokenLinkColumns = 6;
constexpr double kLargestExactInteger = 9007199254740992.0;  // 2^53

std::vector<double> broken_link_rows(const std::vector<solid::BrokenLink>& broken) {
  std::vector<double> rows;
  rows.reserve(broken.size() * kBrokenLinkColumns);
  for (const auto& link : broken) {
    if (static_cast<double>(link.step) >= kLargestExactInteger)
      throw std::runtime_error("a broken link's step " + std::to_string(link.step) + " is past 2^53");
    rows.insert(rows.end(), {static_cast<double>(link.step), static_cast<double>(link.particle),
                             static_cast<double>(link.link), link.position[0], link.position[1], link.position[2]});
  }
  return rows;
}
static_assert(sizeof(solid::Vec3) == 3 * sizeof(double), "Vec3 lists are written as [n][3] doubles");

const double* data_of(const Vec3List& values) { return values.empty() ? nullptr : values[0].data(); }

// --- writing ----------------------------------------------------------------------------------

DatasetChecksums checksums_of(const CheckpointContents& contents) {
  DatasetChecksums sums;
  sums["/scenario"] = text_checksum(contents.scenario_text);
  const scene::SimulationState& state = contents.state;
  if (state.has_fluid) {
    const auto& populations = state.fluid.populations;
    sums["/fluid/populations"] = values_checksum({populations.size()}, populations.data(), populations.size());
  }
  if (state.has_solid) {
    for (const auto& [path, list] :
         {std::pair{"/solid/positions", &state.solid.positions}, std::pair{"/solid/incoming", &state.solid.incoming},
          std::pair{"/solid/momentum", &state.solid.momentum}})
      sums[path] = values_checksum({list->size(), 3}, data_of(*list), 3 * list->size());
    if (!state.solid.broken.empty()) {
      const std::vector<double> rows = broken_link_rows(state.solid.broken);
      sums[kBrokenLinks] = values_checksum({state.solid.broken.size(), kBrokenLinkColumns}, rows.data(), rows.size());
    }
    if (!state.solid.shed_momentum.empty()) {
      const auto& shed = state.solid.shed_momentum;
      sums[kShedMomentum] = values_checksum({shed.size(), 3}, data_of(shed), 3 * shed.size());
    }
  }
  return sums;
}

void attach_checksum(hid_t file, const std::string& path, const DatasetChecksums& sums) {
  const h5::Dataset dataset(h5::check(H5Dopen2(file, path.c_str(), H5P_DEFAULT), "cannot open dataset " + path));
  h5::write_string_attribute(dataset.get(), kChecksumAttribute, sums.at(path));
}

void write_vec3_list(hid_t file, const std::string& path, const Vec3List& values, const DatasetChecksums& sums) {
  h5::write_dataset<double>(file, path, {values.size(), 3}, data_of(values));
  attach_checksum(file, path, sums);
}

void write_fluid(hid_t file, const fluid::FluidRawState& fluid, const DatasetChecksums& sums) {
  const h5::Group group = h5::create_group(file, "fluid");
  h5::write_attribute(group.get(), "steps", fluid.steps);
  h5::write_attribute(group.get(), "current", fluid.current);
  h5::write_attribute(group.get(), "pulled", static_cast<int>(fluid.pulled));
  h5::write_attribute(group.get(), "stepped", static_cast<int>(fluid.stepped));
  h5::write_attribute(group.get(), "buffers", fluid.buffers);
  h5::write_attribute(group.get(), "cells", fluid.cells);
  h5::write_dataset<double>(file, "/fluid/populations", {fluid.populations.size()}, fluid.populations.data());
  attach_checksum(file, "/fluid/populations", sums);
}

void write_solid(hid_t file, const solid::SolidState& solid, const DatasetChecksums& sums) {
  h5::create_group(file, "solid");
  write_vec3_list(file, "/solid/positions", solid.positions, sums);
  write_vec3_list(file, "/solid/incoming", solid.incoming, sums);
  write_vec3_list(file, "/solid/momentum", solid.momentum, sums);
  if (!solid.broken.empty()) {
    const std::vector<double> rows = broken_link_rows(solid.broken);
    h5::write_dataset<double>(file, kBrokenLinks, {solid.broken.size(), kBrokenLinkColumns}, rows.data());
    attach_checksum(file, kBrokenLinks, sums);
  }
  if (!solid.shed_momentum.empty()) write_vec3_list(file, kShedMomentum, solid.shed_momentum, sums);
}

// --- reading ----------------------------------------------------------------------------------

// The file's format version, if this build reads it.
int check_format(hid_t root) {
  if (H5Aexists(root, "format") <= 0 || h5::read_string_attribute(root, "format") != kFormatName)
    throw std::runtime_error(std::string("not an lbsolid checkpoint (no format attribute \"") + kFormatName + "\")");
  const int version = h5::read_attribute<int>(root, "format_version");
  const std::string reads =
      " (this build reads version " + std::to_string(kCheckpointFormatVersion) + " and the older versions 2 and 3)";
  if (version >= 2 && version <= kCheckpointFormatVersion) return version;
  if (version > kCheckpointFormatVersion)
    throw std::runtime_error("checkpoint format version " + std::to_string(version) +
                             " is newer than this build reads" + reads);
  // Any other version is refused, so a damaged version attribute cannot turn verification off.
  if (version == 1)
    throw std::runtime_error("checkpoint format version 1 has no checksums and is no longer read" + reads +
                             ": restore it with the lbsolid that wrote it and take a new checkpoint");
  throw std::runtime_error("invalid checkpoint format version " + std::to_string(version) + reads);
}

void verify(const std::string& path, const std::string& computed, const std::string& stored) {
  if (computed != stored)
    throw std::runtime_error("dataset " + path + ": checksum mismatch (its contents are not those written)");
}

std::string stored_checksum(hid_t file, const std::string& path) {
  const h5::Dataset dataset(h5::check(H5Dopen2(file, path.c_str(), H5P_DEFAULT), "missing dataset " + path));
  try {
    return h5::read_string_attribute(dataset.get(), kChecksumAttribute);
  } catch (const std::runtime_error& e) {
    throw std::runtime_error("dataset " + path + ": " + e.what());
  }
}

// A dataset's values, verified against its checksum, which goes into sums for the root's.
h5::DatasetValues<double> read_verified(hid_t file, const std::string& path, hsize_t max_values,
                                        DatasetChecksums& sums) {
  h5::DatasetValues<double> data = h5::read_dataset<double>(file, path, max_values);
  const std::string stored = stored_checksum(file, path);
  verify(path, values_checksum({data.dims.begin(), data.dims.end()}, data.values.data(), data.values.size()), stored);
  sums[path] = stored;
  return data;
}

Vec3List read_vec3_list(hid_t file, const std::string& path, hsize_t max_values, DatasetChecksums& sums) {
  const h5::DatasetValues<double> data = read_verified(file, path, max_values, sums);
  if (data.dims.size() != 2 || data.dims[1] != 3)
    throw std::runtime_error("dataset " + path + " is not an [n][3] array");
  Vec3List values(data.dims[0]);
  for (std::size_t i = 0; i < values.size(); ++i)
    for (int k = 0; k < 3; ++k) values[i][k] = data.values[3 * i + k];
  return values;
}

// Booleans are stored as 0 or 1; anything else is damage, not "true".
bool read_flag(hid_t object, const std::string& where, const std::string& name) {
  const int value = h5::read_attribute<int>(object, name);
  if (value != 0 && value != 1)
    throw std::runtime_error(where + "attribute " + name + ": " + std::to_string(value) + " is not 0 or 1");
  return value == 1;
}

fluid::FluidRawState read_fluid(hid_t file, hsize_t max_values, DatasetChecksums& sums) {
  fluid::FluidRawState fluid;
  try {
    const h5::Group group = h5::open_group(file, "fluid");
    fluid.steps = h5::read_attribute<long>(group.get(), "steps");
    fluid.current = h5::read_attribute<int>(group.get(), "current");
    fluid.pulled = read_flag(group.get(), "", "pulled");
    fluid.stepped = read_flag(group.get(), "", "stepped");
    fluid.buffers = h5::read_attribute<int>(group.get(), "buffers");
    fluid.cells = h5::read_attribute<long>(group.get(), "cells");
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(std::string("/fluid: ") + e.what());
  }
  h5::DatasetValues<double> populations = read_verified(file, "/fluid/populations", max_values, sums);
  if (populations.dims.size() != 1) throw std::runtime_error("dataset /fluid/populations is not 1-D");
  fluid.populations = std::move(populations.values);
  return fluid;
}

// An integer column of a broken link's row, or a throw naming it.
long integer_in(double value, std::size_t row, const char* column) {
  if (!(value >= 0 && value < kLargestExactInteger) || value != std::floor(value))
    throw std::runtime_error(std::string("dataset ") + kBrokenLinks + " row " + std::to_string(row) + ": " + column +
                             " " + std::to_string(value) + " is not a non-negative integer");
  return static_cast<long>(value);
}

std::vector<solid::BrokenLink> read_broken_links(hid_t file, hsize_t max_values, DatasetChecksums& sums) {
  const h5::DatasetValues<double> data = read_verified(file, kBrokenLinks, max_values, sums);
  if (data.dims.size() != 2 || data.dims[1] != kBrokenLinkColumns)
    throw std::runtime_error(std::string("dataset ") + kBrokenLinks + " is not an [n][6] array");
  std::vector<solid::BrokenLink> broken(data.dims[0]);
  for (std::size_t i = 0; i < broken.size(); ++i) {
    const double* row = &data.values[i * kBrokenLinkColumns];
    const long particle = integer_in(row[1], i, "particle"), link = integer_in(row[2], i, "link");
    if (particle > std::numeric_limits<int>::max() || link > 2)
      throw std::runtime_error(std::string("dataset ") + kBrokenLinks + " row " + std::to_string(i) +
                               ": no such particle or link");
    broken[i] = {integer_in(row[0], i, "step"), static_cast<int>(particle), static_cast<int>(link),
                 {row[3], row[4], row[5]}};
  }
  return broken;
}

solid::SolidState read_solid(hid_t file, int version, hsize_t max_values, DatasetChecksums& sums) {
  solid::SolidState solid;
  solid.positions = read_vec3_list(file, "/solid/positions", max_values, sums);
  solid.incoming = read_vec3_list(file, "/solid/incoming", max_values, sums);
  solid.momentum = read_vec3_list(file, "/solid/momentum", max_values, sums);
  if (version >= 4) {
    if (h5::has_link(file, kBrokenLinks)) solid.broken = read_broken_links(file, max_values, sums);
    if (h5::has_link(file, kShedMomentum)) solid.shed_momentum = read_vec3_list(file, kShedMomentum, max_values, sums);
  }
  return solid;
}

// No dataset holds more float64 values than the file has room for (nothing is compressed).
hsize_t most_values_in(hid_t file) {
  hsize_t bytes = 0;
  h5::check_status(H5Fget_filesize(file, &bytes), "cannot read the file size");
  return bytes / sizeof(double);
}

}  // namespace

void write_checkpoint_layout(const std::string& file_path, const CheckpointContents& contents,
                             const WriterInfo& writer) {
  const DatasetChecksums sums = checksums_of(contents);
  const h5::PropertyList creation = h5::file_creation();
  const h5::PropertyList access = h5::file_access_v18();
  h5::File file(h5::check(H5Fcreate(file_path.c_str(), H5F_ACC_TRUNC, creation.get(), access.get()),
                          "cannot create " + file_path));
  const hid_t root = file.get();
  h5::write_string_attribute(root, "format", kFormatName);
  h5::write_attribute(root, "format_version", kCheckpointFormatVersion);
  h5::write_string_attribute(root, "lbsolid_version", writer.version);
  h5::write_string_attribute(root, "git_revision", writer.git_revision);
  h5::write_string_attribute(root, "session_id", contents.session_id);
  h5::write_string_attribute(root, "session_name", contents.session_name);
  h5::write_string_attribute(root, "request_id", contents.request_id);
  h5::write_string_attribute(root, "owner", contents.owner);
  h5::write_attribute(root, "done", static_cast<int>(contents.done));
  h5::write_attribute(root, "started", static_cast<int>(contents.started));
  h5::write_attribute(root, "target_step", contents.target_step);
  h5::write_attribute(root, "step", contents.state.step);
  h5::write_string_dataset(root, "scenario", contents.scenario_text);
  attach_checksum(root, "/scenario", sums);
  if (contents.state.has_fluid) write_fluid(root, contents.state.fluid, sums);
  if (contents.state.has_solid) write_solid(root, contents.state.solid, sums);
  h5::write_string_attribute(root, kChecksumAttribute, root_checksum(kCheckpointFormatVersion, writer, contents, sums));
  h5::check_status(H5Fflush(root, H5F_SCOPE_GLOBAL), "cannot flush " + file_path);
  // Closing writes the remaining metadata: its failure is a failed checkpoint.
  h5::check_status(file.close(), "cannot close " + file_path);
}

CheckpointContents read_checkpoint_layout(const std::string& file_path) {
  if (!std::filesystem::exists(file_path)) throw std::runtime_error("no such file");
  if (H5Fis_hdf5(file_path.c_str()) <= 0) {
    h5::take_error_cause();
    throw std::runtime_error("not an HDF5 file");
  }
  h5::File file(h5::check(H5Fopen(file_path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), "cannot open"));
  const hid_t root = file.get();
  const int version = check_format(root);
  const hsize_t max_values = most_values_in(root);
  DatasetChecksums sums;
  WriterInfo writer;
  CheckpointContents contents;
  writer.version = h5::read_string_attribute(root, "lbsolid_version");
  writer.git_revision = h5::read_string_attribute(root, "git_revision");
  contents.session_id = h5::read_string_attribute(root, "session_id");
  contents.session_name = h5::read_string_attribute(root, "session_name");
  contents.request_id = h5::read_string_attribute(root, "request_id");
  contents.owner = version >= 3 ? h5::read_string_attribute(root, "owner") : kLegacyOwner;
  contents.done = read_flag(root, "root ", "done");
  contents.started = read_flag(root, "root ", "started");
  contents.target_step = h5::read_attribute<long>(root, "target_step");
  contents.state.step = h5::read_attribute<long>(root, "step");
  contents.scenario_text = h5::read_string_dataset(root, "/scenario");
  sums["/scenario"] = stored_checksum(root, "/scenario");
  verify("/scenario", text_checksum(contents.scenario_text), sums["/scenario"]);
  contents.state.has_fluid = h5::has_link(root, "fluid");
  if (contents.state.has_fluid) contents.state.fluid = read_fluid(root, max_values, sums);
  contents.state.has_solid = h5::has_link(root, "solid");
  if (contents.state.has_solid) contents.state.solid = read_solid(root, version, max_values, sums);
  if (root_checksum(version, writer, contents, sums) !=
      h5::read_string_attribute(root, kChecksumAttribute))
    throw std::runtime_error(
        "root attributes: checksum mismatch (an attribute of / or /fluid, the groups present or a dataset's "
        "checksum differ from what was written)");
  return contents;
}

}  // namespace lbsolid::server::storage
