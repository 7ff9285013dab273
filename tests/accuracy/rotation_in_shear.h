#pragma once
// Rotating bodies in simple shear (issue 16), shared by tests/physics/jeffery_orbit_test.cpp and the
// accuracy report's rotation problems (shear_rotation, jeffery):
//   - a plane Couette flow: periodic in x, between halfway bounce-back walls at y = -1/2 and
//     H - 1/2 moving at -U and +U, so u_x = gamma_dot (y - (H - 1)/2) with gamma_dot = 2 U / H;
//   - a lattice ellipse: the labels within an ellipse of semi-axes a (along x) and b;
//   - the angle a body turns through, followed every few steps;
//   - Jeffery's law for that angle, and how well a measured turn follows it.
//
// Jeffery (1922; the same law holds for an elliptic cylinder): a torque-free ellipse of aspect
// ratio r in Stokes shear turns with d(phi)/dt = gamma_dot (r^2 sin^2 phi + cos^2 phi) / (r^2 + 1),
// phi its long axis' angle from the flow, measured the way the flow turns it (clockwise here).
// Its solution is tan phi = tan(psi) / r with the phase psi = 2 pi t / T growing uniformly, and the
// period of a full turn is T = 2 pi (r + 1/r) / gamma_dot. The body spends the fraction
// f = 2 atan(r) / pi of each half turn within 45 degrees of the flow, so r = tan(pi f / 2): the
// aspect ratio the turn's SHAPE says, measured without its period. That the period then equals
// 2 pi (r + 1/r) / gamma_dot is what Jeffery's law adds (a law d(phi)/dt = A + B sin^2 phi has
// two free constants; Jeffery's ties them by A + (A + B) = gamma_dot: the slowest and fastest rates
// add up to the flow's vorticity).
#include <vector>

#include "fluid/fluid_config.h"
#include "scene/scene.h"
#include "scene/simulation.h"
#include "solid/body_shape.h"

namespace lbsolid::accuracy {

struct CouetteFlow {
  scene::LatticeKind lattice = scene::LatticeKind::kD2Q9;
  scene::Precision precision = scene::Precision::kDouble;
  fluid::CollisionModel collision = fluid::CollisionModel::kBgk;
  double omega = 1.0;
  int threads = 1;
  int height = 64;  // H: rows between the walls
  int length = 128;
  double shear_rate = 5e-4;
};
// The flow without bodies; a body placed at (length / 2, (height - 1) / 2) sits where u_x = 0.
scene::Scene couette_scene(const CouetteFlow& flow);
double viscosity(const CouetteFlow& flow);  // (1/omega - 1/2) c_s^2

// Labels (i, j) with (i s / a)^2 + (j s / b)^2 <= 1 (s the spacing; a, b in lattice units), as a
// rotating body of that spacing centred at `centre`.
solid::BodySpec lattice_ellipse(double a, double b, double spacing, const solid::Vec3& centre);

struct TurnSample {
  long step = 0;
  double angle = 0;  // turned clockwise since the start (the way the flow turns it), unwrapped
};
// Runs `sim` `every` steps at a time until body 0 has turned `until` radians clockwise or
// `max_steps` have passed, recording its best-fit angle after each run.
std::vector<TurnSample> follow_turn(scene::Simulation& sim, int every, double until, long max_steps);

// Jeffery's angle at phase psi (continuous in psi, equal to it at every multiple of pi/2).
double jeffery_angle(double psi, double r);
// Jeffery's period times gamma_dot for aspect ratio r.
double jeffery_shear_period(double r);

struct JefferyFit {
  bool complete = false;      // the samples cover a full turn from the first perpendicular passage
  double shear_period = 0;    // gamma_dot T, T from angle pi/2 to 5 pi/2 (one full turn)
  double half_periods[2]{0, 0};  // gamma_dot times each half turn's duration
  double aspect_ratio = 0;    // r from the time spent within 45 degrees of the flow (above)
  double period_error = 0;    // T / (jeffery_shear_period(aspect_ratio) / gamma_dot) - 1
  // Largest |angle - Jeffery's angle| over the turn, each half turn's phase running uniformly
  // from its perpendicular passage to the next (so a drift between them does not add up).
  double law_deviation = 0;
};
// The turn from angle pi/2 (long axis across the flow; a body placed along the flow passes it
// once) to 5 pi/2.
JefferyFit fit_jeffery(const std::vector<TurnSample>& samples, double shear_rate);

}  // namespace lbsolid::accuracy
