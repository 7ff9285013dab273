#include "io/storage/xdmf_text.h"

#include <filesystem>
#include <set>

namespace lbsolid::server::storage {

std::string xml_escaped(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&apos;"; break;
      default: out += c;
    }
  }
  return out;
}

std::string xdmf_path_for(const std::string& h5_path) {
  return std::filesystem::path(h5_path).replace_extension(".xdmf").string();
}

std::string xdmf_temporal_document(const std::string& name, const std::string& grids) {
  std::string x;
  x += "<?xml version=\"1.0\" ?>\n";
  x += "<!DOCTYPE Xdmf SYSTEM \"Xdmf.dtd\" []>\n";
  x += "<Xdmf Version=\"3.0\">\n";
  x += "  <Domain>\n";
  x += "    <Grid Name=\"" + xml_escaped(name) + "\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  x += grids;
  x += "    </Grid>\n";
  x += "  </Domain>\n";
  x += "</Xdmf>\n";
  return x;
}

namespace {

// A frame of a [frame][particle][dimension] dataset, components first..first+count-1.
std::string hyperslab(const std::string& dataset, std::size_t frame, std::size_t frames, std::size_t particles,
                      int dimension, int first, int count) {
  const std::string n = std::to_string(particles), d = std::to_string(dimension), c = std::to_string(count);
  std::string x;
  x += "<DataItem ItemType=\"HyperSlab\" Dimensions=\"" + n + " " + c + "\" Type=\"HyperSlab\">";
  x += "<DataItem Dimensions=\"3 3\" Format=\"XML\">" + std::to_string(frame) + " 0 " + std::to_string(first) +
       " 1 1 1 1 " + n + " " + c + "</DataItem>";
  x += "<DataItem Dimensions=\"" + std::to_string(frames) + " " + n + " " + d +
       "\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">" + dataset + "</DataItem>";
  x += "</DataItem>";
  return x;
}

}  // namespace

std::string h5md_particles_xdmf(const std::string& h5_basename, int dimension,
                                const std::map<std::string, H5mdParticleSeries>& bodies) {
  std::set<long> steps;
  for (const auto& [name, series] : bodies) steps.insert(series.steps.begin(), series.steps.end());
  const std::string file = xml_escaped(h5_basename);
  std::string x;
  for (long step : steps) {
    x += "      <Grid Name=\"step " + std::to_string(step) + "\" GridType=\"Collection\" CollectionType=\"Spatial\">\n";
    x += "        <Time Value=\"" + std::to_string(step) + "\"/>\n";
    for (const auto& [name, series] : bodies) {
      std::size_t frame = 0;
      while (frame < series.steps.size() && series.steps[frame] != step) ++frame;
      if (frame == series.steps.size()) continue;
      const std::size_t frames = series.steps.size();
      const std::string group = file + ":/particles/" + xml_escaped(name) + "/";
      const std::string n = std::to_string(series.particles);
      x += "        <Grid Name=\"" + xml_escaped(name) + "\" GridType=\"Uniform\">\n";
      x += "          <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"" + n + "\" NodesPerElement=\"1\"/>\n";
      x += std::string("          <Geometry GeometryType=\"") + (dimension == 2 ? "XY" : "XYZ") + "\">" +
           hyperslab(group + "position/value", frame, frames, series.particles, dimension, 0, dimension) +
           "</Geometry>\n";
      if (dimension == 3) {
        x += "          <Attribute Name=\"velocity\" AttributeType=\"Vector\" Center=\"Node\">" +
             hyperslab(group + "velocity/value", frame, frames, series.particles, 3, 0, 3) + "</Attribute>\n";
      } else {
        for (int a = 0; a < 2; ++a)
          x += std::string("          <Attribute Name=\"velocity_") + (a == 0 ? "x" : "y") +
               "\" AttributeType=\"Scalar\" Center=\"Node\">" +
               hyperslab(group + "velocity/value", frame, frames, series.particles, 2, a, 1) + "</Attribute>\n";
      }
      x += "        </Grid>\n";
    }
    x += "      </Grid>\n";
  }
  return xdmf_temporal_document("particles", x);
}

}  // namespace lbsolid::server::storage
