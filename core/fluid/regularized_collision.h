#pragma once
// Regularized BGK (Latt & Chopard 2006) with Guo's forcing, on the shifted populations of
// bgk_collision.h. BGK with Guo's source S_i (guo_forcing.h) is
//   f_i* = feq_i + (1 - omega) g_i + S_i/2,   g_i = f_i - feq_i + S_i/2,
// (expand: f - omega (f - feq) + (1 - omega/2) S). The regularized operator keeps only the part
// of g a hydrodynamic state has, its second-order Hermite projection:
//   g_i -> w_i/(2 c_s^4) Q_i : Pi,   Q_i = c_i c_i - c_s^2 I,
//   Pi = sum_i g_i c_i c_i = sum_i f_i c_i c_i - (rho c_s^2 I + rho u u) + (u F + F u)/2,
// the last term being the second moment of S/2 (guo_forcing.h) and u Guo's velocity, as in BGK.
// The projection returns Pi exactly (sum_i w_i c_i c_i Q_i : Pi/(2 c_s^4) = Pi) on any lattice
// whose weights are isotropic to fourth order,
// sum w c_a c_b c_c c_d = c_s^4 (d_ab d_cd + d_ac d_bd + d_ad d_bc): D2Q9 and
// D3Q19 with c_s^2 = 1/3, and the hexagonal D2Q7 with c_s^2 = 1/4 (6 (1/12) (1 + 2/16) = 3/16).
// It carries no mass and no momentum, so mass is conserved and momentum grows by exactly F.
// The viscosity is BGK's, c_s^2 (1/omega - 1/2).
#include "fluid/bgk_collision.h"
#include "fluid/fluid_config.h"

namespace lbsolid::fluid {

template <class L, class T>
struct RegularizedCollision {
  using Base = BgkCollision<L, T>;
  using Rates = T;
  static constexpr int Q = L::Q;
  static constexpr int D = L::D;
  static constexpr T kInvCs2 = Base::kInvCs2;
  using Guo = GuoForcing<L, T>;

  static Rates rates(const FluidConfig& config) { return static_cast<T>(config.omega); }

  static LBSOLID_FORCE_INLINE void moments(const T* f, T rho0, T& rho, T (&j)[3]) {
    Base::moments(f, rho0, rho, j);
  }

  static inline T equilibrium(int i, T rho, T rho0, const T (&u)[3], T usq) {
    return Base::equilibrium(i, rho, rho0, u, usq);
  }

  template <bool kForce>
  static LBSOLID_FORCE_INLINE void collide(T* f, T omega, T rho0, const T (&force)[3]) {
    collide_directions<kForce>(f, omega, rho0, force, std::make_integer_sequence<int, Q>{});
  }

 private:
  // s + c_{I,A} c_{I,B} v, with products 0 and +-1 resolved at compile time (see add_c).
  template <int I, int A, int B>
  static inline T add_cc(T s, T v) {
    constexpr double cc = L::c[I][A] * L::c[I][B];
    if constexpr (cc == 0.0) return s;
    else if constexpr (cc == 1.0) return s + v;
    else if constexpr (cc == -1.0) return s - v;
    else return s + T(cc) * v;
  }

  template <int A, int B, int... I>
  static inline T second_moment(const T* f, std::integer_sequence<int, I...>) {
    T s = T(-0.0);
    ((s = add_cc<I, A, B>(s, f[I])), ...);
    return s;
  }

  // c_K c_K : M for a symmetric M given by its upper triangle, off-diagonal entries doubled.
  template <int K>
  static inline T contract(const T (&m)[3][3]) {
    T s = T(-0.0);
    s = add_cc<K, 0, 0>(s, m[0][0]);
    s = add_cc<K, 0, 1>(s, m[0][1]);
    s = add_cc<K, 1, 1>(s, m[1][1]);
    if constexpr (D == 3) {
      s = add_cc<K, 0, 2>(s, m[0][2]);
      s = add_cc<K, 1, 2>(s, m[1][2]);
      s = add_cc<K, 2, 2>(s, m[2][2]);
    }
    return s;
  }

  template <bool kForce, int... I>
  static LBSOLID_FORCE_INLINE void collide_directions(T* f, T omega, T rho0, const T (&force)[3],
                                                      std::integer_sequence<int, I...> dirs) {
    const auto s = Base::template node_state<kForce>(f, rho0, force);
    const T rho = s.rho, u_dot_force = s.u_dot_force;
    const T(&u)[3] = s.u;
    // Pi of the stored populations: sum f~ c c carries (rho - rho0) c_s^2 I of the equilibrium,
    // the shift w rho0 having been taken out. Scaled by (1 - omega)/(2 c_s^4), off-diagonals doubled.
    const T scale = (T(1) - omega) * T(0.5) * kInvCs2 * kInvCs2;
    const T pressure = (rho - rho0) * T(L::cs2);
    T m[3][3] = {};
    T trace = stress<0, 0, kForce>(f, rho, pressure, u, force, dirs);
    m[0][0] = scale * trace;
    m[0][1] = T(2) * scale * stress<0, 1, kForce>(f, rho, pressure, u, force, dirs);
    const T pyy = stress<1, 1, kForce>(f, rho, pressure, u, force, dirs);
    m[1][1] = scale * pyy;
    trace += pyy;
    if constexpr (D == 3) {
      m[0][2] = T(2) * scale * stress<0, 2, kForce>(f, rho, pressure, u, force, dirs);
      m[1][2] = T(2) * scale * stress<1, 2, kForce>(f, rho, pressure, u, force, dirs);
      const T pzz = stress<2, 2, kForce>(f, rho, pressure, u, force, dirs);
      m[2][2] = scale * pzz;
      trace += pzz;
    }
    // Terms common to every direction: equilibrium, -c_s^2 tr(Pi) of Q_i : Pi, and S/2's -u.F.
    T isotropic = s.isotropic - scale * T(L::cs2) * trace;
    if constexpr (kForce) isotropic += Guo::half_source_isotropic(u_dot_force);
    auto rebuild = [&]<int K>(std::integral_constant<int, K>) __attribute__((always_inline)) {
      const T cu = Base::template c_dot<K>(u);
      T g = isotropic + rho * cu * (kInvCs2 + T(0.5) * cu * kInvCs2 * kInvCs2) + contract<K>(m);
      if constexpr (kForce) g += Guo::half_source_directional(cu, Base::template c_dot<K>(force));
      f[K] = T(L::w[K]) * g;
    };
    (rebuild(std::integral_constant<int, I>{}), ...);
  }

  // Pi_AB of the stored populations (see collide_directions), force-corrected.
  template <int A, int B, bool kForce, int... I>
  static LBSOLID_FORCE_INLINE T stress(const T* f, T rho, T pressure, const T (&u)[3], const T (&force)[3],
                                       std::integer_sequence<int, I...> dirs) {
    T p = second_moment<A, B>(f, dirs) - rho * u[A] * u[B];
    if constexpr (A == B) p -= pressure;
    if constexpr (kForce) p += Guo::template half_source_second_moment<A, B>(u, force);
    return p;
  }
};

}  // namespace lbsolid::fluid
