#pragma once
// Problems with a known answer, each run at one resolution with one method (lattice, precision,
// collision operator) through the public scene API, to its own measurement point:
//   shear wave  - analytic: u_y = A exp(-nu k^2 t) sin(k x); error = relative error of the decay
//                 rate fitted over one decay time against nu k^2.
//   Poiseuille  - analytic: the parabola between half-way bounce-back walls; error = relative L2
//                 error of the steady profile (steady: SteadyMonitor, not a step count).
//   disk drag   - no closed form: c_d at Re = 1 of an LB-solid disk in a walled channel of fixed
//                 shape; the error is filled in by the sweep (accuracy_sweep.h) against the
//                 Richardson extrapolation of the method's two finest runs.
// Scaling: DIFFUSIVE. omega (hence the lattice viscosity) is the same at every resolution and the
// physical time scales with N^2; the velocities scale as 1/N, so the Reynolds number is fixed and
// the Mach number falls as 1/N. This is the scaling under which LB converges to the
// incompressible Navier-Stokes equations: the compressibility error O(Ma^2) falls as N^-2, like
// the discretisation error, so the observed order is the scheme's. (At fixed Mach, the O(Ma^2)
// error would stay as N grows and the error would stall.)
#include <string>

#include "fluid/fluid_config.h"
#include "scene/scene.h"

namespace lbsolid::accuracy {

enum class Problem { kShearWave, kPoiseuille, kDiskDrag };
const char* problem_name(Problem problem);

struct Method {
  scene::LatticeKind lattice = scene::LatticeKind::kD2Q9;
  scene::Precision precision = scene::Precision::kDouble;
  fluid::CollisionModel collision = fluid::CollisionModel::kBgk;
};
std::string method_name(const Method& method);  // e.g. "BGK/double/D2Q9"
const char* precision_name(scene::Precision precision);

struct RunSettings {
  // One omega for every problem and method. Not 1: at omega = 1 the regularized operator is BGK
  // exactly (both set f to the equilibrium), and BGK's wall error at omega = 1 is unusually small.
  double omega = 0.8;
  int threads = 1;
};

struct RunResult {
  Problem problem = Problem::kShearWave;
  Method method;
  int resolution = 0;   // cells across: wavelength, channel rows, or disk diameter
  double measured = 0;  // decay rate / nu k^2; (unused); c_d at Re = 1
  double error = 0;     // relative error (drag: filled by the sweep)
  double reynolds = 0;  // drag only: the Re the run reached
  double wall_s = 0;
  double mlups = 0;     // fluid cell updates per second / 1e6
  std::size_t memory_bytes = 0;  // Simulation::fluid_bytes() + solid_bytes()
  long peak_rss_bytes = 0;       // the process's peak resident set so far (getrusage)
  long steps = 0;
  // Why the run stopped: "time" (reached its physical end, shear wave), "tolerance" (estimated
  // distance to steady state below tolerance), "floor" (change stalled far below its largest: a
  // round-off floor or a flicker), "cap" (hit the safety cap: not converged).
  std::string stop = "time";
  bool converged() const { return stop != "cap"; }
};

// Disk diameter in lattice units for a disk of `radius` particles: 2 radius + 1 spacings.
inline int disk_diameter(int radius) { return 2 * radius + 1; }

// Shear wave of wavelength n cells in an n x 2 periodic box, run for one decay time.
RunResult run_shear_wave(const Method& method, int n, const RunSettings& settings);

// Body-force Poiseuille flow across n rows between bounce-back walls, run to steady state.
RunResult run_poiseuille(const Method& method, int n, const RunSettings& settings);

// A disk of diameter D = 2 radius + 1 particles in a channel of length 3.3 D and width 2.4 D
// (drag_fig5_test's shape), pulled by a force chosen for Re = 1 from `stokes_constant` K, the
// expected c_d Re (the sweep passes the value measured at the previous resolution), run until its
// velocity is steady. measured = c_d Re, which is c_d at Re = 1 in the Stokes regime (c_d ~ 1/Re):
// the run's Re is within a few per cent of 1 and this removes that residual.
RunResult run_disk_drag(const Method& method, int radius, double stokes_constant, const RunSettings& settings);

// Whether `model` really runs on `lattice` as something other than BGK: a short forced channel
// run at omega != 1 must differ from the BGK one. (Until an operator lands, FluidConfig accepts
// it and silently runs BGK.)
bool collision_differs_from_bgk(fluid::CollisionModel model, scene::LatticeKind lattice, const RunSettings& settings);

}  // namespace lbsolid::accuracy
