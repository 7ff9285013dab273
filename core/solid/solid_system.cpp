#include "solid/solid_system.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <map>
#include <set>
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
  if (std::set<Label>(labels.begin(), labels.end()).size() != labels.size())
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
  positions_change();
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
  }
  neighbours_.resize(mass_.size() * links_);
  place_links(body, neighbours_);
  for (int p = first; p < first + n; ++p)
    for (int k = 0; k < links_; ++k)
      if (const int q = neighbours_[static_cast<std::size_t>(p) * links_ + k]; q >= 0) reach_ = std::max(reach_, std::abs(q - p));
  if (!anchored_.empty()) anchored_.resize(mass_.size(), 0);  // a later body starts unanchored
  // A rigid motion: every existing incoming link carries velocity/2. Link k arrives from l - c_k,
  // which exists exactly when link opp(k) of l does.
  const Vec3 half{0.5 * velocity[0], 0.5 * velocity[1], 0.5 * velocity[2]};
  for (int p = first; p < first + n; ++p)
    for (int k = 0; k < links_; ++k) {
      const Vec3 f = neighbours_[p * links_ + topology_.opposite(k)] >= 0 ? half : Vec3{0, 0, 0};
      incoming_.insert(incoming_.end(), f.begin(), f.begin() + dim_);
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

void SolidSystem::place_links(int b, std::vector<int>& neighbours) const {
  const Body& body = bodies_[b];
  std::map<Label, int> index;
  for (int p = body.first; p < body.first + body.count; ++p) index.emplace(labels_[p], p);
  for (int p = body.first; p < body.first + body.count; ++p) {
    const Label& l = labels_[p];
    for (int k = 0; k < links_; ++k) {
      const Label c = topology_.link(k);
      const auto it = index.find({l[0] + c[0], l[1] + c[1], l[2] + c[2]});
      neighbours[static_cast<std::size_t>(p) * links_ + k] = it == index.end() ? -1 : it->second;
    }
  }
}

double SolidSystem::mass_from_links(const std::vector<int>& neighbours, int p) const {
  int links = 0;
  for (int k = 0; k < links_; ++k) links += neighbours[static_cast<std::size_t>(p) * links_ + k] >= 0;
  return 0.5 * links;
}

RemovedVectors SolidSystem::break_link(int p, int k, long step) {
  const int q = neighbour(p, k);
  if (q < 0) throw std::logic_error("break_link: particle " + std::to_string(p) + " has no link " + std::to_string(k));
  const int back = topology_.opposite(k);
  RemovedVectors removed{q, incoming(p, back), incoming(q, k)};
  const std::size_t slot_p = (static_cast<std::size_t>(p) * links_ + back) * dim_;
  const std::size_t slot_q = (static_cast<std::size_t>(q) * links_ + k) * dim_;
  // Nothing arrives along a missing link again: the step replaces only existing links' vectors.
  std::fill_n(&incoming_[slot_p], dim_, 0.0);
  std::fill_n(&incoming_[slot_q], dim_, 0.0);
  neighbours_[static_cast<std::size_t>(p) * links_ + k] = -1;
  neighbours_[static_cast<std::size_t>(q) * links_ + back] = -1;
  mass_[p] = mass_from_links(neighbours_, p);
  mass_[q] = mass_from_links(neighbours_, q);
  const auto resum = [&](int x) {
    links_ == 6 ? update_momentum<6>(x, x + 1) : update_momentum<4>(x, x + 1);
  };
  resum(p);
  resum(q);
  const Vec3 rp = position(p), rq = position(q);
  const int lower = k < dimension() ? p : q;  // recorded from its lower end
  broken_.push_back({step, lower, k % dimension(), {(rp[0] + rq[0]) / 2, (rp[1] + rq[1]) / 2, (rp[2] + rq[2]) / 2}});
  return removed;
}

void SolidSystem::shed(int p, const Vec3& momentum) {
  if (mass_[p] != 0) throw std::logic_error("shed: particle " + std::to_string(p) + " still has a link");
  if (shed_momentum_.empty()) shed_momentum_.assign(bodies_.size(), Vec3{0, 0, 0});
  for (int a = 0; a < 3; ++a) shed_momentum_[body_index_[p]][a] += momentum[a];
  any_shed_ = true;
}

Vec3 SolidSystem::total_shed_momentum() const {
  Vec3 total{0, 0, 0};
  for (const Vec3& m : shed_momentum_)
    for (int a = 0; a < 3; ++a) total[a] += m[a];
  return total;
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
         (positions_.capacity() + incoming_.capacity() + base_.capacity() + momentum_.capacity()) * sizeof(double) +
         broken_.capacity() * sizeof(BrokenLink) + shed_momentum_.capacity() * sizeof(Vec3);
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
  return {as_vec3(positions_, dim_), as_vec3(incoming_, dim_), as_vec3(momentum_, dim_), broken_, shed_momentum_};
}

void SolidSystem::restore(const SolidState& state) {
  const std::size_t n = particle_count(), slots = n * links_;
  if (state.positions.size() != n || state.momentum.size() != n || state.incoming.size() != slots)
    throw std::invalid_argument("solid state: holds " + std::to_string(state.positions.size()) + " particles and " +
                                std::to_string(state.incoming.size()) + " link slots; this solid has " +
                                std::to_string(n) + " and " + std::to_string(slots));
  if (!state.shed_momentum.empty() && state.shed_momentum.size() != bodies_.size())
    throw std::invalid_argument("solid state: shed momentum for " + std::to_string(state.shed_momentum.size()) +
                                " bodies; this solid has " + std::to_string(bodies_.size()));
  auto positions = as_stored(state.positions, dim_, "a position");
  auto incoming = as_stored(state.incoming, dim_, "a link vector");
  auto momentum = as_stored(state.momentum, dim_, "a momentum");
  as_stored(state.shed_momentum, dim_, "a shed momentum");  // only checked: kept as Vec3
  // The links as placed, less the broken ones; every missing link's slot must be empty.
  std::vector<int> neighbours(slots);
  for (int b = 0; b < body_count(); ++b) place_links(b, neighbours);
  for (std::size_t i = 0; i < state.broken.size(); ++i) {
    const BrokenLink& link = state.broken[i];
    const std::string which = "solid state: broken link " + std::to_string(i);
    if (link.particle < 0 || static_cast<std::size_t>(link.particle) >= n || link.link < 0 || link.link >= dim_)
      throw std::invalid_argument(which + " names no link of this solid");
    if (link.step < 0) throw std::invalid_argument(which + " has a negative step");
    int& forward = neighbours[static_cast<std::size_t>(link.particle) * links_ + link.link];
    if (forward < 0) throw std::invalid_argument(which + " is not a link of this solid, or is broken twice");
    neighbours[static_cast<std::size_t>(forward) * links_ + topology_.opposite(link.link)] = -1;
    forward = -1;
  }
  for (std::size_t p = 0; p < n; ++p)
    for (int k = 0; k < links_; ++k)
      if (neighbours[p * links_ + topology_.opposite(k)] < 0)
        for (int a = 0; a < dim_; ++a)
          if (incoming[(p * links_ + k) * dim_ + a] != 0)
            throw std::invalid_argument("solid state: particle " + std::to_string(p) + " receives along link " +
                                        std::to_string(k) + ", which it does not have");
  positions_change();
  positions_ = std::move(positions);
  incoming_ = std::move(incoming);
  momentum_ = std::move(momentum);
  neighbours_ = std::move(neighbours);
  any_shed_ = false;
  for (int p = 0; p < static_cast<int>(n); ++p) {
    mass_[p] = mass_from_links(neighbours_, p);
    any_shed_ = any_shed_ || mass_[p] == 0;
  }
  broken_ = state.broken;
  shed_momentum_ = state.shed_momentum;
  for (int b = 0; b < body_count(); ++b)
    if (bodies_[b].rotates) {  // as the last step left it
      bodies_[b].frame = best_fit_rotation(b);
      if (dimension() == 2) bodies_[b].angle = best_fit_angle(b);
    }
}

void SolidSystem::positions_change() {
  static std::atomic<std::uint64_t> last_version{0};
  positions_version_ = last_version.fetch_add(1, std::memory_order_relaxed) + 1;
}

void SolidSystem::anchor(int p) {
  if (anchored_.empty()) anchored_.assign(mass_.size(), 0);
  anchored_[p] = 1;
}

}  // namespace lbsolid::solid
