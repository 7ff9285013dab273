#pragma once
// Least-squares fits used to read results off a run: a straight line (velocity gradients,
// log-log slopes) and the saturating exponential u(t) = U (1 - exp(-a t)) of the paper's drag
// experiment (Fig. 5). Each reports its coefficient of determination R^2.
#include <vector>

namespace lbsolid::observe {

struct LineFit {
  double slope = 0, intercept = 0, r2 = 0;
  double chi2 = 0;  // sum of squared residuals
};
LineFit fit_line(const std::vector<double>& x, const std::vector<double>& y);

struct ExponentialFit {
  double terminal = 0;  // U = F/a, the terminal value
  double rate = 0;      // a
  double r2 = 0;
};
// Fits u(t) = U (1 - exp(-a t)) to samples (t_k, u_k); a is searched in [rate_min, rate_max].
ExponentialFit fit_saturating_exponential(const std::vector<double>& t, const std::vector<double>& u,
                                          double rate_min = 1e-7, double rate_max = 10.0);

}  // namespace lbsolid::observe
