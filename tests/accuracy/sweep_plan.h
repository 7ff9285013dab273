#pragma once
// Which resolutions and methods the accuracy report sweeps: the full plan (run by hand) and the
// quick one (seconds; the CI test runs it in process).
#include <string>
#include <vector>

#include "accuracy/accuracy_problems.h"

namespace lbsolid::accuracy {

struct SweepPlan {
  std::vector<int> shear_wave;  // wavelengths in cells
  std::vector<int> poiseuille;  // rows across the channel
  std::vector<int> drag_radii;  // disk radii in particles: D = 2 radius + 1
  std::vector<int> array_2d;    // array drag: disk radii in lattice units (R / spacing particles)
  std::vector<int> array_3d;    // array drag: ball radii in lattice units
  std::vector<int> shear_rotation;  // disk radii in lattice units (R / spacing particles)
  std::vector<int> jeffery;         // the ellipse's semi-minor axis b in lattice units (a = 3 b)
  const std::vector<int>& resolutions(Problem p) const {
    switch (p) {
      case Problem::kShearWave: return shear_wave;
      case Problem::kPoiseuille: return poiseuille;
      case Problem::kDiskDrag: return drag_radii;
      case Problem::kArrayDrag2d: return array_2d;
      case Problem::kArrayDrag3d: return array_3d;
      case Problem::kShearRotation: return shear_rotation;
      case Problem::kJeffery: return jeffery;
    }
    return drag_radii;
  }
};

// Channels 16 to 256 cells; disks of diameter 9 up to `max_disk_diameter` (at most 65). A D = 65 run
// costs 1 to 3 minutes per method on one core (cells and steps both grow as D^2), so the default
// stops at D = 37 (a few seconds per method) and the whole range is one flag away. The rotation
// problems' largest bodies (R = 16, b = 4) take about half a minute per method.
inline SweepPlan full_plan(int max_disk_diameter = 37) {
  SweepPlan plan{{16, 32, 64, 128, 256}, {16, 32, 64, 128, 256}, {}, {3, 4, 6, 8, 11, 16}, {3, 4, 5, 6, 8},
                 {3, 4, 6, 8, 12, 16}, {1, 2, 3, 4}};
  for (int radius : {4, 8, 12, 18, 24, 32})
    if (2 * radius + 1 <= max_disk_diameter) plan.drag_radii.push_back(radius);
  return plan;
}
// Three resolutions each: the least that gives an order free of the reference (drag) or a check
// that the order is steady (shear wave, Poiseuille).
// The array drag: two radii each (R = 4, 8 in 2D; 3, 5 in 3D), enough for the error to fall; the
// rotation problems likewise (disks R = 4, 8; ellipses b = 1, 2).
inline SweepPlan quick_plan() { return {{16, 32, 64}, {16, 32, 64}, {3, 6, 12}, {4, 8}, {3, 5}, {4, 8}, {1, 2}}; }

// Every lattice x precision x collision operator, keeping only the operators that really run
// (collision_differs_from_bgk): until TRT and regularized land they would silently repeat BGK.
inline std::vector<Method> available_methods(const RunSettings& settings, std::vector<std::string>* skipped) {
  std::vector<Method> methods;
  for (auto collision : {fluid::CollisionModel::kBgk, fluid::CollisionModel::kTrt, fluid::CollisionModel::kRegularized})
    for (auto lattice : {scene::LatticeKind::kD2Q9, scene::LatticeKind::kD2Q7}) {
      if (!collision_differs_from_bgk(collision, lattice, settings)) {
        if (skipped) skipped->push_back(method_name({lattice, scene::Precision::kDouble, collision}));
        continue;
      }
      for (auto precision : {scene::Precision::kDouble, scene::Precision::kFloat})
        methods.push_back({lattice, precision, collision});
    }
  return methods;
}

// The array drag's methods: its lattice (D2Q9 in 2D, D3Q19 in 3D) x every operator that runs x
// double, float x particle spacing 1, 1/2.
inline std::vector<Method> array_methods(Problem problem, const RunSettings& settings, std::vector<std::string>* skipped) {
  const scene::LatticeKind lattice =
      problem == Problem::kArrayDrag3d ? scene::LatticeKind::kD3Q19 : scene::LatticeKind::kD2Q9;
  std::vector<Method> methods;
  for (auto collision : {fluid::CollisionModel::kBgk, fluid::CollisionModel::kTrt, fluid::CollisionModel::kRegularized}) {
    if (!collision_differs_from_bgk(collision, lattice, settings)) {
      if (skipped) skipped->push_back(method_name({lattice, scene::Precision::kDouble, collision}));
      continue;
    }
    for (auto precision : {scene::Precision::kDouble, scene::Precision::kFloat})
      for (double spacing : {1.0, 0.5}) methods.push_back({lattice, precision, collision, spacing});
  }
  return methods;
}

}  // namespace lbsolid::accuracy
