#pragma once
// The paper's Fig. 5 measurement (section 4.1) on a recorded run, with the definitions of
// tests/physics/drag_fig5_test.cpp:
//   u(t) = u_inf (1 - exp(-a t))       fitted to the disk's mean velocity along x
//   F    = load_x x particles          the force on the whole disk
//   D    = (2 floor(R) + 1) spacing    the particles' extent across the disk
//   nu   = c_s^2 (1/omega - 1/2)       c_s^2 = 1/4 on D2Q7, 1/3 on D2Q9 and D3Q19
//   Re   = u_inf D / nu,  c_d = F / (rho0 u_inf^2 D)
#include <string>
#include <vector>

#include "lbsolid/v1/scenario.pb.h"
#include "observe/fits.h"
#include "io/storage/h5md_file.h"

namespace lbsolid::drag {

struct DragSetup {
  std::string scenario_name;
  std::string lattice;   // "D2Q7", ...
  int dimension = 2;
  std::string body;      // the disk's name (its H5MD group)
  double radius = 0, spacing = 1;
  long particles = 0;
  double load = 0;       // per particle, along x
  double initial_velocity = 0;  // along x, the scenario's rigid start velocity
  double omega = 1, rho0 = 1, cs2 = 1.0 / 3;
  double viscosity() const { return cs2 * (1 / omega - 0.5); }
  double diameter() const;
  double force() const { return load * static_cast<double>(particles); }
};

// The first DISK body of the scenario with the defaults filled in as the daemon does
// (translate_scenario). Throws std::runtime_error if the scenario has no disk or no fluid, or the
// disk is not pulled along x.
DragSetup drag_setup(const lbsolid::v1::Scenario& scenario);

struct DragResult {
  std::vector<double> t, u;        // the samples fitted
  bool origin_added = false;       // (0, initial velocity) added: the file starts after step 0
  observe::ExponentialFit fit;
  double reynolds = 0, drag_coefficient = 0;
  double relaxation_times = 0;     // a t_last: the test asks for > 8 (terminal speed reached)
};

// velocity: the /observables/<disk>/velocity series (x, y[, z] per frame).
DragResult analyse_drag(const DragSetup& setup, const lbsolid::server::storage::H5mdSeries& velocity);

}  // namespace lbsolid::drag
