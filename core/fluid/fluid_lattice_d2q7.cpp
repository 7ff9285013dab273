// FluidLattice on D2Q7, in double and in single precision.
#include "fluid/fluid_lattice_methods.h"
#include "lattice/d2q7.h"

namespace lbsolid::fluid {

template class FluidLattice<lattice::D2Q7, double>;
template class FluidLattice<lattice::D2Q7, float>;

}  // namespace lbsolid::fluid
