#include "io/storage/checkpoint_validation.h"

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace lbsolid::server::storage {
namespace {

[[noreturn]] void refuse(const std::string& field, const std::string& reason) {
  throw std::runtime_error(field + ": " + reason);
}

void check_step(const std::string& field, long value) {
  if (value < 0) refuse(field, std::to_string(value) + " is negative");
  if (value > kMaxCheckpointStep)
    refuse(field, std::to_string(value) +
                      " is beyond any possible run (at most 2^53 = " + std::to_string(kMaxCheckpointStep) + ")");
}

std::string describe(double value) {
  if (std::isnan(value)) return "NaN";
  return value > 0 ? "+infinity" : "-infinity";
}

void check_finite(const std::string& dataset, const double* values, std::size_t count) {
  for (std::size_t i = 0; i < count; ++i)
    if (!std::isfinite(values[i]))
      refuse("dataset " + dataset, "value " + std::to_string(i) + " is " + describe(values[i]));
}

void check_finite(const std::string& dataset, const std::vector<solid::Vec3>& values) {
  if (!values.empty()) check_finite(dataset, values[0].data(), 3 * values.size());
}

void check_fluid(const fluid::FluidRawState& fluid, long step) {
  if (fluid.steps != step)
    refuse("/fluid attribute steps", std::to_string(fluid.steps) + " differs from the step " + std::to_string(step) +
                                         " (the fluid steps once per step)");
  if (fluid.buffers != 1 && fluid.buffers != 2)
    refuse("/fluid attribute buffers", std::to_string(fluid.buffers) + " is not 1 (in place) or 2 (two buffers)");
  if (fluid.current < 0 || fluid.current >= fluid.buffers)
    refuse("/fluid attribute current",
           std::to_string(fluid.current) + " is not a buffer (0 to " + std::to_string(fluid.buffers - 1) + ")");
  if (fluid.cells < 1) refuse("/fluid attribute cells", std::to_string(fluid.cells) + " is not positive");
  // Q is the lattice's business (load_state checks it); the count must be whole populations.
  const long per_population = static_cast<long>(fluid.buffers) * fluid.cells;
  const long count = static_cast<long>(fluid.populations.size());
  if (count == 0 || count % per_population != 0)
    refuse("dataset /fluid/populations", "holds " + std::to_string(count) + " values, not a multiple of buffers (" +
                                             std::to_string(fluid.buffers) + ") x cells (" +
                                             std::to_string(fluid.cells) + ")");
  check_finite("/fluid/populations", fluid.populations.data(), fluid.populations.size());
}

void check_solid(const solid::SolidState& solid) {
  const std::size_t n = solid.positions.size();
  if (solid.momentum.size() != n)
    refuse("/solid",
           "has " + std::to_string(n) + " positions but " + std::to_string(solid.momentum.size()) + " momenta");
  if ((n == 0 && !solid.incoming.empty()) || (n > 0 && solid.incoming.size() % n != 0))
    refuse("dataset /solid/incoming", "holds " + std::to_string(solid.incoming.size()) +
                                          " links, not a multiple of the " + std::to_string(n) + " particles");
  check_finite("/solid/positions", solid.positions);
  check_finite("/solid/incoming", solid.incoming);
  check_finite("/solid/momentum", solid.momentum);
  check_finite("/solid/shed_momentum", solid.shed_momentum);
  for (const auto& link : solid.broken)
    if (link.particle >= static_cast<long>(n) || link.link < 0 || link.step < 0)
      refuse("dataset /solid/broken_links", "names a link this solid does not have");
    else check_finite("/solid/broken_links", link.position.data(), 3);
}

}  // namespace

void check_checkpoint_contents(const CheckpointContents& contents) {
  check_step("attribute step", contents.state.step);
  check_step("attribute target_step", contents.target_step);
  if (contents.state.has_fluid) check_fluid(contents.state.fluid, contents.state.step);
  if (contents.state.has_solid) check_solid(contents.state.solid);
}

}  // namespace lbsolid::server::storage
