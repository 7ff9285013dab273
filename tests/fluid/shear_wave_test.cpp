// Decaying shear wave u = A e^{-nu k^2 t} sin(k.r) t_hat: the viscosity fitted from the decay rate
// must match the BGK viscosity (1/omega - 1/2) c_s^2, to round-off the decay rate of a Fourier
// analysis of the linearised lattice (the BGK value plus its O(k^2) lattice terms), and on D2Q7 it
// must not depend on direction at leading order (the anisotropy falls as k^2).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <complex>
#include <cstdio>
#include <utility>
#include <vector>

#include "fluid/fluid_test_support.h"

namespace lbsolid::testing {
namespace {

constexpr double kPi = 3.14159265358979323846;

struct Wave {
  Vec3 k;       // wave vector
  Vec3 t_hat;   // unit velocity direction, perpendicular to k
};

// Projection of the velocity field on sin(k.r) t_hat: the wave's current amplitude.
template <class F>
double amplitude(const F& fluid, const Wave& wave) {
  const auto& c = fluid.config();
  double sum = 0;
  for (int z = 0; z < c.nz; ++z)
    for (int y = 0; y < c.ny; ++y)
      for (int x = 0; x < c.nx; ++x) {
        const Vec3 r = F::position(x, y, z);
        const Vec3 u = fluid.velocity(x, y, z);
        const double phase = wave.k[0] * r[0] + wave.k[1] * r[1] + wave.k[2] * r[2];
        sum += (u[0] * wave.t_hat[0] + u[1] * wave.t_hat[1] + u[2] * wave.t_hat[2]) * std::sin(phase);
      }
  return 2.0 * sum / static_cast<double>(fluid.cells());
}

// Runs the wave for about one decay time and returns the viscosity fitted from ln A(t).
template <class L>
double fitted_viscosity(FluidConfig c, const Wave& wave) {
  FluidLattice<L, double> fluid(c);
  const double a0 = 1e-3;
  fluid.initialize([](int, int, int) { return 1.0; },
                   [&](int x, int y, int z) {
                     const Vec3 r = FluidLattice<L, double>::position(x, y, z);
                     const double s = a0 * std::sin(wave.k[0] * r[0] + wave.k[1] * r[1] + wave.k[2] * r[2]);
                     return Vec3{s * wave.t_hat[0], s * wave.t_hat[1], s * wave.t_hat[2]};
                   });
  const double k2 = wave.k[0] * wave.k[0] + wave.k[1] * wave.k[1] + wave.k[2] * wave.k[2];
  const long decay_steps = static_cast<long>(1.0 / (bgk_viscosity<L>(c.omega) * k2));
  // Skip the first steps: the equilibrium start lacks the non-equilibrium part of a shear flow.
  const long skip = 50;
  const long samples = 20;
  fluid.run(skip);
  std::vector<double> t, log_a;
  for (long s = 0; s <= samples; ++s) {
    t.push_back(static_cast<double>(fluid.step_count()));
    log_a.push_back(std::log(amplitude(fluid, wave)));
    fluid.run(decay_steps / samples + 1);
  }
  return -fit_line(t, log_a).slope / k2;
}

// The viscosity a wave of vector k really decays with on the lattice, from a Fourier analysis of
// the linearised BGK step (independent of the fluid code: no streaming, boundaries or kernels).
// Around rest, f_i = w_i + g_i, one step maps the mode g_i e^{i k.r} to
//   g_i <- e^{-i k.c_i} [g_i - omega (g_i - w_i (rho + c_i.j / c_s^2))],  rho = sum g, j = sum g c,
// a Q x Q matrix A(k). Its shear eigenvalue lambda (the one nearest 1 - nu k^2, found by inverse
// iteration from the shear wave's own populations) decays the amplitude by |lambda| per step:
// nu(k) = -ln|lambda| / k^2, which is nu = (1/omega - 1/2) c_s^2 plus the lattice's O(k^2) terms.
template <class L>
double linear_theory_viscosity(double omega, const Wave& wave) {
  using C = std::complex<double>;
  constexpr int Q = L::Q;
  std::array<std::array<C, Q>, Q> a{};
  for (int i = 0; i < Q; ++i) {
    double k_dot_c = 0;
    for (int d = 0; d < 3; ++d) k_dot_c += wave.k[d] * L::c[i][d];
    const C shift = std::exp(C(0, -k_dot_c));
    for (int m = 0; m < Q; ++m) {
      double c_dot_c = 0;
      for (int d = 0; d < 3; ++d) c_dot_c += L::c[i][d] * L::c[m][d];
      const double equilibrium = L::w[i] * (1 + c_dot_c / L::cs2);  // d feq_i / d g_m
      a[i][m] = shift * ((i == m ? 1 - omega : 0.0) + omega * equilibrium);
    }
  }
  const double k2 = wave.k[0] * wave.k[0] + wave.k[1] * wave.k[1] + wave.k[2] * wave.k[2];
  const C mu = 1 - bgk_viscosity<L>(omega) * k2 * 0.999;  // near, not on, the eigenvalue
  std::array<C, Q> x;
  for (int i = 0; i < Q; ++i) {
    double c_dot_t = 0;
    for (int d = 0; d < 3; ++d) c_dot_t += L::c[i][d] * wave.t_hat[d];
    x[i] = L::w[i] * c_dot_t / L::cs2;
  }
  for (int iteration = 0; iteration < 30; ++iteration) {
    // Solve (A - mu I) y = x by Gaussian elimination with partial pivoting, then normalise.
    auto m = a;
    auto y = x;
    for (int i = 0; i < Q; ++i) m[i][i] -= mu;
    for (int col = 0; col < Q; ++col) {
      int pivot = col;
      for (int r = col + 1; r < Q; ++r)
        if (std::abs(m[r][col]) > std::abs(m[pivot][col])) pivot = r;
      std::swap(m[col], m[pivot]);
      std::swap(y[col], y[pivot]);
      for (int r = col + 1; r < Q; ++r) {
        const C factor = m[r][col] / m[col][col];
        for (int j = col; j < Q; ++j) m[r][j] -= factor * m[col][j];
        y[r] -= factor * y[col];
      }
    }
    for (int r = Q - 1; r >= 0; --r) {
      for (int j = r + 1; j < Q; ++j) y[r] -= m[r][j] * y[j];
      y[r] /= m[r][r];
    }
    double norm = 0;
    for (const C& v : y) norm += std::norm(v);
    for (int i = 0; i < Q; ++i) x[i] = y[i] / std::sqrt(norm);
  }
  C numerator = 0, denominator = 0;  // Rayleigh quotient x^H A x / x^H x
  for (int i = 0; i < Q; ++i) {
    C ax = 0;
    for (int m = 0; m < Q; ++m) ax += a[i][m] * x[m];
    numerator += std::conj(x[i]) * ax;
    denominator += std::conj(x[i]) * x[i];
  }
  return -std::log(std::abs(numerator / denominator)) / k2;
}

template <class L>
class ShearWaveTest : public ::testing::Test {};
using Lattices = ::testing::Types<D2Q9, D2Q7, D3Q19>;
TYPED_TEST_SUITE(ShearWaveTest, Lattices);

// The periodic box both decay-rate tests run: a wavelength of 64 along x, u along y.
template <class L>
FluidConfig wave_box() {
  FluidConfig c;
  c.nx = 64;
  c.ny = 2;  // even, so D2Q7 can be periodic in y
  c.nz = L::D == 3 ? 2 : 1;
  return c;
}
const Wave kWaveAlongX{{2 * kPi / 64, 0, 0}, {0, 1, 0}};

TYPED_TEST(ShearWaveTest, ViscosityFromDecayRateMatchesBgk) {
  using L = TypeParam;
  FluidConfig c = wave_box<L>();
  const Wave& wave = kWaveAlongX;
  for (double omega : {0.6, 1.0, 1.6}) {
    c.omega = omega;
    const double ratio = fitted_viscosity<L>(c, wave) / bgk_viscosity<L>(omega);
    report(std::string(L::name) + " shear-wave viscosity error, omega " + std::to_string(omega),
           std::abs(ratio - 1), 0.01);
    EXPECT_NEAR(ratio, 1.0, 0.01) << "omega " << omega;
  }
}

// The same runs against the linearised lattice's own decay rate (linear_theory_viscosity): what is
// left is the nonlinear part of the run. On D2Q9 and D3Q19 the equilibrium's quadratic terms of a
// shear wave (u perpendicular to k) do not act back on it: the fit's round-off remains, measured
// at most 6.8e-13 (gcc -O2, -O3 -march=native, clang with sanitizers), bound 5e-12. On D2Q7
// they do: the difference scales as the amplitude squared (3.9e-7, 3.9e-9, 3.9e-11 at A = 1e-2, 1e-3, 1e-4, omega 0.6), so the bound is 1e-2 A^2 = 1e-8
// (measured at most 3.9e-9). A viscosity off by 1e-6 of itself in the fluid code would fail both.
TYPED_TEST(ShearWaveTest, DecayRateMatchesTheLinearisedLattice) {
  using L = TypeParam;
  FluidConfig c = wave_box<L>();
  const Wave& wave = kWaveAlongX;
  for (double omega : {0.6, 1.0, 1.6}) {
    c.omega = omega;
    const double theory = linear_theory_viscosity<L>(omega, wave);
    const double error = std::abs(fitted_viscosity<L>(c, wave) / theory - 1);
    std::printf("[ figure   ] %s omega %.1f: linear theory nu / BGK nu - 1 = %+.3e\n", L::name, omega,
                theory / bgk_viscosity<L>(omega) - 1);
    const double bound = L::hexagonal ? 1e-8 : 5e-12;
    report(std::string(L::name) + " fitted vs linearised-lattice viscosity, omega " + std::to_string(omega), error,
           bound);
    EXPECT_LT(error, bound) << "omega " << omega;
  }
}

// D2Q7 isotropy. The hexagonal lattice maps 0, 60, 120 degrees onto each other, and 30, 90, 150
// degrees onto each other, but not one set onto the other, so the test compares a wave along x
// (0 degrees) with one along y (90) and one at 30 degrees. Each needs a box it is periodic on: node
// (x, y) sits at (x + (y mod 2)/2, y sqrt(3)/2), so
//   0 degrees, wavelength n:              n x 2 nodes;
//   90 degrees, wavelength m sqrt(3)/2:   2 x m nodes (m even);
//   30 degrees, wavelength m sqrt(3)/2:   m x 2m nodes (the phase is 2 pi (x + (y + y mod 2)/2) / m).
// n = 26, m = 30 (25.981) and n = 52, m = 60 (51.962) give the same |k| to 7.7e-4.
// D2Q7's 4th-order velocity tensor is isotropic, so the viscosity is isotropic at leading order;
// its 6th-order tensor is not, and the decay rate nu k^2 (1 + eps(theta) k^2 + ...) carries an
// anisotropic part at relative order k^2. So eps = nu_fit / nu - 1 must fall as k^2 (at least) in
// every direction, and the anisotropy Delta = eps(0) - eps(90) must fall exactly as k^2: by 4 when
// the wavelength doubles. A lattice whose leading-order viscosity depended on direction would give
// a Delta that does not fall at all. (A Fourier-space linear analysis of BGK D2Q7, done apart from
// this code, gives the same eps to 5e-9: e.g. eps(0) = 5.534138e-3, eps(90) = -4.818535e-3 at
// wavelength 48, omega 0.6.)
TEST(HexagonalIsotropyTest, ViscosityIsIsotropicAtLeadingOrderAnisotropyFallsAsKSquared) {
  const double s = D2Q7::half_sqrt3;
  auto at_0 = [](int n, double omega) {
    FluidConfig c;
    c.nx = n;
    c.ny = 2;
    c.omega = omega;
    const double k = 2 * kPi / n;
    return fitted_viscosity<D2Q7>(c, {{k, 0, 0}, {0, 1, 0}}) / bgk_viscosity<D2Q7>(omega) - 1;
  };
  auto at_90 = [s](int m, double omega) {
    FluidConfig c;
    c.nx = 2;
    c.ny = m;
    c.omega = omega;
    const double k = 2 * kPi / (m * s);
    return fitted_viscosity<D2Q7>(c, {{0, k, 0}, {-1, 0, 0}}) / bgk_viscosity<D2Q7>(omega) - 1;
  };
  auto at_30 = [s](int m, double omega) {
    FluidConfig c;
    c.nx = m;
    c.ny = 2 * m;
    c.omega = omega;
    const double k = 2 * kPi / (m * s);
    return fitted_viscosity<D2Q7>(c, {{s * k, 0.5 * k, 0}, {-0.5, s, 0}}) / bgk_viscosity<D2Q7>(omega) - 1;
  };
  // Delta / k^2 at wavelength 52, measured (Release, -O3 -march=native): 0.6036 (omega 0.6),
  // 0.04172 (omega 1, where it tends to 1/24), -0.07564 (omega 1.6); the same at wavelength 104 to
  // 0.7%. A discretisation effect: bound 1.5x.
  const std::vector<std::pair<double, double>> anisotropy_per_k2 = {{0.6, 0.6036}, {1.0, 0.04172}, {1.6, 0.07564}};
  const double k2 = std::pow(2 * kPi / 52, 2);
  for (const auto& [omega, measured] : anisotropy_per_k2) {
    const std::string at = ", omega " + std::to_string(omega);
    const double e0_26 = at_0(26, omega), e0_52 = at_0(52, omega);
    const double e90_26 = at_90(30, omega), e90_52 = at_90(60, omega);
    const double e30_26 = at_30(30, omega);
    std::printf("[ figure   ] D2Q7 nu_fit/nu - 1 at wavelength 26 / 52%s: 0 deg %+.4e / %+.4e, 90 deg %+.4e / %+.4e\n",
                at.c_str(), e0_26, e0_52, e90_26, e90_52);
    // 30 and 90 degrees map onto each other (a 60 degree turn), but the 30 degree wave crosses the
    // shifted odd rows at every phase: equal to round-off, measured up to 7e-14; bound 1e-12 (14x).
    report("D2Q7 30 vs 90 degrees, eps difference" + at, std::abs(e30_26 - e90_26), 1e-12);
    EXPECT_LT(std::abs(e30_26 - e90_26), 1e-12) << "omega " << omega;
    // Leading order: eps falls at least as k^2 in both directions (measured 4.00-4.12x per halving
    // of k; 16x at 90 degrees and omega 1, where the k^2 term vanishes); bound: 3.6x (10% below 4).
    report("D2Q7 0 degree eps fall, wavelength 26 -> 52" + at, e0_26 / e0_52, 3.6);
    report("D2Q7 90 degree eps fall, wavelength 26 -> 52" + at, e90_26 / e90_52, 3.6);
    EXPECT_GT(e0_26 / e0_52, 3.6) << "omega " << omega;
    EXPECT_GT(e90_26 / e90_52, 3.6) << "omega " << omega;
    // The anisotropy is second order: Delta(26) / Delta(52) = 4 up to the next order, O(k^2);
    // measured 4.120, 4.016, 4.005 at omega 0.6, 1, 1.6 (4.030, 4.004, 4.001 from 52 to 104).
    // Bound |ratio - 4| < 0.25, 2x the largest measured departure.
    const double delta_26 = e0_26 - e90_26, delta_52 = e0_52 - e90_52;
    report("D2Q7 anisotropy fall, wavelength 26 -> 52 (minus 4)" + at, std::abs(delta_26 / delta_52 - 4), 0.25);
    EXPECT_NEAR(delta_26 / delta_52, 4.0, 0.25) << "omega " << omega;
    report("D2Q7 |0 - 90 degree eps| / k^2 at wavelength 52" + at, std::abs(delta_52) / k2, 1.5 * measured);
    EXPECT_LT(std::abs(delta_52) / k2, 1.5 * measured) << "omega " << omega;
  }
}

}  // namespace
}  // namespace lbsolid::testing
