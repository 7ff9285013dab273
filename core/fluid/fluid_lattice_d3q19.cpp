// FluidLattice on D3Q19, in double and in single precision.
#include "fluid/fluid_lattice_methods.h"
#include "lattice/d3q19.h"

namespace lbsolid::fluid {

template class FluidLattice<lattice::D3Q19, double>;
template class FluidLattice<lattice::D3Q19, float>;

}  // namespace lbsolid::fluid
