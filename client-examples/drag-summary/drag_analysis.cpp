#include "drag_analysis.h"

#include <cmath>
#include <stdexcept>

#include "scene/scene.h"
#include "io/api/scenario_translation.h"
#include "solid/body_shape.h"

namespace lbsolid::drag {

double DragSetup::diameter() const {
  // Labels run from -R to +R and each particle stands for one spacing: (2R + 1) spacings.
  return (2 * std::floor(radius) + 1) * spacing;
}

DragSetup drag_setup(const lbsolid::v1::Scenario& scenario) {
  const auto translated = lbsolid::server::translate_scenario(scenario);
  if (!translated.ok()) throw std::runtime_error("the scenario does not translate: " + translated.errors.front());
  const scene::Scene& s = translated.scene;
  if (!s.with_fluid) throw std::runtime_error("the scenario has no fluid: there is no drag to measure");
  DragSetup setup;
  setup.scenario_name = scenario.name();
  setup.lattice = scene::lattice_kind_name(s.lattice);
  setup.dimension = scene::lattice_dimension(s.lattice);
  setup.omega = s.fluid.omega;
  setup.rho0 = s.fluid.rho0;
  setup.cs2 = scene::lattice_cs2(s.lattice);
  for (std::size_t i = 0; i < s.bodies.size(); ++i) {
    const solid::BodySpec& body = s.bodies[i];
    if (body.shape != solid::BodyShape::kDisk) continue;
    setup.body = body.name.empty() ? "body" + std::to_string(i) : body.name;
    setup.radius = body.radius;
    setup.spacing = body.spacing;
    setup.particles = static_cast<long>(solid::body_labels(body, setup.dimension).size());
    setup.load = body.load[0];
    setup.initial_velocity = body.velocity[0];
    if (setup.load == 0) throw std::runtime_error("the disk '" + setup.body + "' has no load along x");
    return setup;
  }
  throw std::runtime_error("the scenario has no DISK body");
}

DragResult analyse_drag(const DragSetup& setup, const lbsolid::server::storage::H5mdSeries& velocity) {
  if (velocity.value_shape.size() != 1 || velocity.value_shape[0] < 1)
    throw std::runtime_error("the velocity series is not one vector per frame");
  const std::size_t width = static_cast<std::size_t>(velocity.value_shape[0]);
  const std::size_t frames = velocity.step.size();
  if (frames < 3 || velocity.value.size() < frames * width)
    throw std::runtime_error("the velocity series has " + std::to_string(frames) + " frames; the fit needs 3 or more");
  DragResult r;
  // The test samples from step 0, where the disk moves at its initial velocity; a recording
  // starting later gets that sample from the scenario.
  if (velocity.step.front() > 0) {
    r.t.push_back(0);
    r.u.push_back(setup.initial_velocity);
    r.origin_added = true;
  }
  for (std::size_t k = 0; k < frames; ++k) {
    r.t.push_back(static_cast<double>(velocity.step[k]));
    r.u.push_back(velocity.value[k * width]);
  }
  r.fit = observe::fit_saturating_exponential(r.t, r.u);
  const double u_inf = r.fit.terminal, d = setup.diameter();
  r.reynolds = u_inf * d / setup.viscosity();
  r.drag_coefficient = setup.force() / (setup.rho0 * u_inf * u_inf * d);
  r.relaxation_times = r.fit.rate * r.t.back();
  return r;
}

}  // namespace lbsolid::drag
