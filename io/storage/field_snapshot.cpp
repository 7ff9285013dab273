// Field snapshot layout: /fields/step_<step, 12 digits>/{density [nz][ny][nx], velocity
// [nz][ny][nx][3]} float64, each step group with attrs step (int64), origin and spacing (float64
// [3], x y z). Zero-padded names sort by step, so the XDMF lists the snapshots in time order, and
// the XDMF is rebuilt from the file alone (the groups carry everything it needs).
#include "io/storage/field_snapshot.h"

#include "io/storage/xdmf_text.h"

#include <charconv>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <vector>

#include "io/storage/file_replace.h"
#include "io/storage/hdf5_handles.h"
#include "io/storage/hdf5_io.h"

namespace lbsolid::server::storage {
namespace {

struct SnapshotRecord {
  std::string name;               // of the step group
  long step = 0;
  std::vector<hsize_t> shape;     // nz, ny, nx
  std::vector<double> origin;     // x, y, z
  std::vector<double> spacing;    // x, y, z
};

std::string step_group_name(long step) {
  char name[32];
  std::snprintf(name, sizeof name, "step_%012ld", step);
  return name;
}

void check_fields(const std::string& h5_path, const scene::FluidFields& fields, long step) {
  const auto [nx, ny, nz] = fields.shape;
  if (nx <= 0 || ny <= 0 || nz <= 0)
    throw std::invalid_argument(h5_path + ": field shape " + std::to_string(nx) + " x " + std::to_string(ny) +
                                " x " + std::to_string(nz) + " is empty");
  const std::size_t nodes = static_cast<std::size_t>(nx) * ny * nz;
  if (fields.density.size() != nodes || fields.velocity.size() != 3 * nodes)
    throw std::invalid_argument(h5_path + ": fields hold " + std::to_string(fields.density.size()) + " densities and " +
                                std::to_string(fields.velocity.size()) + " velocity components for " +
                                std::to_string(nodes) + " nodes");
  if (step < 0) throw std::invalid_argument(h5_path + ": negative step " + std::to_string(step));
}

std::vector<std::string> child_names(hid_t group) {
  std::vector<std::string> names;
  const H5L_iterate_t collect = [](hid_t, const char* name, const H5L_info_t*, void* out) -> herr_t {
    static_cast<std::vector<std::string>*>(out)->push_back(name);
    return 0;
  };
  h5::check_status(H5Literate(group, H5_INDEX_NAME, H5_ITER_INC, nullptr, collect, &names), "cannot list /fields");
  return names;
}

std::vector<SnapshotRecord> list_snapshots(hid_t fields_group) {
  std::vector<SnapshotRecord> records;
  for (const std::string& name : child_names(fields_group)) {
    const h5::Group group = h5::open_group(fields_group, name);
    SnapshotRecord record;
    record.name = name;
    record.step = h5::read_attribute<long>(group.get(), "step");
    record.origin = h5::read_attribute_values<double>(group.get(), "origin");
    record.spacing = h5::read_attribute_values<double>(group.get(), "spacing");
    const h5::Dataset density(h5::check(H5Dopen2(group.get(), "density", H5P_DEFAULT), "missing " + name + "/density"));
    const h5::Dataspace space(h5::check(H5Dget_space(density.get()), "cannot read " + name + "/density"));
    record.shape = h5::extent_of(space.get());
    if (record.shape.size() != 3 || record.origin.size() != 3 || record.spacing.size() != 3)
      throw std::runtime_error("snapshot " + name + " is not a 3-D grid with origin and spacing");
    records.push_back(std::move(record));
  }
  return records;
}

void write_snapshot(hid_t fields_group, const std::string& name, const scene::FluidFields& fields, long step,
                    const SnapshotGeometry& geometry) {
  const h5::Group group = h5::create_group(fields_group, name);
  h5::write_attribute(group.get(), "step", step);
  h5::write_attribute(group.get(), "origin", std::vector<double>(geometry.origin.begin(), geometry.origin.end()));
  h5::write_attribute(group.get(), "spacing", std::vector<double>(geometry.spacing.begin(), geometry.spacing.end()));
  const auto [nx, ny, nz] = fields.shape;
  const std::vector<hsize_t> grid{hsize_t(nz), hsize_t(ny), hsize_t(nx)};
  h5::write_dataset<double>(group.get(), "density", grid, fields.density.data());
  h5::write_dataset<double>(group.get(), "velocity", {grid[0], grid[1], grid[2], 3}, fields.velocity.data());
}

// --- XDMF ---------------------------------------------------------------------------------------

std::string number(double value) {
  char text[32];
  const auto result = std::to_chars(text, text + sizeof text, value);  // shortest exact form
  return std::string(text, result.ptr);
}

std::string zyx(const std::vector<double>& xyz) { return number(xyz[2]) + " " + number(xyz[1]) + " " + number(xyz[0]); }

std::string xdmf_text(const std::string& h5_basename, const std::vector<SnapshotRecord>& records) {
  const std::string file = xml_escaped(h5_basename);
  std::string x;
  for (const SnapshotRecord& r : records) {
    const std::string dims =
        std::to_string(r.shape[0]) + " " + std::to_string(r.shape[1]) + " " + std::to_string(r.shape[2]);
    const std::string data = file + ":/fields/" + r.name + "/";
    x += "      <Grid Name=\"" + r.name + "\" GridType=\"Uniform\">\n";
    x += "        <Time Value=\"" + std::to_string(r.step) + "\"/>\n";
    x += "        <Topology TopologyType=\"3DCoRectMesh\" Dimensions=\"" + dims + "\"/>\n";
    x += "        <Geometry GeometryType=\"ORIGIN_DXDYDZ\">\n";
    x += "          <DataItem Name=\"Origin\" Dimensions=\"3\" NumberType=\"Float\" Precision=\"8\" Format=\"XML\">" +
         zyx(r.origin) + "</DataItem>\n";
    x += "          <DataItem Name=\"Spacing\" Dimensions=\"3\" NumberType=\"Float\" Precision=\"8\" Format=\"XML\">" +
         zyx(r.spacing) + "</DataItem>\n";
    x += "        </Geometry>\n";
    x += "        <Attribute Name=\"density\" AttributeType=\"Scalar\" Center=\"Node\">\n";
    x += "          <DataItem Dimensions=\"" + dims + "\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">" + data +
         "density</DataItem>\n";
    x += "        </Attribute>\n";
    x += "        <Attribute Name=\"velocity\" AttributeType=\"Vector\" Center=\"Node\">\n";
    x += "          <DataItem Dimensions=\"" + dims + " 3\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">" +
         data + "velocity</DataItem>\n";
    x += "        </Attribute>\n";
    x += "      </Grid>\n";
  }
  return xdmf_temporal_document("fields", x);
}

// Appends the snapshot and returns every snapshot now in the file.
std::vector<SnapshotRecord> append(const std::string& h5_path, const scene::FluidFields& fields, long step,
                                   const SnapshotGeometry& geometry) {
  const bool exists = std::filesystem::exists(h5_path);
  const h5::PropertyList creation = h5::file_creation();
  h5::File file(h5::check(exists ? H5Fopen(h5_path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT)
                                 : H5Fcreate(h5_path.c_str(), H5F_ACC_EXCL, creation.get(), H5P_DEFAULT),
                          exists ? "cannot open for appending" : "cannot create"));
  std::vector<SnapshotRecord> after;
  {
    const h5::Group fields_group = h5::open_or_create_group(file.get(), "fields");
    const std::string name = step_group_name(step);
    const std::vector<SnapshotRecord> before = list_snapshots(fields_group.get());
    for (const SnapshotRecord& r : before) {
      if (r.step == step || r.name == name)
        throw std::invalid_argument(h5_path + ": a snapshot of step " + std::to_string(step) + " is already there");
    }
    const auto [nx, ny, nz] = fields.shape;
    if (!before.empty() && before.front().shape != std::vector<hsize_t>{hsize_t(nz), hsize_t(ny), hsize_t(nx)})
      throw std::invalid_argument(h5_path + ": fields of " + std::to_string(nx) + " x " + std::to_string(ny) + " x " +
                                  std::to_string(nz) + " nodes differ from the file's earlier snapshots");
    try {
      write_snapshot(fields_group.get(), name, fields, step, geometry);
    } catch (...) {
      // Unlink the half-written group so the file stays a consistent list of snapshots.
      H5Ldelete(fields_group.get(), name.c_str(), H5P_DEFAULT);
      throw;
    }
    after = list_snapshots(fields_group.get());
  }
  // Every object is closed, so this really closes the file and writes its metadata.
  h5::check_status(file.close(), "cannot close");
  return after;
}

}  // namespace

void append_field_snapshot(const std::string& h5_path, const scene::FluidFields& fields, long step,
                           const SnapshotGeometry& geometry) {
  check_fields(h5_path, fields, step);
  const std::vector<SnapshotRecord> records = h5::with_context(
      "cannot append a field snapshot to " + h5_path, [&] { return append(h5_path, fields, step, geometry); });
  // Written after the data is in the HDF5 file, so the XDMF never points at a missing snapshot.
  const std::string xdmf = xdmf_path_for(h5_path);
  h5::with_context("cannot write " + xdmf, [&] {
    write_text_file_replacing(xdmf, xdmf_text(std::filesystem::path(h5_path).filename().string(), records));
  });
}


}  // namespace lbsolid::server::storage
