// GuoForcing (core/fluid/guo_forcing.h) against the identities Guo's source must satisfy, for
// random u and F on D2Q9, D2Q7 (c_s^2 = 1/4) and D3Q19: sum S = 0, sum S c = F,
// sum S c c = u F + F u; S+ + S- = S with S+ even and S- odd under c -> -c; the regularized
// operator's two pieces of S/2 add up to S/2, and its stress correction is the second moment of
// S/2; the velocity is shifted by exactly half the force.
//
// Round-off bound. Each S_i is at most 8 roundings (each <= eps/2 relative) from the exact
// w_i (...) of the double-valued lattice constants, relative to R_i, the sum of the absolute
// values of its terms; the constants themselves (w, c, 1/c_s^2, D2Q7's sqrt(3)/2) are rounded to
// double, which moves the identities by a few eps relative; a product with a component of c is one
// more rounding (none for 0, +-1, +-1/2); a sum over Q directions adds at most Q - 1 roundings of
// at most sum_i R_i. So every identity holds to (Q + 16) eps sum_i R_i, about twice that
// forward estimate. A wrong factor anywhere is an O(1) relative error, 10^13 times larger.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <utility>

#include "fluid/guo_forcing.h"
#include "lattice/d2q7.h"
#include "lattice/d2q9.h"
#include "lattice/d3q19.h"
#include "lattice/lattice_traits.h"

namespace lbsolid::testing {
namespace {

using lattice::D2Q7;
using lattice::D2Q9;
using lattice::D3Q19;

constexpr double kEps = std::numeric_limits<double>::epsilon();
constexpr int kTrials = 200;

// What the policy gives for one (u, F), direction by direction, with the scale 1.
template <class L>
struct Sources {
  double u[3] = {}, force[3] = {};
  double s[L::Q], even[L::Q], odd[L::Q], half[L::Q];  // S, S+, S-, and S/2 from its two pieces
  double magnitude = 0;                                // sum_i R_i (see the bound above)
};

template <class L>
Sources<L> random_sources(std::mt19937_64& rng) {
  using G = fluid::GuoForcing<L, double>;
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  Sources<L> r;
  for (int a = 0; a < L::D; ++a) {
    r.u[a] = 0.2 * unit(rng);
    r.force[a] = unit(rng);
  }
  const double uf = G::u_dot_force(r.u, r.force);
  [&]<int... K>(std::integer_sequence<int, K...>) {
    auto one = [&]<int I>(std::integral_constant<int, I>) {
      double cu = 0, cf = 0;  // computed here, not by the operators' code
      for (int a = 0; a < 3; ++a) {
        cu += L::c[I][a] * r.u[a];
        cf += L::c[I][a] * r.force[a];
      }
      r.s[I] = G::template source<I>(1.0, cu, cf, uf);
      r.even[I] = G::template even_source<I>(1.0, cu, cf, uf);
      r.odd[I] = G::template odd_source<I>(1.0, cf);
      r.half[I] = L::w[I] * (G::half_source_isotropic(uf) + G::half_source_directional(cu, cf));
      r.magnitude +=
          L::w[I] * ((std::abs(cf) + std::abs(uf)) / L::cs2 + std::abs(cu * cf) / (L::cs2 * L::cs2));
    };
    (one(std::integral_constant<int, K>{}), ...);
  }(std::make_integer_sequence<int, L::Q>{});
  return r;
}

template <class L>
double bound(const Sources<L>& r) {
  return (L::Q + 16) * kEps * r.magnitude;
}

template <class L>
class GuoForcingTest : public ::testing::Test {};
using Lattices = ::testing::Types<D2Q9, D2Q7, D3Q19>;
TYPED_TEST_SUITE(GuoForcingTest, Lattices);

TYPED_TEST(GuoForcingTest, SourceAddsNoMassMomentumFAndStressUFPlusFU) {
  using L = TypeParam;
  std::mt19937_64 rng(20020101);
  for (int trial = 0; trial < kTrials; ++trial) {
    const auto r = random_sources<L>(rng);
    const double tol = bound(r);
    double mass = 0, momentum[3] = {}, stress[3][3] = {};
    for (int i = 0; i < L::Q; ++i) {
      mass += r.s[i];
      for (int a = 0; a < 3; ++a) {
        momentum[a] += r.s[i] * L::c[i][a];
        for (int b = 0; b < 3; ++b) stress[a][b] += r.s[i] * L::c[i][a] * L::c[i][b];
      }
    }
    ASSERT_NEAR(mass, 0.0, tol) << "trial " << trial;
    for (int a = 0; a < 3; ++a) {
      ASSERT_NEAR(momentum[a], r.force[a], tol) << "trial " << trial << " axis " << a;
      for (int b = 0; b < 3; ++b)
        ASSERT_NEAR(stress[a][b], r.u[a] * r.force[b] + r.force[a] * r.u[b], tol)
            << "trial " << trial << " component " << a << b;
    }
  }
}

// Parity holds exactly, not only to round-off: c_opp(i) = -c_i exactly on every lattice, so c.u and
// c.F change sign exactly, and each formula is even or odd operation by operation (rounding to
// nearest is symmetric under negation).
TYPED_TEST(GuoForcingTest, ParityPartsAddUpToSourceAndAreEvenAndOdd) {
  using L = TypeParam;
  constexpr auto opposite = lattice::opposite_table<L>();
  std::mt19937_64 rng(20050101);
  for (int trial = 0; trial < kTrials; ++trial) {
    const auto r = random_sources<L>(rng);
    const double tol = bound(r);
    for (int i = 0; i < L::Q; ++i) {
      ASSERT_NEAR(r.even[i] + r.odd[i], r.s[i], tol) << "trial " << trial << " direction " << i;
      ASSERT_EQ(r.even[opposite[i]], r.even[i]) << "trial " << trial << " direction " << i;
      ASSERT_EQ(r.odd[opposite[i]], -r.odd[i]) << "trial " << trial << " direction " << i;
    }
  }
}

TYPED_TEST(GuoForcingTest, RegularizedHalfSourceMatchesSourceAndItsSecondMoment) {
  using L = TypeParam;
  using G = fluid::GuoForcing<L, double>;
  std::mt19937_64 rng(20060101);
  for (int trial = 0; trial < kTrials; ++trial) {
    const auto r = random_sources<L>(rng);
    const double tol = bound(r);
    double half_stress[3][3] = {};
    for (int i = 0; i < L::Q; ++i) {
      ASSERT_NEAR(r.half[i], 0.5 * r.s[i], tol) << "trial " << trial << " direction " << i;
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) half_stress[a][b] += 0.5 * r.s[i] * L::c[i][a] * L::c[i][b];
    }
    double want[3][3];  // the policy's stress correction, all nine components
    [&]<int... AB>(std::integer_sequence<int, AB...>) {
      ((want[AB / 3][AB % 3] = G::template half_source_second_moment<AB / 3, AB % 3>(r.u, r.force)), ...);
    }(std::make_integer_sequence<int, 9>{});
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) {
        const double uf = r.u[a] * r.force[b], fu = r.force[a] * r.u[b];
        ASSERT_NEAR(want[a][b], 0.5 * (uf + fu), 2 * kEps * (std::abs(uf) + std::abs(fu)))
            << "trial " << trial << " component " << a << b;
        ASSERT_NEAR(half_stress[a][b], want[a][b], tol) << "trial " << trial << " component " << a << b;
      }
  }
}

// rho u = sum f c + F/2: three roundings (F/2 is exact), each <= eps/2 of |j| + |F|.
TEST(GuoForcing, VelocityIsShiftedByHalfTheForce) {
  using G = fluid::GuoForcing<D2Q9, double>;
  std::mt19937_64 rng(20020102);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (int trial = 0; trial < kTrials; ++trial) {
    const double rho = 1.0 + 0.1 * unit(rng), j = 0.1 * unit(rng), force = unit(rng);
    const double u = G::velocity(j, force, 1.0 / rho);
    EXPECT_NEAR(rho * u, j + 0.5 * force, 4 * kEps * (std::abs(j) + std::abs(force))) << "trial " << trial;
  }
}

}  // namespace
}  // namespace lbsolid::testing
