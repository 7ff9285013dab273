#pragma once
// Two-relaxation-time collision (Ginzburg 2005) with a second-order body force, on the shifted
// populations of bgk_collision.h. Each population pair (i, ibar), c_ibar = -c_i, splits into
//   f+_i = (f_i + f_ibar)/2 (even),  f-_i = (f_i - f_ibar)/2 (odd),  and likewise feq+-, S+-.
// The collision is
//   f_i* = f_i - w+ (f+_i - feq+_i) - w- (f-_i - feq-_i) + (1 - w+/2) S+_i + (1 - w-/2) S-_i,
// with feq the BGK equilibrium at Guo's velocity and S+- the even and odd parts of Guo's source
// (both in guo_forcing.h).
// w+ = omega sets the viscosity nu = c_s^2 (1/w+ - 1/2); w- follows from the magic parameter
//   Lambda = (1/w+ - 1/2)(1/w- - 1/2).
// Every steady solution depends on omega only through Lambda; Lambda = 3/16 puts half-way
// bounce-back walls exactly half-way for Poiseuille flow, whatever the viscosity (BGK, where
// w- = w+, has Lambda = (1/omega - 1/2)^2 and a viscosity-dependent wall slip).
// The momentum gained per step is exactly F: the odd relaxation adds w- F/2, the odd source
// (1 - w-/2) F. With w- = w+ this is BGK with Guo forcing.
#include "fluid/bgk_collision.h"
#include "fluid/fluid_config.h"

namespace lbsolid::fluid {

template <class L, class T>
struct TrtCollision {
  using Base = BgkCollision<L, T>;
  static constexpr int Q = L::Q;
  static constexpr T kInvCs2 = Base::kInvCs2;
  using Guo = GuoForcing<L, T>;

  struct Rates {
    T plus;   // even (symmetric) part: the viscosity
    T minus;  // odd (antisymmetric) part: from the magic parameter
  };

  static Rates rates(const FluidConfig& config) {
    const double lambda_plus = 1.0 / config.omega - 0.5;
    const double omega_minus = 1.0 / (0.5 + config.trt_magic / lambda_plus);
    return {static_cast<T>(config.omega), static_cast<T>(omega_minus)};
  }

  static LBSOLID_FORCE_INLINE void moments(const T* f, T rho0, T& rho, T (&j)[3]) {
    Base::moments(f, rho0, rho, j);
  }

  static inline T equilibrium(int i, T rho, T rho0, const T (&u)[3], T usq) {
    return Base::equilibrium(i, rho, rho0, u, usq);
  }

  template <bool kForce>
  static LBSOLID_FORCE_INLINE void collide(T* f, Rates rates, T rho0, const T (&force)[3]) {
    collide_pairs<kForce>(f, rates, rho0, force, std::make_integer_sequence<int, Q>{});
  }

 private:
  static constexpr auto kOpp = lattice::opposite_table<L>();

  template <bool kForce, int... I>
  static LBSOLID_FORCE_INLINE void collide_pairs(T* f, Rates rates, T rho0, const T (&force)[3],
                                                 std::integer_sequence<int, I...>) {
    const auto s = Base::template node_state<kForce>(f, rho0, force);
    const T rho = s.rho, isotropic = s.isotropic, u_dot_force = s.u_dot_force;
    const T(&u)[3] = s.u;
    const T even_scale = T(1) - T(0.5) * rates.plus;  // of S+
    const T odd_scale = T(1) - T(0.5) * rates.minus;  // of S-
    // Each pair is handled once, by its lower index; the rest population is its own pair and has
    // no odd part.
    auto relax = [&]<int K>(std::integral_constant<int, K>) __attribute__((always_inline)) {
      constexpr int B = kOpp[K];
      if constexpr (B == K) {
        T feq = T(L::w[K]) * isotropic;
        f[K] += rates.plus * (feq - f[K]);
        // c = 0: the source has no c.u, c.F and no odd part.
        if constexpr (kForce) f[K] += Guo::template even_source<K>(even_scale, T(0), T(0), u_dot_force);
      } else if constexpr (K < B) {
        const T cu = Base::template c_dot<K>(u);
        const T feq_even = T(L::w[K]) * (isotropic + T(0.5) * rho * cu * cu * kInvCs2 * kInvCs2);
        const T feq_odd = T(L::w[K]) * rho * cu * kInvCs2;
        T d_even = rates.plus * (feq_even - T(0.5) * (f[K] + f[B]));
        T d_odd = rates.minus * (feq_odd - T(0.5) * (f[K] - f[B]));
        if constexpr (kForce) {
          const T cf = Base::template c_dot<K>(force);
          d_even += Guo::template even_source<K>(even_scale, cu, cf, u_dot_force);
          d_odd += Guo::template odd_source<K>(odd_scale, cf);
        }
        f[K] += d_even + d_odd;
        f[B] += d_even - d_odd;
      }
    };
    (relax(std::integral_constant<int, I>{}), ...);
  }
};

}  // namespace lbsolid::fluid
