#include "accuracy/rotation_problems.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "accuracy/rotation_in_shear.h"
#include "accuracy/run_clock.h"

namespace lbsolid::accuracy {

namespace {

constexpr double kShearRotationReynolds = 0.04;
constexpr double kJefferyReynolds = 0.1;
constexpr double kJefferyAspectRatio = 3;  // a = 3 b

CouetteFlow flow_for(const Method& method, const RunSettings& settings, int height, int length) {
  CouetteFlow flow;
  flow.lattice = method.lattice;
  flow.precision = method.precision;
  flow.collision = method.collision;
  flow.omega = settings.omega;
  flow.threads = settings.threads;
  flow.height = height;
  flow.length = length;
  return flow;
}

RunResult result_for(Problem problem, const Method& method, int resolution) {
  RunResult r;
  r.problem = problem;
  r.method = method;
  r.resolution = resolution;
  return r;
}

}  // namespace

RunResult run_shear_rotation(const Method& method, int radius, const RunSettings& settings) {
  RunResult r = result_for(Problem::kShearRotation, method, radius);
  const RunClock clock;
  CouetteFlow flow = flow_for(method, settings, 12 * radius, 12 * radius);
  const double nu = viscosity(flow);
  flow.shear_rate = kShearRotationReynolds * nu / (radius * radius);
  scene::Scene s = couette_scene(flow);
  solid::BodySpec disk;
  disk.shape = solid::BodyShape::kDisk;
  disk.radius = radius / method.spacing;
  disk.spacing = method.spacing;
  disk.centre = {flow.length / 2.0, flow.height / 2.0, 0};  // on a node: no particle halfway between two
  disk.rotation = true;
  s.bodies.push_back(disk);
  auto sim = scene::build_simulation(s);
  const double pi2 = std::numbers::pi * std::numbers::pi;
  sim->run(static_cast<long>(std::ceil(7 * flow.height * flow.height / (pi2 * nu))));
  const long settled = sim->step_count();
  const long window = static_cast<long>(std::ceil(2 / flow.shear_rate));  // one radian at gamma_dot / 2
  const auto turn = follow_turn(*sim, static_cast<int>(std::max(1L, window / 200)), 1.0, 2 * window);
  const double rate = turn.back().angle / static_cast<double>(sim->step_count() - settled);
  r.measured = rate / (flow.shear_rate / 2);
  r.error = std::abs(r.measured - 1);
  r.reynolds = kShearRotationReynolds;
  r.stop = turn.back().angle >= 1.0 ? "time" : "cap";
  clock.finish(*sim, r);
  return r;
}

RunResult run_jeffery(const Method& method, int semi_minor, const RunSettings& settings) {
  RunResult r = result_for(Problem::kJeffery, method, semi_minor);
  const RunClock clock;
  const double b = semi_minor, a = kJefferyAspectRatio * b;
  CouetteFlow flow = flow_for(method, settings, 32 * semi_minor, 64 * semi_minor);
  flow.shear_rate = kJefferyReynolds * viscosity(flow) / (a * a);
  scene::Scene s = couette_scene(flow);
  s.bodies.push_back(lattice_ellipse(a, b, method.spacing, {flow.length / 2.0, (flow.height - 1) / 2.0, 0}));
  auto sim = scene::build_simulation(s);
  // About 2,500 samples per turn; a full turn after the first quarter takes gamma_dot t ~ 35 at the
  // aspect ratios seen (up to ~5); 60 leaves room for slower ones.
  const int every = std::max(1, static_cast<int>(0.01 / flow.shear_rate));
  const auto turn = follow_turn(*sim, every, 2.6 * std::numbers::pi, static_cast<long>(60 / flow.shear_rate));
  const JefferyFit fit = fit_jeffery(turn, flow.shear_rate);
  r.reynolds = kJefferyReynolds;
  r.stop = fit.complete ? "time" : "cap";
  if (fit.complete) {
    r.measured = fit.shear_period;
    r.error = std::abs(fit.shear_period / jeffery_shear_period(kJefferyAspectRatio) - 1);
    r.aspect_ratio = fit.aspect_ratio;
    r.jeffery_period_error = fit.period_error;
    r.law_deviation = fit.law_deviation;
  } else {
    r.measured = r.error = kNoValue;
  }
  clock.finish(*sim, r);
  return r;
}

std::vector<Method> rotation_methods(const RunSettings& settings, std::vector<std::string>* skipped) {
  std::vector<Method> methods;
  for (auto collision : {fluid::CollisionModel::kBgk, fluid::CollisionModel::kTrt, fluid::CollisionModel::kRegularized}) {
    if (!collision_differs_from_bgk(collision, scene::LatticeKind::kD2Q9, settings)) {
      if (skipped) skipped->push_back(method_name({scene::LatticeKind::kD2Q9, scene::Precision::kDouble, collision}));
      continue;
    }
    for (double spacing : {1.0, 0.5})
      methods.push_back({scene::LatticeKind::kD2Q9, scene::Precision::kDouble, collision, spacing});
  }
  return methods;
}

}  // namespace lbsolid::accuracy
