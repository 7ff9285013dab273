#pragma once
// What a body does as a whole, computed from its particles on request.
#include "solid/solid_system.h"

namespace lbsolid::scene {

using Vec3 = solid::Vec3;

struct BodyState {
  Vec3 centre_of_mass{0, 0, 0};  // mass-weighted mean position
  Vec3 velocity{0, 0, 0};        // total momentum / total mass
  double mass = 0;
  Vec3 angular_momentum{0, 0, 0};  // sum of (r - centre of mass) x Psi
  // The inertia tensor about the centre of mass (sum of M (|r|^2 1 - r r^T)) solved for the angular
  // momentum; 2D: L_z / I_zz. Zero where the tensor is singular (a straight 3D chain).
  Vec3 angular_velocity{0, 0, 0};
  double orientation = 0;  // 2D: the best-fit angle of the shape from its rest shape, (-pi, pi]; 3D: 0
  // The best-fit rotation of the shape from its rest shape (SolidSystem::best_fit_quaternion), in
  // 2D and 3D; a straight 3D chain's turn about its own axis is undetermined.
  solid::Quaternion orientation_quaternion{1, 0, 0, 0};
  // In scenes with a rotating body, for every body: the torque about its centre of mass that the
  // external forces (loads, the fluid's exchange, wall contact) exerted in the last step
  // (scene/stages/torque_record.h). Zero in other scenes, and before the first step a simulation
  // takes (also right after a restore). Simulation::body_state fills it; measure_body cannot.
  Vec3 torque{0, 0, 0};
  // The momentum the body's anchored particles absorbed in the last step: the force that the flow,
  // the loads and the rest of the body exert on its anchors (drag along the flow, lift across it;
  // scene/stages/anchor_record.h). Zero for a body without anchors, and before the first step.
  Vec3 anchor_force{0, 0, 0};
};

// Body `body` of `solid` (a valid index). Without orientation, the best fits (a pass over the
// links, and a 4 x 4 eigenproblem in 3D) are skipped and orientation, orientation_quaternion keep
// their defaults: for a caller that needs the motion only, every step.
BodyState measure_body(const solid::SolidSystem& solid, int body, bool with_orientation = true);

}  // namespace lbsolid::scene
