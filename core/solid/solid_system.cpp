#include "solid/solid_system.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>

#include "solid/body_shape.h"

namespace lbsolid::solid {

SolidSystem::SolidSystem(int dimension) : topology_{dimension}, links_(2 * dimension), dim_(dimension) {
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
  if (dim_ == 2 && (centre[2] != 0 || velocity[2] != 0 || load[2] != 0 || angular_velocity[0] != 0 ||
                    angular_velocity[1] != 0))
    throw std::invalid_argument("body '" + name + "': a 2D body has no z component of centre, velocity or load, "
                                "and spins only about z");
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
    positions_.insert(positions_.end(), positions[q].begin(), positions[q].begin() + dim_);
    mass_.push_back(masses[q]);
    for (int k = 0; k < links_; ++k) {
      const Label c = topology_.link(k);
      const auto it = index.find({l[0] + c[0], l[1] + c[1], l[2] + c[2]});
      neighbours_.push_back(it == index.end() ? -1 : it->second);
    }
  }
  if (!anchored_.empty()) anchored_.resize(mass_.size(), 0);  // a later body starts unanchored
  // A rigid motion: every existing incoming link carries velocity/2. Link k arrives from l - c_k,
  // which exists exactly when link opp(k) of l does.
  const Vec3 half{0.5 * velocity[0], 0.5 * velocity[1], 0.5 * velocity[2]};
  for (int p = first; p < first + n; ++p)
    for (int k = 0; k < links_; ++k) {
      const Vec3 f = neighbours_[p * links_ + topology_.opposite(k)] >= 0 ? half : Vec3{0, 0, 0};
      incoming_.insert(incoming_.end(), f.begin(), f.begin() + dim_);
      outgoing_.insert(outgoing_.end(), dim_, 0.0);
    }
  momentum_.resize(static_cast<std::size_t>(particle_count()) * dim_);
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
  for (int k = 0; k < links_; ++k) {
    const Vec3 f = incoming(p, k);
    for (int a = 0; a < 3; ++a) e += f[a] * f[a];
  }
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
         mass_.capacity() * sizeof(double) + neighbours_.capacity() * sizeof(int) + anchored_.capacity() +
         (positions_.capacity() + incoming_.capacity() + outgoing_.capacity() + momentum_.capacity()) * sizeof(double);
}

namespace {

std::vector<Vec3> as_vec3(const std::vector<double>& stored, int dimension) {
  const ParticleVectors view{stored.data(), dimension};
  std::vector<Vec3> v(stored.size() / dimension);
  for (std::size_t i = 0; i < v.size(); ++i) v[i] = view[static_cast<long>(i)];
  return v;
}

// Throws when a 2D system would be given a z component (it stores none).
std::vector<double> as_stored(const std::vector<Vec3>& v, int dimension, const char* what) {
  std::vector<double> stored;
  stored.reserve(v.size() * dimension);
  for (const Vec3& x : v) {
    if (dimension == 2 && x[2] != 0)
      throw std::invalid_argument(std::string("solid state: ") + what + " has a z component in a 2D solid");
    stored.insert(stored.end(), x.begin(), x.begin() + dimension);
  }
  return stored;
}

}  // namespace

SolidState SolidSystem::state() const {
  return {as_vec3(positions_, dim_), as_vec3(incoming_, dim_), as_vec3(momentum_, dim_)};
}

void SolidSystem::restore(const SolidState& state) {
  const std::size_t n = particle_count(), slots = n * links_;
  if (state.positions.size() != n || state.momentum.size() != n || state.incoming.size() != slots)
    throw std::invalid_argument("solid state: holds " + std::to_string(state.positions.size()) + " particles and " +
                                std::to_string(state.incoming.size()) + " link slots; this solid has " +
                                std::to_string(n) + " and " + std::to_string(slots));
  auto positions = as_stored(state.positions, dim_, "a position");
  auto incoming = as_stored(state.incoming, dim_, "a link vector");
  auto momentum = as_stored(state.momentum, dim_, "a momentum");
  positions_ = std::move(positions);
  incoming_ = std::move(incoming);
  momentum_ = std::move(momentum);
  for (int b = 0; b < body_count(); ++b)
    if (bodies_[b].rotates) {  // as the last step left it
      bodies_[b].frame = best_fit_rotation(b);
      if (dimension() == 2) bodies_[b].angle = best_fit_angle(b);
    }
}

void SolidSystem::anchor(int p) {
  if (anchored_.empty()) anchored_.assign(mass_.size(), 0);
  anchored_[p] = 1;
}

}  // namespace lbsolid::solid
