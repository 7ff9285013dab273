#pragma once
// BGK collision (MODEL.md eq. 1) with Guo's second-order forcing, on populations stored as the
// deviation from rest, f~_i = f_i - w_i rho0, which keeps float storage accurate (the rest part
// is ~10^2 times the flow part and would otherwise eat the mantissa).
#include "lattice/lattice_traits.h"

namespace lbsolid::fluid {

template <class L, class T>
struct BgkCollision {
  static constexpr int Q = L::Q;

  // Density and momentum sum_i f_i c_i of shifted populations.
  static inline void moments(const T* f, T rho0, T& rho, T (&j)[3]) {
    T drho = 0;
    j[0] = j[1] = j[2] = 0;
#pragma GCC unroll 32
    for (int i = 0; i < Q; ++i) {
      drho += f[i];
      j[0] += T(L::c[i][0]) * f[i];
      j[1] += T(L::c[i][1]) * f[i];
      if constexpr (L::D == 3) j[2] += T(L::c[i][2]) * f[i];
    }
    rho = rho0 + drho;
  }

  // Shifted equilibrium w_i (rho - rho0) + w_i rho (c.u/cs2 + (c.u)^2/(2 cs4) - u.u/(2 cs2)).
  static inline T equilibrium(int i, T rho, T rho0, const T (&u)[3], T usq) {
    constexpr T inv_cs2 = T(1.0 / L::cs2);
    const T cu = T(L::c[i][0]) * u[0] + T(L::c[i][1]) * u[1] + T(L::c[i][2]) * u[2];
    return T(L::w[i]) *
           ((rho - rho0) + rho * (cu * inv_cs2 + T(0.5) * cu * cu * inv_cs2 * inv_cs2 -
                                  T(0.5) * usq * inv_cs2));
  }

  // One collision in place. With kForce, F is the force on this node and the velocity in the
  // equilibrium is (sum f c + F/2) / rho (Guo et al. 2002), so the momentum gained is exactly F.
  template <bool kForce>
  static inline void collide(T* f, T omega, T rho0, const T (&force)[3]) {
    constexpr T inv_cs2 = T(1.0 / L::cs2);
    T rho, j[3];
    moments(f, rho0, rho, j);
    const T inv_rho = T(1) / rho;
    T u[3];
    for (int a = 0; a < 3; ++a) u[a] = kForce ? (j[a] + T(0.5) * force[a]) * inv_rho : j[a] * inv_rho;
    if constexpr (L::D == 2) u[2] = 0;
    const T usq = u[0] * u[0] + u[1] * u[1] + u[2] * u[2];
#pragma GCC unroll 32
    for (int i = 0; i < Q; ++i) {
      f[i] += omega * (equilibrium(i, rho, rho0, u, usq) - f[i]);
      if constexpr (kForce) {
        const T cu = T(L::c[i][0]) * u[0] + T(L::c[i][1]) * u[1] + T(L::c[i][2]) * u[2];
        T source = 0;
#pragma GCC unroll 3
        for (int a = 0; a < 3; ++a) {
          source += ((T(L::c[i][a]) - u[a]) * inv_cs2 + cu * T(L::c[i][a]) * inv_cs2 * inv_cs2) *
                    force[a];
        }
        f[i] += (T(1) - T(0.5) * omega) * T(L::w[i]) * source;
      }
    }
  }
};

}  // namespace lbsolid::fluid
