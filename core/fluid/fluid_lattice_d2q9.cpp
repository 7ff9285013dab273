// FluidLattice on D2Q9, in double and in single precision.
#include "fluid/fluid_lattice_methods.h"
#include "lattice/d2q9.h"

namespace lbsolid::fluid {

template class FluidLattice<lattice::D2Q9, double>;
template class FluidLattice<lattice::D2Q9, float>;

}  // namespace lbsolid::fluid
