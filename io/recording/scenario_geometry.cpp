#include "io/recording/scenario_geometry.h"

#include "io/api/enum_mapping.h"

namespace lbsolid::server::recording {
namespace {

bool periodic(const lbsolid::v1::Side& side) {
  return side.kind() == lbsolid::v1::WALL_KIND_UNSPECIFIED || side.kind() == lbsolid::v1::WALL_KIND_PERIODIC;
}

}  // namespace

bool has_fluid(const lbsolid::v1::Scenario& s) { return !s.fluid().has_enabled() || s.fluid().enabled(); }

int dimension(const lbsolid::v1::Scenario& s) { return s.lattice() == lbsolid::v1::LATTICE_D3Q19 ? 3 : 2; }

std::array<double, 3> node_spacing(const lbsolid::v1::Scenario& s) {
  const auto lattice = lattice_of(s.lattice());
  return {1.0, lattice ? scene::lattice_row_spacing(*lattice) : 1.0, 1.0};
}

std::array<double, 3> box_edges(const lbsolid::v1::Scenario& s) {
  const auto spacing = node_spacing(s);
  const int nz = s.domain().has_nz() ? s.domain().nz() : 1;
  return {s.domain().nx() * spacing[0], s.domain().ny() * spacing[1], nz * spacing[2]};
}

std::array<bool, 3> periodic_axes(const lbsolid::v1::Scenario& s) {
  const auto& d = s.domain();
  return {periodic(d.x_low()) && periodic(d.x_high()), periodic(d.y_low()) && periodic(d.y_high()),
          periodic(d.z_low()) && periodic(d.z_high())};
}

storage::H5mdBox h5md_box(const lbsolid::v1::Scenario& s) {
  storage::H5mdBox box;
  box.dimension = dimension(s);
  box.edges = box_edges(s);
  box.periodic = periodic_axes(s);
  return box;
}

}  // namespace lbsolid::server::recording
