#pragma once
// Guo, Zheng & Shi (2002) second-order forcing: the one place its formulas live. The collision
// operators (bgk_collision.h, trt_collision.h, regularized_collision.h) call it for the body force
// F on a node, as waLBerla's collision models call their ForceModel. Guo's scheme
//   u   = (sum_i f_i c_i + F/2) / rho                            (equilibrium and physical velocity)
//   S_i = w_i ((c_i - u).F / c_s^2 + (c_i.u)(c_i.F) / c_s^4),    added as (1 - omega/2) S_i,
// gives the fluid exactly F of momentum per step and no mass, without the spurious O(u F) terms
// of a plain source. S has the moments sum S = 0, sum S c = F, sum S c c = u F + F u (fourth-order
// isotropic weights: D2Q9, D3Q19, and D2Q7 with c_s^2 = 1/4; tests/fluid/guo_forcing_test.cpp).
// Split by parity under c -> -c (TRT relaxes the two parts at different rates):
//   S+_i = w_i ((c_i.u)(c_i.F)/c_s^4 - u.F/c_s^2)  (even),    S-_i = w_i (c_i.F)/c_s^2  (odd).
//
// Each operator adds S in its own grouping of the same terms, and every grouping below is the one
// that operator has always evaluated: floating-point arithmetic is not associative, so regrouping
// would change the populations in the last bits. The caller passes cu = c_K.u and cf = c_K.F
// (it has c_K.u at hand for the equilibrium anyway) and a scale such as 1 - omega/2. Without a
// force the operators skip every call at compile time (their template <bool kForce>), so the
// unforced kernels do not contain this code at all.
#include "fluid/force_inline.h"

namespace lbsolid::fluid {

template <class L, class T>
struct GuoForcing {
  static constexpr T kInvCs2 = T(1.0 / L::cs2);

  // Component a of u: (j_a + F_a/2) / rho, with j = sum f c and inv_rho = 1/rho.
  static LBSOLID_FORCE_INLINE T velocity(T j, T force, T inv_rho) { return (j + T(0.5) * force) * inv_rho; }

  static LBSOLID_FORCE_INLINE T u_dot_force(const T (&u)[3], const T (&force)[3]) {
    return u[0] * force[0] + u[1] * force[1] + u[2] * force[2];
  }

  // scale * S_K, whole (BGK).
  template <int K>
  static LBSOLID_FORCE_INLINE T source(T scale, T cu, T cf, T u_dot_force) {
    return scale * T(L::w[K]) * ((cf - u_dot_force) * kInvCs2 + cu * cf * kInvCs2 * kInvCs2);
  }

  // scale * S+_K, the even part (TRT). The rest direction (c = 0) keeps only -w u.F/c_s^2, so it
  // ignores cu and cf.
  template <int K>
  static LBSOLID_FORCE_INLINE T even_source(T scale, T cu, T cf, T u_dot_force) {
    if constexpr (L::c[K][0] == 0.0 && L::c[K][1] == 0.0 && L::c[K][2] == 0.0)
      return -(scale * T(L::w[K]) * u_dot_force * kInvCs2);
    else
      return scale * T(L::w[K]) * (cu * cf * kInvCs2 - u_dot_force) * kInvCs2;
  }

  // scale * S-_K, the odd part (TRT).
  template <int K>
  static LBSOLID_FORCE_INLINE T odd_source(T scale, T cf) { return scale * T(L::w[K]) * cf * kInvCs2; }

  // The regularized operator adds S/2 before weighting, in two parts:
  //   S_i / 2 = w_i (half_source_isotropic(u.F) + half_source_directional(c_i.u, c_i.F)),
  // the first common to every direction (it joins the isotropic part of the equilibrium).
  static LBSOLID_FORCE_INLINE T half_source_isotropic(T u_dot_force) {
    return -(T(0.5) * u_dot_force * kInvCs2);
  }
  static LBSOLID_FORCE_INLINE T half_source_directional(T cu, T cf) {
    return T(0.5) * (cf * kInvCs2 + cu * cf * kInvCs2 * kInvCs2);
  }

  // Second moment of S/2, sum_i (S_i/2) c_iA c_iB = (u_A F_B + F_A u_B)/2: the force correction
  // that makes the regularized operator's Pi the physical non-equilibrium stress.
  template <int A, int B>
  static LBSOLID_FORCE_INLINE T half_source_second_moment(const T (&u)[3], const T (&force)[3]) {
    return T(0.5) * (u[A] * force[B] + force[A] * u[B]);
  }
};

}  // namespace lbsolid::fluid
