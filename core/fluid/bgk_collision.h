#pragma once
// BGK collision (MODEL.md eq. 1) with Guo's second-order forcing (guo_forcing.h), on populations
// stored as the deviation from rest, f~_i = f_i - w_i rho0, which keeps float storage accurate
// (the rest part is ~10^2 times the flow part and would otherwise eat the mantissa).
//
// The directions are unrolled at compile time so that products with a zero velocity component
// vanish from the code: a compiler may not drop `x * 0` itself (NaN * 0 is NaN), and on D3Q19
// those products were most of the arithmetic.
#include <utility>

#include "fluid/fluid_config.h"
#include "fluid/force_inline.h"
#include "fluid/guo_forcing.h"
#include "lattice/lattice_traits.h"

namespace lbsolid::fluid {

template <class L, class T>
struct BgkCollision {
  static constexpr int Q = L::Q;
  static constexpr T kInvCs2 = T(1.0 / L::cs2);
  using Guo = GuoForcing<L, T>;
  // What the kernels hand to collide() for every cell (TRT needs two rates; BGK has one).
  using Rates = T;
  static Rates rates(const FluidConfig& config) { return static_cast<T>(config.omega); }

  // s + c_{I,A} v (lattice::add_c). Sums start from -0.0, the exact identity of floating-point
  // addition, so the first term needs no special case.
  template <int I, int A>
  static inline T add_c(T s, T v) {
    return lattice::add_c<L, I, A>(s, v);
  }

  template <int I>
  static inline T c_dot(const T (&v)[3]) {
    return add_c<I, 2>(add_c<I, 1>(add_c<I, 0>(T(-0.0), v[0]), v[1]), v[2]);
  }

  template <int... I>
  static inline T zeroth_moment(const T* f, std::integer_sequence<int, I...>) {
    T s = T(-0.0);
    ((s += f[I]), ...);
    return s;
  }

  template <int A, int... I>
  static inline T first_moment(const T* f, std::integer_sequence<int, I...>) {
    T s = T(-0.0);
    ((s = add_c<I, A>(s, f[I])), ...);
    return s;
  }

  // The sum of f_I over the directions with c_{I,0} == C.
  template <int C, int... I>
  static inline T sum_where_cx(const T* f, std::integer_sequence<int, I...>) {
    T s = T(-0.0);
    ((s = L::c[I][0] == C ? s + f[I] : s), ...);
    return s;
  }

  static constexpr bool unit_cx() {
    for (int i = 0; i < Q; ++i)
      if (L::c[i][0] != 0 && L::c[i][0] != 1 && L::c[i][0] != -1) return false;
    return true;
  }

  // Density and momentum sum_i f_i c_i of shifted populations. Where every c_x is -1, 0 or 1
  // (D2Q9, D3Q19), the density reuses the two sums that make j_x: 8 additions fewer on D3Q19.
  static LBSOLID_FORCE_INLINE void moments(const T* f, T rho0, T& rho, T (&j)[3]) {
    constexpr auto dirs = std::make_integer_sequence<int, Q>{};
    if constexpr (unit_cx()) {
      const T plus = sum_where_cx<1>(f, dirs), minus = sum_where_cx<-1>(f, dirs);
      rho = rho0 + ((sum_where_cx<0>(f, dirs) + plus) + minus);
      j[0] = plus - minus;
    } else {
      rho = rho0 + zeroth_moment(f, dirs);
      j[0] = first_moment<0>(f, dirs);
    }
    j[1] = first_moment<1>(f, dirs);
    j[2] = L::D == 3 ? first_moment<2>(f, dirs) : T(0);
  }

  // What every collision operator needs of a node before it relaxes: density, the velocity (with
  // a force, Guo's (sum f c + F/2) / rho), |u|^2, the equilibrium terms common to every
  // direction, and u.F.
  struct NodeState {
    T rho;
    T u[3];
    T usq;
    T isotropic;  // (rho - rho0) - rho |u|^2 / (2 c_s^2)
    T u_dot_force;
    T rho_linear;     // rho / c_s^2: the equilibrium's term linear in c.u is w rho_linear c.u
    T rho_quadratic;  // rho / (2 c_s^4): its quadratic term w rho_quadratic (c.u)^2
  };

  template <bool kForce>
  static LBSOLID_FORCE_INLINE NodeState node_state(const T* f, T rho0, const T (&force)[3]) {
    NodeState s;
    T j[3];
    moments(f, rho0, s.rho, j);
    const T inv_rho = T(1) / s.rho;
    for (int a = 0; a < 3; ++a) s.u[a] = kForce ? Guo::velocity(j[a], force[a], inv_rho) : j[a] * inv_rho;
    if constexpr (L::D == 2) s.u[2] = 0;
    s.usq = s.u[0] * s.u[0] + s.u[1] * s.u[1] + s.u[2] * s.u[2];
    s.isotropic = (s.rho - rho0) - T(0.5) * s.rho * s.usq * kInvCs2;
    s.u_dot_force = kForce ? Guo::u_dot_force(s.u, force) : T(0);
    s.rho_linear = s.rho * kInvCs2;
    s.rho_quadratic = s.rho * T(0.5 * (1.0 / L::cs2) * (1.0 / L::cs2));
    return s;
  }

  // Shifted equilibrium w_i (rho - rho0) + w_i rho (c.u/cs2 + (c.u)^2/(2 cs4) - u.u/(2 cs2)).
  static inline T equilibrium(int i, T rho, T rho0, const T (&u)[3], T usq) {
    const T cu = T(L::c[i][0]) * u[0] + T(L::c[i][1]) * u[1] + T(L::c[i][2]) * u[2];
    return T(L::w[i]) * ((rho - rho0) + rho * (cu * kInvCs2 + T(0.5) * cu * cu * kInvCs2 * kInvCs2 -
                                                T(0.5) * usq * kInvCs2));
  }

  // Population K after the collision, from its value f_K before and the node's state: relaxed
  // towards equilibrium and, with kForce, given Guo's source for the force F on this node
  // (guo_forcing.h): summed over K the momentum gained is exactly F.
  template <bool kForce, int K>
  static LBSOLID_FORCE_INLINE T relaxed(T f_k, const NodeState& s, T omega, const T (&force)[3]) {
    // The equilibrium's even and odd parts in c: c_J = -c_K for the opposite direction J, so
    // both directions of a pair take them from the pair's first c.u (the compiler shares them):
    // about half the equilibrium's operations, which bound the D3Q19 kernels (docs/performance.md).
    // The relaxation is taken as (1 - omega) f + omega feq with omega folded into the node's
    // terms once a weight (shared by the compiler like the pair's terms): three operations a
    // direction fewer than f + omega (feq - f).
    constexpr int J = lattice::opposite_table<L>()[K];
    constexpr int P = K < J ? K : J;  // the pair's first direction: c_K = +-c_P
    const T cp = c_dot<P>(s.u);
    const T w = T(L::w[K]);
    const T even = w * (omega * s.isotropic) + (w * (omega * s.rho_quadratic)) * (cp * cp);
    const T odd = (w * (omega * s.rho_linear)) * cp;
    const T cu = K == P ? cp : -cp;
    f_k = (T(1) - omega) * f_k + (K == P ? even + odd : even - odd);
    if constexpr (kForce) f_k += Guo::template source<K>(T(1) - T(0.5) * omega, cu, c_dot<K>(force), s.u_dot_force);
    return f_k;
  }

  // One collision in place.
  template <bool kForce>
  static LBSOLID_FORCE_INLINE void collide(T* f, T omega, T rho0, const T (&force)[3]) {
    const NodeState s = node_state<kForce>(f, rho0, force);
    [&]<int... K>(std::integer_sequence<int, K...>) __attribute__((always_inline)) {
      ((f[K] = relaxed<kForce, K>(f[K], s, omega, force)), ...);
    }(std::make_integer_sequence<int, Q>{});
  }
};

}  // namespace lbsolid::fluid
