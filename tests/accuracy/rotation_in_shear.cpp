#include "accuracy/rotation_in_shear.h"

#include <cmath>
#include <numbers>

namespace lbsolid::accuracy {

namespace {
constexpr double kPi = std::numbers::pi;
}

scene::Scene couette_scene(const CouetteFlow& flow) {
  scene::Scene s;
  s.lattice = flow.lattice;
  s.precision = flow.precision;
  s.fluid.nx = flow.length;
  s.fluid.ny = flow.height;
  s.fluid.omega = flow.omega;
  s.fluid.collision = flow.collision;
  s.fluid.threads = flow.threads;
  const double wall_speed = flow.shear_rate * flow.height / 2;
  s.fluid.sides[fluid::kYLow].kind = fluid::WallKind::kMovingWall;
  s.fluid.sides[fluid::kYLow].wall_velocity = {-wall_speed, 0, 0};
  s.fluid.sides[fluid::kYHigh].kind = fluid::WallKind::kMovingWall;
  s.fluid.sides[fluid::kYHigh].wall_velocity = {wall_speed, 0, 0};
  return s;
}

double viscosity(const CouetteFlow& flow) { return (1 / flow.omega - 0.5) * scene::lattice_cs2(flow.lattice); }

solid::BodySpec lattice_ellipse(double a, double b, double spacing, const solid::Vec3& centre) {
  solid::BodySpec e;
  e.shape = solid::BodyShape::kLabels;
  const int reach_x = static_cast<int>(std::ceil(a / spacing)), reach_y = static_cast<int>(std::ceil(b / spacing));
  for (int j = -reach_y; j <= reach_y; ++j)
    for (int i = -reach_x; i <= reach_x; ++i) {
      const double x = i * spacing / a, y = j * spacing / b;
      if (x * x + y * y <= 1 + 1e-12) e.labels.push_back({i, j, 0});
    }
  e.spacing = spacing;
  e.centre = centre;  // the labels are symmetric: their centroid is (0, 0)
  e.rotation = true;
  return e;
}

std::vector<TurnSample> follow_turn(scene::Simulation& sim, int every, double until, long max_steps) {
  std::vector<TurnSample> samples{{0, 0}};
  double last = sim.body_state(0).orientation;  // counter-clockwise, in (-pi, pi]
  for (long step = 0; step < max_steps && samples.back().angle < until;) {
    sim.run(every);
    step += every;
    const double now = sim.body_state(0).orientation;
    samples.push_back({step, samples.back().angle - std::remainder(now - last, 2 * kPi)});
    last = now;
  }
  return samples;
}

double jeffery_angle(double psi, double r) {
  // tan(phi) = tan(psi) / r, written as psi minus the lag: tan(psi - phi) is
  // (r - 1) sin cos / (r cos^2 + sin^2), whose denominator never vanishes.
  const double s = std::sin(psi), c = std::cos(psi);
  return psi - std::atan2((r - 1) * s * c, r * c * c + s * s);
}

double jeffery_shear_period(double r) { return 2 * kPi * (r + 1 / r); }

JefferyFit fit_jeffery(const std::vector<TurnSample>& samples, double shear_rate) {
  // passage[k]: when the angle first reaches k pi / 4 (linear between samples), k = 2 .. 10.
  double passage[11];
  std::size_t i = 1;
  for (int k = 2; k <= 10; ++k) {
    const double level = k * kPi / 4;
    while (i < samples.size() && samples[i].angle < level) ++i;
    if (i >= samples.size()) return {};
    const TurnSample &p = samples[i - 1], &q = samples[i];
    passage[k] = p.step + (level - p.angle) / (q.angle - p.angle) * (q.step - p.step);
  }
  JefferyFit fit;
  fit.complete = true;
  const double period = passage[10] - passage[2];
  fit.shear_period = shear_rate * period;
  fit.half_periods[0] = shear_rate * (passage[6] - passage[2]);
  fit.half_periods[1] = shear_rate * (passage[10] - passage[6]);
  // Within 45 degrees of the flow: angles pi -+ pi/4 and 2 pi -+ pi/4.
  const double near_flow = (passage[5] - passage[3] + passage[9] - passage[7]) / period;
  fit.aspect_ratio = std::tan(kPi * near_flow / 2);
  fit.period_error = fit.shear_period / jeffery_shear_period(fit.aspect_ratio) - 1;
  for (int half = 0; half < 2; ++half) {
    const double from = passage[2 + 4 * half], to = passage[6 + 4 * half];
    for (const TurnSample& s : samples) {
      if (s.step < from || s.step > to) continue;
      const double psi = -kPi / 2 + kPi * (s.step - from) / (to - from);
      const double expected = (1 + half) * kPi + jeffery_angle(psi, fit.aspect_ratio);
      fit.law_deviation = std::max(fit.law_deviation, std::abs(s.angle - expected));
    }
  }
  return fit;
}

}  // namespace lbsolid::accuracy
