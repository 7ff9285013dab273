#pragma once
// Convergence arithmetic for the accuracy report: observed orders from runs at successive
// resolutions, Richardson extrapolation, and the Pareto front of error against cost.
// Resolutions enter as a count of cells across the problem (N): the grid spacing is h ~ 1/N.
#include <cstddef>
#include <vector>

namespace lbsolid::accuracy {

// Order p from two runs, e ~ N^-p: log(e_coarse / e_fine) / log(n_fine / n_coarse).
// NaN when either error is not positive (an exact result has no order).
double pairwise_order(double n_coarse, double e_coarse, double n_fine, double e_fine);

// Order p from a least-squares line through (log N, -log e) over all runs with a positive error;
// NaN with fewer than two such runs. Less sensitive to one noisy run than pairwise orders.
double fitted_order(const std::vector<double>& n, const std::vector<double>& e);

// Order p of a quantity q(N) = q* + C N^-p from three runs (N1 < N2 < N3), without knowing q*:
// solves (q1 - q2) / (q2 - q3) = (N1^-p - N2^-p) / (N2^-p - N3^-p) by bisection on [0.05, 8].
// NaN when the differences change sign (not in the asymptotic range) or no root is bracketed.
double order_from_three(const double n[3], const double q[3]);

// Richardson extrapolation of q from two runs, assuming q(N) = q* + C N^-p.
double richardson(double n_coarse, double q_coarse, double n_fine, double q_fine, double order);

struct CostPoint {
  double cost = 0;   // wall seconds
  double error = 0;  // relative error
};

// Indices of the points no other point dominates (another is no worse in both cost and error
// and strictly better in one), sorted by cost. Points with a non-finite error are never on it.
std::vector<std::size_t> pareto_front(const std::vector<CostPoint>& points);

// True when some point of `points` dominates `p`.
bool dominated(const CostPoint& p, const std::vector<CostPoint>& points);

}  // namespace lbsolid::accuracy
