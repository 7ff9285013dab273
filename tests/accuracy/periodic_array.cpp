#include "accuracy/periodic_array.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <set>
#include <stdexcept>

#include "accuracy/run_clock.h"
#include "accuracy/steady_monitor.h"
#include "coupling/node_locator.h"
#include "lattice/d2q7.h"
#include "lattice/d2q9.h"
#include "lattice/d3q19.h"
#include "scene/simulation.h"

namespace lbsolid::accuracy {

using scene::LatticeKind;

double square_array_drag(double phi) {
  return 4 * M_PI / (-0.5 * std::log(phi) - 0.738 + phi - 0.887 * phi * phi + 2.039 * phi * phi * phi);
}

double cubic_array_k(double phi) {
  return 1.0 / (1 - 1.7601 * std::cbrt(phi) + phi - 1.5593 * phi * phi + 3.9799 * std::pow(phi, 8.0 / 3) -
                3.0734 * std::pow(phi, 10.0 / 3));
}

double reference_drag(int dimension, double a, double cell) {
  if (dimension == 2) return square_array_drag(M_PI * a * a / cell);
  return 6 * M_PI * a * cubic_array_k(4 * M_PI * a * a * a / (3 * cell));
}

double solid_fraction(int dimension, double a, double cell) {
  return dimension == 2 ? M_PI * a * a / cell : 4 * M_PI * a * a * a / (3 * cell);
}

double hydrodynamic_radius(int dimension, double drag, double cell, bool interstitial) {
  double lo = 0.05, hi = 0.45 * std::pow(cell, 1.0 / dimension);
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    const double measured = interstitial ? drag * (1 - solid_fraction(dimension, mid, cell)) : drag;
    (reference_drag(dimension, mid, cell) < measured ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

double cell_radius(int dimension, double particles) {
  return dimension == 2 ? std::sqrt(particles / M_PI) : std::cbrt(3 * particles / (4 * M_PI));
}

double wet_node_radius(int dimension, double particles) { return cell_radius(dimension, particles) - 0.5; }

int dimension_of(const ArrayBox& box) { return scene::lattice_dimension(box.lattice); }

double cell_measure(const ArrayBox& box) {
  const double nodes = static_cast<double>(box.nx) * box.ny * box.nz;
  return box.lattice == LatticeKind::kD2Q7 ? nodes * lattice::D2Q7::row_spacing : nodes;
}

double viscosity(const ArrayBox& box, const ArrayFluid& fluid) {
  return (1.0 / fluid.omega - 0.5) * (box.lattice == LatticeKind::kD2Q7 ? 0.25 : 1.0 / 3);
}

double dynamic_viscosity(const ArrayBox& box, const ArrayFluid& fluid) {
  return fluid.rho0 * viscosity(box, fluid) * static_cast<double>(box.nx) * box.ny * box.nz / cell_measure(box);
}

SteadyRun run_to_steady(const ArrayBox& box, solid::BodySpec body, double expected_drag, const ArrayFluid& fluid) {
  scene::Scene s;
  s.lattice = box.lattice;
  s.precision = fluid.precision;
  s.fluid.nx = box.nx;
  s.fluid.ny = box.ny;
  s.fluid.nz = box.nz;
  s.fluid.omega = fluid.omega;
  s.fluid.rho0 = fluid.rho0;
  s.fluid.collision = fluid.collision;
  s.fluid.threads = fluid.threads;
  const int dimension = dimension_of(box);
  SteadyRun run;
  run.particles = static_cast<double>(solid::body_labels(body, dimension).size());
  const double nodes = static_cast<double>(box.nx) * box.ny * box.nz;
  run.force = expected_drag * dynamic_viscosity(box, fluid) * fluid.target_velocity;
  body.load = {run.force / run.particles, 0, 0};
  s.fluid.body_force = {-run.force / nodes, 0, 0};  // the applied forces cancel
  s.bodies.push_back(body);
  const auto start = std::chrono::steady_clock::now();
  auto sim = scene::build_simulation(s);
  const double x0 = sim->body_state(0).centre_of_mass[0];
  // Sample every 0.2 of the box's slowest viscous time L^2 / (4 pi^2 nu) (L its largest extent): the
  // monitor reads the geometric decay of the change between samples, and only counts a decay faster
  // than 0.95 per sample (slower looks like a plateau); exp(-0.2) = 0.82.
  const double nu = viscosity(box, fluid);
  const double extent = std::max({static_cast<double>(box.nx), static_cast<double>(box.nz),
                                  box.lattice == LatticeKind::kD2Q7 ? box.ny * lattice::D2Q7::row_spacing
                                                                    : static_cast<double>(box.ny)});
  long every = std::max(50L, std::lround(0.2 * extent * extent / (4 * M_PI * M_PI * nu)));
  // The other slow mode: the relative velocity U itself, which the drag relaxes at the rate
  // drag mu (1/M_body + 1/M_fluid). For the physics test's bodies (spacing 1, M_body / M_fluid < 1)
  // its time is below the viscous one and changes nothing; a heavy body (spacing 1/2 packs 2^d
  // particles per node, 2^d times the mass) can take several viscous times, and sampled on the
  // viscous clock its decay per sample could come close to the monitor's 0.95 (a false plateau).
  // So the interval is never below 0.2 of that time either.
  const double body_mass = sim->body_state(0).mass;
  const double fluid_mass = fluid.rho0 * nodes;
  const double relax = 1.0 / (expected_drag * dynamic_viscosity(box, fluid) * (1 / body_mass + 1 / fluid_mass));
  every = std::max(every, std::lround(0.2 * relax));
  run.interval = every;
  SteadyMonitor monitor(fluid.tolerance, fluid.target_velocity);
  bool stop = false;
  int quiet = 0;
  while (!stop && run.steps < fluid.max_steps) {
    sim->run(every);
    run.steps += every;
    const scene::FluidFields fields = sim->fluid_fields();
    double sum = 0;
    for (std::size_t k = 0; k < fields.density.size(); ++k) sum += fields.velocity[3 * k];
    run.body_velocity = sim->body_state(0).velocity[0];
    run.superficial = run.body_velocity - sum / nodes;
    quiet = monitor.update({run.superficial, run.body_velocity}) ? quiet + 1 : 0;
    stop = quiet >= fluid.quiet_samples || monitor.at_floor();
  }
  run.converged = monitor.converged();
  run.stop = !stop ? "cap" : monitor.converged() ? "tolerance" : "floor";
  run.displacement = sim->body_state(0).centre_of_mass[0] - x0;
  run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  run.memory_bytes = sim->fluid_bytes() + sim->solid_bytes();
  return run;
}

namespace {

// Distinct nodes the body's particles are nearest to (square and cubic lattices).
template <class L>
double coupled_nodes(const ArrayBox& box, const solid::BodySpec& body) {
  fluid::FluidConfig config;
  config.nx = box.nx;
  config.ny = box.ny;
  config.nz = box.nz;
  const coupling::NodeLocator<L> locator(config);
  std::set<long> cells;
  for (const auto& r : solid::placed_positions(solid::body_labels(body, L::D), body.centre, body.spacing))
    cells.insert(locator.cell(locator.nearest(r)));
  return static_cast<double>(cells.size());
}

}  // namespace

ArrayResult periodic_array(const ArrayBox& box, double radius, const std::string& label, const ArrayFluid& fluid,
                           double spacing) {
  const int dimension = dimension_of(box);
  solid::BodySpec body;
  body.name = label;
  body.shape = solid::BodyShape::kDisk;
  body.radius = radius;
  body.spacing = spacing;
  if (box.lattice == LatticeKind::kD2Q7) {
    if (spacing != 1.0) throw std::invalid_argument("periodic_array: D2Q7 runs at spacing 1 only");
    const int row = 2 * (box.ny / 4);  // an even row: its nodes sit at integer x
    body.centre = {static_cast<double>(box.nx / 2), row * lattice::D2Q7::row_spacing, 0};
  } else {
    const double shift = 0.5 * (1 - spacing);  // 0 at spacing 1: on the middle node
    body.centre = {box.nx / 2 + shift, box.ny / 2 + shift, dimension == 3 ? box.nz / 2 + shift : 0.0};
  }
  ArrayResult r;
  r.label = label;
  r.dimension = dimension;
  r.spacing = spacing;
  r.cell = cell_measure(box);
  const double particles = static_cast<double>(solid::body_labels(body, dimension).size());
  r.a_cells = spacing * cell_radius(dimension, particles);
  switch (box.lattice) {
    case LatticeKind::kD2Q7:
      r.nodes = particles;  // not used: the test's convention below
      r.a_wet = wet_node_radius(dimension, particles);
      break;
    case LatticeKind::kD2Q9:
      r.nodes = coupled_nodes<lattice::D2Q9>(box, body);
      r.a_wet = wet_node_radius(dimension, r.nodes);
      break;
    case LatticeKind::kD3Q19:
      r.nodes = coupled_nodes<lattice::D3Q19>(box, body);
      r.a_wet = wet_node_radius(dimension, r.nodes);
      break;
  }
  r.run = run_to_steady(box, body, reference_drag(dimension, r.a_wet, r.cell), fluid);
  r.drag = r.run.force / (dynamic_viscosity(box, fluid) * r.run.superficial);
  r.a_hydro = hydrodynamic_radius(dimension, r.drag, r.cell);
  r.reynolds = 2 * r.a_wet * r.run.superficial / viscosity(box, fluid);
  const double at_wet = reference_drag(dimension, r.a_wet, r.cell);
  r.error_cells = r.drag / reference_drag(dimension, r.a_cells, r.cell) - 1;
  r.error_wet = r.drag / at_wet - 1;
  r.band_low = reference_drag(dimension, r.a_wet - 0.5, r.cell) / at_wet - 1;
  r.band_high = reference_drag(dimension, r.a_wet + 0.5, r.cell) / at_wet - 1;
  return r;
}

ArrayBox array_box(Problem problem, int radius) {
  if (problem == Problem::kArrayDrag3d) {
    const int side = 4 * radius;
    return {LatticeKind::kD3Q19, side, side, side};
  }
  const int side = static_cast<int>(std::lround(5.6 * radius));
  return {LatticeKind::kD2Q9, side, side, 1};
}

RunResult run_array_drag(Problem problem, const Method& method, int radius, const RunSettings& settings) {
  if (problem != Problem::kArrayDrag2d && problem != Problem::kArrayDrag3d)
    throw std::invalid_argument("run_array_drag: not an array problem");
  const ArrayBox box = array_box(problem, radius);
  if (method.lattice != box.lattice)
    throw std::invalid_argument(std::string("run_array_drag: ") + problem_name(problem) + " runs on " +
                                scene::lattice_kind_name(box.lattice));
  ArrayFluid fluid;
  fluid.omega = settings.omega;
  fluid.precision = method.precision;
  fluid.collision = method.collision;
  fluid.threads = settings.threads;
  fluid.target_velocity = method.precision == scene::Precision::kFloat ? settings.array_velocity_float
                                                                       : settings.array_velocity;
  fluid.tolerance = settings.array_tolerance;
  fluid.quiet_samples = 2;  // a particle hopping to the next node must not stop a run (ArrayFluid)
  // Physical radius R: R / spacing particles per radius (the labels within that many spacings).
  const double particle_radius = radius / method.spacing;
  const ArrayResult a = periodic_array(box, particle_radius, problem_name(problem), fluid, method.spacing);
  RunResult r;
  r.problem = problem;
  r.method = method;
  r.resolution = radius;
  r.measured = a.drag;
  r.error = std::abs(a.error_cells);
  r.reynolds = a.reynolds;
  r.wall_s = a.run.seconds;
  r.steps = a.run.steps;
  r.mlups = a.run.seconds > 0 ? cell_measure(box) * static_cast<double>(a.run.steps) / a.run.seconds / 1e6 : 0;
  r.memory_bytes = a.run.memory_bytes;
  r.peak_rss_bytes = peak_rss_bytes();
  r.stop = a.run.stop;
  r.a_cells = a.a_cells;
  r.a_wet = a.a_wet;
  r.a_hydro = a.a_hydro;
  r.error_wet = a.error_wet;
  r.error_signed = a.error_cells;
  r.displacement = a.run.displacement;
  return r;
}

}  // namespace lbsolid::accuracy
