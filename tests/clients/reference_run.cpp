// lbsolid-reference: runs a scenario file in process, through the same translation and core the
// daemon uses, and prints the numbers a client of the daemon would receive for it, so that the
// Python and Go client tests can check theirs to the last bit.
//
//   lbsolid-reference SCENARIO --steps N [--profiles-every K] [--particles-every K] [--fields]
//
// One record per line, every number as a C99 hexadecimal float (%a: exact, read back by Python's
// float.fromhex and Go's strconv.ParseFloat):
//   profile STEP NY y[NY] u_x[NY]                                   (ProfileFrame)
//   body STEP NAME N position[3N] velocity[3N] com[3] mean_velocity[3] mass energy
//        angular_momentum[3] angular_velocity[3] orientation orientation_quaternion[4] torque[3]  (BodyFrame)
//   field NAME STEP COUNT values[COUNT]                              (GetField, after the last step)
// Frames are printed at step 0 and at every multiple of K up to N, as a lossless stream sends them.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "scene/scene.h"
#include "scene/simulation.h"
#include "io/api/scenario_translation.h"

namespace {

using lbsolid::scene::Simulation;

void print_values(const std::vector<double>& values) {
  for (double v : values) std::printf(" %a", v);
}

void print_profile(const Simulation& sim) {
  const auto u = sim.velocity_profile();
  const double dy = sim.scene().lattice == lbsolid::scene::LatticeKind::kD2Q7 ? std::sqrt(3.0) / 2 : 1.0;
  std::vector<double> y(u.size());
  for (std::size_t j = 0; j < u.size(); ++j) y[j] = static_cast<double>(j) * dy;
  std::printf("profile %ld %zu", sim.step_count(), u.size());
  print_values(y);
  print_values(u);
  std::printf("\n");
}

// The same quantities, summed in the same order, as Session::particle_frame.
void print_bodies(const Simulation& sim) {
  const auto& solid = *sim.solid();
  for (int b = 0; b < solid.body_count(); ++b) {
    const auto& body = solid.body(b);
    std::vector<double> position, velocity;
    double energy = 0;
    for (int p = body.first; p < body.first + body.count; ++p) {
      energy += solid.energy(p);
      const auto& r = solid.position(p);
      const auto u = sim.particle_velocity(p);
      for (int a = 0; a < 3; ++a) {
        position.push_back(r[a]);
        velocity.push_back(u[a]);
      }
    }
    const auto state = sim.body_state(b);
    std::printf("body %ld %s %d", sim.step_count(), body.name.c_str(), body.count);
    print_values(position);
    print_values(velocity);
    print_values({state.centre_of_mass[0], state.centre_of_mass[1], state.centre_of_mass[2]});
    print_values({state.velocity[0], state.velocity[1], state.velocity[2], state.mass, energy});
    print_values({state.angular_momentum[0], state.angular_momentum[1], state.angular_momentum[2]});
    print_values({state.angular_velocity[0], state.angular_velocity[1], state.angular_velocity[2], state.orientation});
    const auto& q = state.orientation_quaternion;
    print_values({q[0], q[1], q[2], q[3]});
    print_values({state.torque[0], state.torque[1], state.torque[2]});
    std::printf("\n");
  }
}

int usage(const std::string& why) {
  std::cerr << "lbsolid-reference: " << why << "\n"
            << "usage: lbsolid-reference SCENARIO --steps N [--profiles-every K] [--particles-every K] [--fields]\n";
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  std::string path;
  long steps = -1, profiles_every = 0, particles_every = 0;
  bool fields = false;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    auto next_number = [&](long* out) {
      if (i + 1 >= argc) return false;
      *out = std::stol(argv[++i]);
      return true;
    };
    if (arg == "--steps") {
      if (!next_number(&steps)) return usage("--steps needs a value");
    } else if (arg == "--profiles-every") {
      if (!next_number(&profiles_every)) return usage("--profiles-every needs a value");
    } else if (arg == "--particles-every") {
      if (!next_number(&particles_every)) return usage("--particles-every needs a value");
    } else if (arg == "--fields") {
      fields = true;
    } else if (path.empty() && arg.rfind("--", 0) != 0) {
      path = arg;
    } else {
      return usage("unknown argument " + arg);
    }
  }
  if (path.empty()) return usage("no scenario file");
  if (steps < 0) return usage("--steps must be given and >= 0");

  std::ifstream in(path);
  if (!in) return usage("cannot read " + path);
  std::stringstream text;
  text << in.rdbuf();
  lbsolid::v1::Scenario scenario;
  std::string error;
  if (!lbsolid::server::parse_scenario_text(text.str(), &scenario, &error)) return usage(path + ": " + error);
  const auto translated = lbsolid::server::translate_scenario(scenario);
  if (!translated.ok()) return usage(translated.errors.front());

  const auto sim = lbsolid::scene::build_simulation(translated.scene);
  auto print_frames = [&] {
    const long step = sim->step_count();
    if (profiles_every > 0 && step % profiles_every == 0) print_profile(*sim);
    if (particles_every > 0 && step % particles_every == 0 && sim->solid()) print_bodies(*sim);
  };
  print_frames();
  for (long s = 0; s < steps; ++s) {
    sim->step();
    print_frames();
  }
  if (fields) {
    const auto f = sim->fluid_fields();
    std::printf("field density %ld %zu", sim->step_count(), f.density.size());
    print_values(f.density);
    std::printf("\nfield velocity %ld %zu", sim->step_count(), f.velocity.size());
    print_values(f.velocity);
    std::printf("\n");
  }
  return 0;
}
