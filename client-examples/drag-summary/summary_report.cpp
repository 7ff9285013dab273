#include "summary_report.h"

#include <cstdarg>
#include <cstdio>

namespace lbsolid::drag {
namespace {

constexpr std::size_t kTableRows = 40;
constexpr double kStokesRange = 5.0;  // Re below which the test checks c_d ~ 1/Re

std::string format(const char* pattern, ...) {
  char text[512];
  va_list args;
  va_start(args, pattern);
  std::vsnprintf(text, sizeof text, pattern, args);
  va_end(args);
  return text;
}

}  // namespace

std::string summary_text(const DragSetup& s, const DragResult& r) {
  std::string out;
  out += "Drag on a disk (Chopard & Marconi 2002, Fig. 5)\n";
  out += format("scenario     %s\n", s.scenario_name.empty() ? "(unnamed)" : s.scenario_name.c_str());
  out += format("lattice      %s, omega %g, rho0 %g, nu = c_s^2 (1/omega - 1/2) = %g (c_s^2 = %g)\n", s.lattice.c_str(),
                s.omega, s.rho0, s.viscosity(), s.cs2);
  out += format("disk         '%s': radius %g, %ld particles, D = (2R+1) spacing = %g\n", s.body.c_str(), s.radius,
                s.particles, s.diameter());
  out += format("force        load %g x %ld particles = F %g\n\n", s.load, s.particles, s.force());

  out += "u(t), the disk's mean velocity along x";
  out += r.origin_added ? " (t = 0 from the scenario's initial velocity)\n" : "\n";
  out += format("  %10s  %14s\n", "t [steps]", "u_x");
  const std::size_t n = r.t.size();
  const std::size_t stride = n > kTableRows ? (n + kTableRows - 1) / kTableRows : 1;
  for (std::size_t k = 0; k < n; k += stride) out += format("  %10.0f  %14.6e\n", r.t[k], r.u[k]);
  if ((n - 1) % stride != 0) out += format("  %10.0f  %14.6e\n", r.t[n - 1], r.u[n - 1]);

  out += "\nfit u(t) = u_inf (1 - exp(-a t))\n";
  out += format("  terminal velocity u_inf     %.6e\n", r.fit.terminal);
  out += format("  rate a                      %.6e per step (the run covers %.1f times 1/a)\n", r.fit.rate,
                r.relaxation_times);
  out += format("  R^2                         %.6f\n", r.fit.r2);
  out += "\nresult\n";
  out += format("  Re = u_inf D / nu           %.6g\n", r.reynolds);
  out += format("  c_d = F / (rho0 u_inf^2 D)  %.6g\n", r.drag_coefficient);
  out += format("  c_d Re                      %.6g\n", r.drag_coefficient * r.reynolds);

  out += "\nexpectation (paper, Fig. 5)\n";
  out += "  At low Re the drag follows Stokes' law for a cylinder: c_d is proportional to 1/Re, so c_d Re\n"
         "  is one constant for every load (set by the geometry and the walls). Runs with other loads\n"
         "  should give the same c_d Re; tests/physics/drag_fig5_test.cpp checks a log-log slope of\n"
         "  -1 +- 0.15 for Re below 5, and R^2 > 0.99 for the fit.\n";
  out += format("  this run: Re %.3g is %s the Stokes range (Re < %g); fit R^2 %.4f %s 0.99\n", r.reynolds,
                r.reynolds < kStokesRange ? "inside" : "OUTSIDE", kStokesRange, r.fit.r2, r.fit.r2 > 0.99 ? ">" : "<=");
  if (s.dimension == 3)
    out += "  note: these are the paper's 2D definitions (drag per unit length of a cylinder); for a\n"
           "  ball the usual c_d divides by the projected area and Stokes' law reads c_d = 24 / Re\n";
  if (r.relaxation_times < 8)
    out += format("  warning: the run covers only %.1f relaxation times (the test asks for 8): u_inf is "
                  "extrapolated\n",
                  r.relaxation_times);
  return out;
}

}  // namespace lbsolid::drag
