#include "observe/fits.h"

#include <cmath>

namespace lbsolid::observe {

namespace {

double mean(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x;
  return v.empty() ? 0 : s / static_cast<double>(v.size());
}

double total_sum_of_squares(const std::vector<double>& y) {
  const double m = mean(y);
  double s = 0;
  for (double v : y) s += (v - m) * (v - m);
  return s;
}

// For a fixed rate the best U is linear least squares; returns the residual and sets U.
double residual_at_rate(const std::vector<double>& t, const std::vector<double>& u, double rate, double& terminal) {
  double gg = 0, gu = 0;
  for (std::size_t k = 0; k < t.size(); ++k) {
    const double g = -std::expm1(-rate * t[k]);
    gg += g * g;
    gu += g * u[k];
  }
  terminal = gg > 0 ? gu / gg : 0;
  double r = 0;
  for (std::size_t k = 0; k < t.size(); ++k) {
    const double e = u[k] - terminal * -std::expm1(-rate * t[k]);
    r += e * e;
  }
  return r;
}

}  // namespace

LineFit fit_line(const std::vector<double>& x, const std::vector<double>& y) {
  LineFit fit;
  const double mx = mean(x), my = mean(y);
  double sxx = 0, sxy = 0;
  for (std::size_t k = 0; k < x.size(); ++k) {
    sxx += (x[k] - mx) * (x[k] - mx);
    sxy += (x[k] - mx) * (y[k] - my);
  }
  fit.slope = sxx > 0 ? sxy / sxx : 0;
  fit.intercept = my - fit.slope * mx;
  for (std::size_t k = 0; k < x.size(); ++k) {
    const double e = y[k] - (fit.intercept + fit.slope * x[k]);
    fit.chi2 += e * e;
  }
  const double tss = total_sum_of_squares(y);
  fit.r2 = tss > 0 ? 1.0 - fit.chi2 / tss : 1.0;
  return fit;
}

ExponentialFit fit_saturating_exponential(const std::vector<double>& t, const std::vector<double>& u,
                                          double rate_min, double rate_max) {
  // Golden-section search on log(rate): the residual is smooth and, for data of this shape, unimodal.
  const double phi = 0.5 * (std::sqrt(5.0) - 1.0);
  double lo = std::log(rate_min), hi = std::log(rate_max);
  double terminal = 0;
  for (int iteration = 0; iteration < 200 && hi - lo > 1e-12; ++iteration) {
    const double a = hi - phi * (hi - lo), b = lo + phi * (hi - lo);
    if (residual_at_rate(t, u, std::exp(a), terminal) < residual_at_rate(t, u, std::exp(b), terminal))
      hi = b;
    else
      lo = a;
  }
  ExponentialFit fit;
  fit.rate = std::exp(0.5 * (lo + hi));
  const double residual = residual_at_rate(t, u, fit.rate, fit.terminal);
  const double tss = total_sum_of_squares(u);
  fit.r2 = tss > 0 ? 1.0 - residual / tss : 1.0;
  return fit;
}

}  // namespace lbsolid::observe
