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
  const std::vector<int>& resolutions(Problem p) const {
    return p == Problem::kShearWave ? shear_wave : p == Problem::kPoiseuille ? poiseuille : drag_radii;
  }
};

// Channels 16 to 256 cells; disks of diameter 9 up to `max_disk_diameter` (at most 65). A D = 65 run
// costs 1 to 3 minutes per method on one core (cells and steps both grow as D^2), so the default
// stops at D = 37 (a few seconds per method) and the whole range is one flag away.
inline SweepPlan full_plan(int max_disk_diameter = 37) {
  SweepPlan plan{{16, 32, 64, 128, 256}, {16, 32, 64, 128, 256}, {}};
  for (int radius : {4, 8, 12, 18, 24, 32})
    if (2 * radius + 1 <= max_disk_diameter) plan.drag_radii.push_back(radius);
  return plan;
}
// Three resolutions each: the least that gives an order free of the reference (drag) or a check
// that the order is steady (shear wave, Poiseuille).
inline SweepPlan quick_plan() { return {{16, 32, 64}, {16, 32, 64}, {3, 6, 12}}; }

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

}  // namespace lbsolid::accuracy
