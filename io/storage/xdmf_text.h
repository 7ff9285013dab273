#pragma once
// XDMF (https://www.xdmf.org, version 3) text beside the HDF5 files, so that ParaView opens them:
// the field snapshots' (field_snapshot.h) and the H5MD particles' (h5md_file.h).
#include <map>
#include <string>
#include <vector>

namespace lbsolid::server::storage {

// Text safe inside an XML attribute or element.
std::string xml_escaped(const std::string& text);

// The XDMF file for `path` (same stem, .xdmf): run.fields.h5 -> run.fields.xdmf.
std::string xdmf_path_for(const std::string& h5_path);

// An XDMF document whose domain is one temporal collection named `name` of the `grids` given (each
// a <Grid> element with its <Time>, indented for the collection).
std::string xdmf_temporal_document(const std::string& name, const std::string& grids);

// What an H5MD file holds of one body's particles: its particle count and the step of each frame
// of /particles/<body>/{position,velocity}/value [frame][particle][dimension].
struct H5mdParticleSeries {
  std::size_t particles = 0;
  std::vector<long> steps;
};

// A temporal collection with, at every recorded step, one Polyvertex grid per body that has a
// frame there: its positions as geometry (XY in 2D, XYZ in 3D) and its velocity as a node
// attribute (a vector in 3D; velocity_x, velocity_y in 2D, since ParaView takes 3-component
// vectors), each a hyperslab of the body's frame in `h5_basename`.
std::string h5md_particles_xdmf(const std::string& h5_basename, int dimension,
                                const std::map<std::string, H5mdParticleSeries>& bodies);

}  // namespace lbsolid::server::storage
