#include "solid/solid_system.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>

#include "solid/body_shape.h"

namespace lbsolid::solid {

SolidSystem::SolidSystem(int dimension) : topology_{dimension}, links_(2 * dimension) {
  if (dimension != 2 && dimension != 3)
    throw std::invalid_argument("dimension: must be 2 or 3, got " + std::to_string(dimension));
}

int SolidSystem::add_body(const std::string& name, const std::vector<Label>& labels, double spacing,
                          const Vec3& centre, const Vec3& velocity, const Vec3& load, const Vec3& angular_velocity,
                          bool rotates) {
  const int first = particle_count();
  const int n = static_cast<int>(labels.size());
  std::map<Label, int> index;
  for (int q = 0; q < n; ++q)
    if (!index.emplace(labels[q], first + q).second)
      throw std::invalid_argument("labels: a label appears twice in body '" + name + "'");
  const auto masses = link_masses(labels, topology_);
  if (std::find(masses.begin(), masses.end(), 0.0) != masses.end())
    throw std::invalid_argument("labels: a particle of body '" + name + "' has no neighbour (M = K/2 = 0)");
  const auto positions = placed_positions(labels, centre, spacing);
  const int body = body_count();
  bodies_.push_back({name, first, n, spacing, load, rotates});
  double total_mass = 0;
  for (int q = 0; q < n; ++q) {
    total_mass += masses[q];
    for (int a = 0; a < 3; ++a) bodies_.back().rest_centroid[a] += masses[q] * spacing * labels[q][a];
  }
  for (int a = 0; a < 3; ++a) bodies_.back().rest_centroid[a] /= total_mass;
  for (int q = 0; q < n; ++q) {
    const Label& l = labels[q];
    body_index_.push_back(body);
    labels_.push_back(l);
    positions_.push_back(positions[q]);
    mass_.push_back(masses[q]);
    for (int k = 0; k < links_; ++k) {
      const Label c = topology_.link(k);
      const auto it = index.find({l[0] + c[0], l[1] + c[1], l[2] + c[2]});
      neighbours_.push_back(it == index.end() ? -1 : it->second);
    }
  }
  // A rigid motion: every existing incoming link carries velocity/2. Link k arrives from l - c_k,
  // which exists exactly when link opp(k) of l does.
  const Vec3 half{0.5 * velocity[0], 0.5 * velocity[1], 0.5 * velocity[2]};
  for (int p = first; p < first + n; ++p)
    for (int k = 0; k < links_; ++k) {
      incoming_.push_back(neighbours_[p * links_ + topology_.opposite(k)] >= 0 ? half : Vec3{0, 0, 0});
      outgoing_.push_back({0, 0, 0});
    }
  momentum_.resize(particle_count());
  if (angular_velocity != Vec3{0, 0, 0}) set_spin(body, velocity, angular_velocity);
  links_ == 6 ? update_momentum<6>(first, first + n) : update_momentum<4>(first, first + n);
  if (rotates) {
    any_rotates_ = true;
    bodies_[body].frame = best_fit_rotation(body);
    if (dimension() == 2) bodies_[body].angle = best_fit_angle(body);
  }
  return body;
}

Vec3 SolidSystem::rest_separation(int p, int k) const {
  if (neighbour(p, k) < 0) return {0, 0, 0};
  const Label c = topology_.link(k);
  const double spacing = bodies_[body_index_[p]].spacing;
  return {spacing * c[0], spacing * c[1], spacing * c[2]};
}

double SolidSystem::energy(int p) const {
  double e = 0;
  for (int k = 0; k < links_; ++k)
    for (int a = 0; a < 3; ++a) e += incoming_[p * links_ + k][a] * incoming_[p * links_ + k][a];
  return e;
}

Vec3 SolidSystem::total_momentum() const {
  Vec3 total{0, 0, 0};
  for (int p = 0; p < particle_count(); ++p) {
    const Vec3 psi = momentum(p);
    for (int a = 0; a < 3; ++a) total[a] += psi[a];
  }
  return total;
}

double SolidSystem::total_energy() const {
  double total = 0;
  for (int p = 0; p < particle_count(); ++p) total += energy(p);
  return total;
}

std::size_t SolidSystem::bytes_allocated() const {
  return body_index_.capacity() * sizeof(int) + labels_.capacity() * sizeof(Label) +
         positions_.capacity() * sizeof(Vec3) + mass_.capacity() * sizeof(double) +
         neighbours_.capacity() * sizeof(int) +
         (incoming_.capacity() + outgoing_.capacity() + momentum_.capacity()) * sizeof(Vec3);
}

void SolidSystem::restore(const SolidState& state) {
  const std::size_t n = positions_.size();
  if (state.positions.size() != n || state.momentum.size() != n || state.incoming.size() != incoming_.size())
    throw std::invalid_argument("solid state: holds " + std::to_string(state.positions.size()) + " particles and " +
                                std::to_string(state.incoming.size()) + " link slots; this solid has " +
                                std::to_string(n) + " and " + std::to_string(incoming_.size()));
  positions_ = state.positions;
  incoming_ = state.incoming;
  momentum_ = state.momentum;
  for (int b = 0; b < body_count(); ++b)
    if (bodies_[b].rotates) {  // as the last step left it
      bodies_[b].frame = best_fit_rotation(b);
      if (dimension() == 2) bodies_[b].angle = best_fit_angle(b);
    }
}

}  // namespace lbsolid::solid
