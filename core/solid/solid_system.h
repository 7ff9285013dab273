#pragma once
// The LB solid (MODEL.md section 2, the paper's eqs. 2-11): particles on a square or cubic label
// topology, each holding the vectors f_k that arrived along its links. One step with external
// forces F_l (eq. 6 and 7):
//   Psi_l = sum_k f_k(l),  f_k(l + c_k) <- Psi_l/M_l - f_opp(k)(l) + F_l/(2 M_l),
//   r_l   <- r_l + Psi_l/M_l + F_l/(2 M_l),        M_l = K_l / 2.
// Momentum (eq. 8), energy (eq. 10) and the deformation invariant (eq. 11) then hold exactly.
// Everything is double: the solid is small beside the fluid and its invariants are checked to
// round-off.
//
// Rotation (issue 16), per body and opt-in. Eqs. 6-7 are a leapfrog of particles
// joined by "vector springs": with D = r_q - r_p + f_k(q) - f_opp(k)(p) for the link from p to
// q = p + c_k (eq. 11's left side), a step changes Psi_q by the spring force -(r_q - r_p - D) at the
// new positions (and Psi_p by its opposite), and leaves D unchanged. With D fixed at the placed
// Delta0, a turned body is pulled back (the paper: it "cannot freely rotate"). After each step of
// a rotating body, every link's two vectors are shifted by +(T - D) at q and -(T - D) at p, with
// T = R Delta0 and R the rotation that best maps the rest links onto the new ones (2D: an atan2;
// 3D: Horn's quaternion, the top eigenvector of a 4 x 4 matrix): the step's
// spring forces are then those of springs at rest along T (co-rotational springs), D becomes
// 2T - D, and the body's momentum (eq. 8) is unchanged. The spring forces of the best fit have
// no net torque, so without other forces sum_p r_p x Psi_p is kept to round-off
// (solid/body_rotation.cpp; eq. 11 then holds with a D that follows the frame, not the placed Delta0).
#include <algorithm>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "parallel/thread_pool.h"
#include "solid/body_shape.h"
#include "solid/particle_vectors.h"
#include "solid/solid_topology.h"

namespace lbsolid::solid {

struct Body {
  std::string name;
  int first = 0;  // its particles are [first, first + count)
  int count = 0;
  double spacing = 1.0;  // rest distance between linked particles
  Vec3 load{0, 0, 0};    // external force on each particle
  bool rotates = false;  // the springs' rest frame turns with the body (above)
  double angle = 0;      // rotating 2D bodies: the frame's angle from the placed shape, (-pi, pi]
  Rotation frame{{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};  // rotating bodies: R, rows of a rotation matrix
  Vec3 rest_centroid{0, 0, 0};  // mass-weighted centroid of spacing * label
};

// A link that broke (fracture, issue 18): the link from `particle` along `link` (k < dimension, so
// from its lower end), at the start of step `step` (counted from 1: the state after that step is
// the first without it), its two ends' midpoint then at `position`.
struct BrokenLink {
  long step = 0;
  int particle = 0;
  int link = 0;
  Vec3 position{0, 0, 0};
  bool operator==(const BrokenLink&) const = default;
};

// Everything a SolidSystem changes as it runs (the bodies themselves come from their specs):
// restoring it into a system built from the same bodies continues the run bit for bit.
struct SolidState {
  std::vector<Vec3> positions;  // r_p
  std::vector<Vec3> incoming;   // f_k(p) at [p * links + k]
  std::vector<Vec3> momentum;   // Psi_p
  std::vector<BrokenLink> broken;  // in the order they broke
  std::vector<Vec3> shed_momentum;  // per body: what its particles held when they lost their last link
};

// What breaking a link takes out of the two particles' momenta: the vector each had received
// along it (MODEL.md section 5: handed back to its owner, so that momentum stays exact).
struct RemovedVectors {
  int neighbour = -1;      // q, the link's other end
  Vec3 at_particle{0, 0, 0};   // f_opp(k)(p), taken from Psi_p
  Vec3 at_neighbour{0, 0, 0};  // f_k(q), taken from Psi_q
};

class SolidSystem {
 public:
  explicit SolidSystem(int dimension);

  // Adds the particles at `labels`, placed at centre + spacing (l - centroid), moving rigidly at
  // `velocity` (f_k = velocity/2 on every existing incoming link, so Psi = M velocity). Labels
  // must be distinct and each must have a neighbour (validate_body_spec). Returns the body index.
  // With an angular velocity w (2D: about z), the body also spins about its centre of mass: each
  // link's two vectors are (v_l + v_m)/4 with v = velocity + w x (rest offset), so that the shape is
  // the rest shape (eq. 11 with every f difference zero) and the body's momentum is M velocity;
  // rim particles, with fewer links, then move slightly differently from a rigid rotation.
  // `rotates`: the springs' rest frame turns with the body.
  int add_body(const std::string& name, const std::vector<Label>& labels, double spacing,
               const Vec3& centre, const Vec3& velocity, const Vec3& load,
               const Vec3& angular_velocity = {0, 0, 0}, bool rotates = false);

  // One step with the total external force on particle p given by `force(p)` (a Vec3, loads
  // included by the caller), evaluated once per particle as the step reaches it: it may read this
  // system's momentum, position and mass of p, which are still those before the step.
  // With a pool, the particles are cut into `parts` ranges run on it: each link's two vectors are
  // replaced once, by one thread, from values no other link changes, so the result is the same
  // bit for bit (stream()).
  template <class Force>
  void step(const Force& force, parallel::ThreadPool* pool = nullptr, int parts = 1) {
    stream(force, pool, parts);
    turn_frames(pool, parts);
  }
  void step(const std::vector<Vec3>& force, parallel::ThreadPool* pool = nullptr, int parts = 1) {
    step([&force](int p) -> const Vec3& { return force[p]; }, pool, parts);
  }
  // A step's two halves, for a caller that runs them as separate stages: eqs. 6-7 with the springs'
  // frames as they are, then the rotating bodies' frames turned to their best fit (above). With a
  // pool, the bodies are cut into `parts` ranges: a body's turn touches only its own particles.
  template <class Force>
  void stream(const Force& force, parallel::ThreadPool* pool = nullptr, int parts = 1) {
    stream(force, NoPositionsSeen{}, pool, parts);
  }
  // The same, showing the new positions to `seen` as the step stores them, while they are in the
  // cache: each range of particles the step runs gets `auto range = seen.range()`, then
  // range(first, end) for each block of its particles, in order, once their positions are final,
  // and range.finish() after its last (not if the step throws). The coupling finds each
  // particle's next node so, instead of reading every position again in a pass of its own.
  template <class Force, class PositionsSeen>
  void stream(const Force& force, const PositionsSeen& seen, parallel::ThreadPool* pool = nullptr, int parts = 1);
  // A number that changes whenever the positions may have: taken from one counter for the whole
  // process, so that two systems share one only where one is a copy of the other, positions
  // and all. What was worked out from the positions is current while the number is the same.
  std::uint64_t positions_version() const { return positions_version_; }
  void turn_frames(parallel::ThreadPool* pool = nullptr, int parts = 1) {
    if (!any_rotates_) return;
    const auto turn = [&](long first, long end) {
      for (long b = first; b < end; ++b)
        if (bodies_[b].rotates) co_rotate(static_cast<int>(b));
    };
    if (pool && parts > 1 && body_count() > 1) pool->parallel_for(body_count(), parts, turn);
    else turn(0, body_count());
  }

  const SolidTopology& topology() const { return topology_; }
  int dimension() const { return topology_.dimension; }
  int particle_count() const { return static_cast<int>(mass_.size()); }
  int body_count() const { return static_cast<int>(bodies_.size()); }
  const Body& body(int b) const { return bodies_[b]; }
  int body_of(int p) const { return body_index_[p]; }
  const Label& label(int p) const { return labels_[p]; }
  Vec3 position(int p) const { return positions()[p]; }
  ParticleVectors positions() const { return {positions_.data(), dim_}; }
  double mass(int p) const { return mass_[p]; }  // K/2
  const std::vector<double>& masses() const { return mass_; }
  ParticleVectors momenta() const { return {momentum_.data(), dim_}; }
  int neighbour(int p, int k) const { return neighbours_[p * links_ + k]; }  // -1 if missing
  Vec3 incoming(int p, int k) const { return ParticleVectors{incoming_.data(), dim_}[p * links_ + k]; }  // f_k(p)
  Vec3 momentum(int p) const { return momenta()[p]; }  // Psi_p = sum_k f_k(p), kept current
  double energy(int p) const;  // E_p = sum_k |f_k(p)|^2 (eq. 9)
  // Delta0_k(p) fixed at placement: the rest separation from p to its neighbour along link k
  // (spacing c_k; zero where the link is missing).
  Vec3 rest_separation(int p, int k) const;

  // Particle p's rest position relative to its body's rest centroid: spacing * label - centroid.
  Vec3 rest_offset(int p) const;
  // The rotation R that best maps body b's rest links onto its current ones (the maximum of the
  // sum over links of (r_q - r_p) . R Delta0). For a straight chain in 3D the turn about its own
  // axis is left undetermined; it changes no T. 2D: its angle, in (-pi, pi].
  Rotation best_fit_rotation(int b) const;
  double best_fit_angle(int b) const;
  // The same rotation as a unit quaternion with w >= 0 (2D: about z, half of best_fit_angle).
  Quaternion best_fit_quaternion(int b) const;


  // Holds particle p where it is (an anchor, MODEL.md section 5): its step's total force is then
  // -2 Psi_p, which keeps r_p (eq. 7) and sends each arriving vector back negated (eq. 6); the
  // caller (the solid stage) supplies that force and books what the anchor absorbed.
  void anchor(int p);
  bool anchored(int p) const { return !anchored_.empty() && anchored_[p]; }
  bool any_anchored() const { return !anchored_.empty(); }
  const std::vector<char>& anchored_flags() const { return anchored_; }  // per particle; empty: none
  // Fracture (issue 18, MODEL.md section 5). Removes the link from p along k: its two vectors
  // leave both buffers (returned, for the caller to hand back as this step's impulses), both ends
  // lose half a unit of mass (M = K/2) and their momenta are summed again from what they still
  // receive. Records the break at `step` (BrokenLink).
  RemovedVectors break_link(int p, int k, long step);
  // Particle p lost its last link (M = 0): it leaves the dynamics where it is (no motion, no
  // force, no exchange) and `momentum`, what it still held, is booked with its body.
  void shed(int p, const Vec3& momentum);
  bool shed(int p) const { return mass_[p] == 0; }
  const std::vector<BrokenLink>& broken_links() const { return broken_; }
  Vec3 shed_momentum(int b) const { return shed_momentum_.empty() ? Vec3{0, 0, 0} : shed_momentum_[b]; }
  Vec3 total_shed_momentum() const;
  Vec3 total_momentum() const;
  double total_energy() const;

  SolidState state() const;
  // Throws std::invalid_argument when the sizes do not match this system's particles and links,
  // or when a 2D system is given a vector with a z component.
  void restore(const SolidState& state);
  std::size_t bytes_allocated() const;

 private:
  SolidTopology topology_;
  int links_;
  int dim_;  // components stored per vector (particle_vectors.h)
  std::vector<Body> bodies_;
  std::vector<int> body_index_;
  std::vector<Label> labels_;
  std::vector<double> positions_;  // r_p at [p * dim + a]
  std::vector<double> mass_;
  std::vector<char> anchored_;     // per particle once any is anchored, else empty
  std::vector<int> neighbours_;  // [p * links + k]
  std::vector<double> incoming_;   // f_k(p) at time t, at [(p * links + k) * dim + a], replaced in place
  std::vector<double> base_;       // per particle, during stream(): Psi/M + F/(2M) at [p * dim + a]
  std::vector<double> momentum_;   // Psi of the incoming vectors: read by the exchange, contact and step
  std::uint64_t positions_version_ = 0;
  // Called before anything changes the positions: a new positions_version().
  void positions_change();
  struct NoPositionsSeen {
    struct Range {
      void operator()(int, int) const {}
      void finish() const {}
    };
    Range range() const { return {}; }
  };
  double* position_at(int p) { return &positions_[static_cast<std::size_t>(p) * dim_]; }
  double* incoming_at(int p, int k) { return &incoming_[(static_cast<std::size_t>(p) * links_ + k) * dim_]; }
  // Per dimension (Links = 4 or 6, Links / 2 components) so that the loops unroll and opp(k) is a
  // constant.
  // Psi_p = sum_k f_k(p), for p in [first, end).
  template <int Links>
  void update_momentum(int first, int end);
  // The stream's blocks: small enough that a block's link vectors stay in the L1/L2 cache until
  // stream() sums them reach_ later.
  static constexpr int kStreamBlock = 256;
  // The step asks for the link vectors of the particle this many on (its own are replaced in place,
  // read and written back, from memory in a large solid): in one process, best of 8 rounds, the
  // solid stage 10.8 -> 9.8 ns a particle (2D sheets, 0.1 per cell), 21.3 -> 15.0 (3D balls).
  static constexpr int kVectorsAhead = 24;
  // Eqs. 6-7 in place for particles [first, end): each one's base Psi/M + F/(2M) (into base_) and
  // new position, and the links to particles in [lowest, p) (whose bases are in base_ already).
  template <int Links, bool kMayShed, class Force>
  void advance_in_place(const Force& force, int first, int end, int lowest);
  // The links from particles in [first, end) to particles below `below` (both bases in base_).
  template <int Links>
  void exchange_links(int first, int end, int below);
  // Link k of p, to q (whose base is in base_ as p's is): f_k(q) and f_opp(k)(p) replaced.
  template <int Links>
  void exchange_link(int p, int k, int q);
  template <class Range>
  void for_parts(parallel::ThreadPool* pool, int parts, const Range& range);
  // Turns body b's springs to its best-fit frame after a step (above; body_rotation.cpp).
  void co_rotate(int b);
  void set_spin(int b, const Vec3& velocity, const Vec3& angular_velocity);
  // Body b's links as placed, from its labels, into `neighbours` ([p * links + k], -1 if missing).
  void place_links(int b, std::vector<int>& neighbours) const;
  // M = K/2 from the links p has now.
  double mass_from_links(const std::vector<int>& neighbours, int p) const;
  // The largest |q - p| over the links placed (breaking links never raises it): a particle's
  // senders are all within reach_ of it in index order (stream()).
  int reach_ = 0;
  bool any_rotates_ = false;
  bool any_shed_ = false;  // some particle has M = 0 (a shed fragment)
  std::vector<BrokenLink> broken_;
  std::vector<Vec3> shed_momentum_;  // per body once a particle is shed, else empty
};

template <class Range>
void SolidSystem::for_parts(parallel::ThreadPool* pool, int parts, const Range& range) {
  const int n = particle_count();
  if (pool) pool->parallel_for(n, parts, [&](long first, long end) { range(static_cast<int>(first), static_cast<int>(end)); });
  else range(0, n);
}

template <class Force, class PositionsSeen>
void SolidSystem::stream(const Force& force, const PositionsSeen& seen, parallel::ThreadPool* pool, int parts) {
  // In place: a link's two vectors, f_k(q) (from p) and f_opp(k)(p) (from q), are each replaced
  // from the other and their senders' bases, so the step needs no second buffer of link vectors
  // (a quarter of a 2D particle's bytes, a third of a 3D one's). A link is done at its higher
  // end in index order, once both bases are known; the lower end lies within reach_ of it. So
  // each part advances its particles a block at a time and sums the momenta of the particles
  // reach_ behind, all of whose links are then done, while their vectors are still in cache. A
  // link between two parts, and the sums of the particles within reach_ of a part's ends, wait
  // until all parts are done. Every value is worked out as with two buffers, and every momentum
  // summed once in link order: the result is the same for any parts, bit for bit.
  positions_change();
  base_.resize(static_cast<std::size_t>(particle_count()) * dim_);
  const bool cubic = links_ == 6;
  const int n = particle_count();
  const auto advance_range = [&](int first, int end, int lowest) {
    if (cubic) any_shed_ ? advance_in_place<6, true>(force, first, end, lowest)
                         : advance_in_place<6, false>(force, first, end, lowest);
    else any_shed_ ? advance_in_place<4, true>(force, first, end, lowest)
                   : advance_in_place<4, false>(force, first, end, lowest);
  };
  const auto sum = [&](long first, long end) {
    if (first < end) cubic ? update_momentum<6>(first, end) : update_momentum<4>(first, end);
  };
  // The particles of [first, end) whose sums need no other part: all but reach_ at an end that
  // adjoins another part.
  const auto inner = [&](int first, int end) {
    return std::pair<long, long>{first > 0 ? static_cast<long>(first) + reach_ : first,
                                 end < n ? static_cast<long>(end) - reach_ : end};
  };
  for_parts(pool, parts, [&](int first, int end) {
    const auto [sum_first, sum_end] = inner(first, end);
    long summed = sum_first;
    auto seen_range = seen.range();
    for (int block = first, block_end; block < end; block = block_end) {
      block_end = block + std::min(kStreamBlock, end - block);
      advance_range(block, block_end, first);
      seen_range(block, block_end);
      const long ready = block_end == end ? sum_end : std::min<long>(block_end - reach_, sum_end);
      if (ready > summed) {
        sum(summed, ready);
        summed = ready;
      }
    }
    seen_range.finish();
  });
  if (!pool || parts <= 1) return;  // one part: nothing waits
  for_parts(pool, parts, [&](int first, int end) {  // the links to the part below
    if (first == 0) return;
    const int last = static_cast<int>(std::min<long>(end, static_cast<long>(first) + reach_));
    cubic ? exchange_links<6>(first, last, first) : exchange_links<4>(first, last, first);
  });
  for_parts(pool, parts, [&](int first, int end) {  // the sums near the ends
    const auto [inner_first, inner_end] = inner(first, end);
    if (inner_first >= inner_end) return sum(first, end);
    sum(first, inner_first);
    sum(inner_end, end);
  });
}

template <int Links, bool kMayShed, class Force>
void SolidSystem::advance_in_place(const Force& force, int first, int end, int lowest) {
  constexpr int D = Links / 2;
  // Raw pointers: through the vectors, every store to a vector's element would make the compiler
  // load that vector's data pointer again (it may not know the store leaves the vector alone).
  const double* __restrict masses = mass_.data();
  const double* __restrict momenta = momentum_.data();
  const int* __restrict neighbours = neighbours_.data();
  double* __restrict bases = base_.data();
  double* __restrict positions = positions_.data();
  constexpr std::uintptr_t kParticleBytes = Links * D * sizeof(double);  // a particle's link vectors
  const auto vectors_at = reinterpret_cast<std::uintptr_t>(incoming_.data());
  for (int p = first; p < end; ++p) {
    if constexpr (kMayShed)
      if (masses[p] == 0) continue;  // no link to send along, no motion, no force asked for
    // The vectors of the particle kVectorsAhead on, asked for now: as an integer, since that
    // particle may lie past the last, where a pointer may not point.
    const std::uintptr_t ahead = vectors_at + (static_cast<std::uintptr_t>(p) + kVectorsAhead) * kParticleBytes;
    for (std::uintptr_t line = 0; line < kParticleBytes; line += 64)
      __builtin_prefetch(reinterpret_cast<const void*>(ahead + line), 1);
    const Vec3 f = force(p);
    const double* psi = &momenta[static_cast<std::size_t>(p) * D];
    const double inv_m = 1.0 / masses[p];
    double* base = &bases[static_cast<std::size_t>(p) * D];
    double* r = &positions[static_cast<std::size_t>(p) * D];
    // x and y as a pair (particle_vectors.h), with the links below in pairs too: the solid stage
    // -0.6 to -0.8 ns a particle in 2D (in one process); in 3D no clear change.
    const XyPair base_xy = (load_xy(psi) + 0.5 * load_xy(f.data())) * inv_m;
    store_xy(base, base_xy);
    store_xy(r, load_xy(r) + base_xy);
    if constexpr (D == 3) {
      base[2] = (psi[2] + 0.5 * f[2]) * inv_m;
      r[2] += base[2];
    }
    // Unrolled, so that opp(k) is a constant in exchange_link: the 3D solid stage 16.4-17.0 ->
    // 14.4-15.6 ns a particle (best of 8 rounds, three runs each way); 2D unchanged.
#pragma GCC unroll 6
    for (int k = 0; k < Links; ++k) {
      const int q = neighbours[static_cast<std::size_t>(p) * Links + k];
      if (q >= lowest && q < p) exchange_link<Links>(p, k, q);  // a missing link's q is -1
    }
  }
}

template <int Links>
void SolidSystem::exchange_links(int first, int end, int below) {
  for (int p = first; p < end; ++p)
    for (int k = 0; k < Links; ++k)
      if (const int q = neighbours_[static_cast<std::size_t>(p) * Links + k]; q >= 0 && q < below)
        exchange_link<Links>(p, k, q);
}

template <int Links>
inline void SolidSystem::exchange_link(int p, int k, int q) {
  constexpr int D = Links / 2;
  double* __restrict at_q = &incoming_[(static_cast<std::size_t>(q) * Links + k) * D];  // f_k(q), from p
  double* __restrict at_p = &incoming_[(static_cast<std::size_t>(p) * Links + (k + D) % Links) * D];  // f_opp(k)(p)
  const double* base_p = &base_[static_cast<std::size_t>(p) * D];
  const double* base_q = &base_[static_cast<std::size_t>(q) * D];
  // x and y as a pair, z alone (at_q and at_p are two particles' vectors: they never overlap).
  const XyPair from_p = load_xy(at_q);
  const XyPair to_q = load_xy(base_p) - load_xy(at_p);
  const XyPair to_p = load_xy(base_q) - from_p;
  if constexpr (D == 3) {
    const double from_p_z = at_q[2];
    at_q[2] = base_p[2] - at_p[2];
    at_p[2] = base_q[2] - from_p_z;
  }
  store_xy(at_q, to_q);
  store_xy(at_p, to_p);
}

template <int Links>
void SolidSystem::update_momentum(int first, int end) {
  constexpr int D = Links / 2;
  for (int p = first; p < end; ++p) {
    const double* in = &incoming_[static_cast<std::size_t>(p) * Links * D];
    double psi[D] = {};
    for (int k = 0; k < Links; ++k)
      for (int a = 0; a < D; ++a) psi[a] += in[k * D + a];
    for (int a = 0; a < D; ++a) momentum_[static_cast<std::size_t>(p) * D + a] = psi[a];
  }
}

}  // namespace lbsolid::solid
