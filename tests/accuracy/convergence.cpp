#include "accuracy/convergence.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace lbsolid::accuracy {

namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
}

double pairwise_order(double n_coarse, double e_coarse, double n_fine, double e_fine) {
  if (!(e_coarse > 0) || !(e_fine > 0) || n_fine == n_coarse) return kNaN;
  return std::log(e_coarse / e_fine) / std::log(n_fine / n_coarse);
}

double fitted_order(const std::vector<double>& n, const std::vector<double>& e) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  int m = 0;
  for (std::size_t k = 0; k < n.size() && k < e.size(); ++k) {
    if (!(e[k] > 0) || !std::isfinite(e[k])) continue;
    const double x = std::log(n[k]), y = -std::log(e[k]);
    sx += x;
    sy += y;
    sxx += x * x;
    sxy += x * y;
    ++m;
  }
  const double denominator = m * sxx - sx * sx;
  if (m < 2 || denominator <= 0) return kNaN;
  return (m * sxy - sx * sy) / denominator;
}

double order_from_three(const double n[3], const double q[3]) {
  const double d12 = q[0] - q[1], d23 = q[1] - q[2];
  if (d12 == 0 || d23 == 0 || (d12 > 0) != (d23 > 0)) return kNaN;
  const double target = d12 / d23;
  // g(p) = (N1^-p - N2^-p) / (N2^-p - N3^-p) - target grows with p for N1 < N2 < N3.
  auto g = [&](double p) {
    const double a = std::pow(n[0], -p), b = std::pow(n[1], -p), c = std::pow(n[2], -p);
    return (a - b) / (b - c) - target;
  };
  double lo = 0.05, hi = 8.0;
  if (g(lo) > 0 || g(hi) < 0) return kNaN;
  for (int it = 0; it < 200; ++it) {
    const double mid = 0.5 * (lo + hi);
    (g(mid) < 0 ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

double richardson(double n_coarse, double q_coarse, double n_fine, double q_fine, double order) {
  const double r = std::pow(n_fine / n_coarse, order);
  return q_fine + (q_fine - q_coarse) / (r - 1.0);
}

bool dominated(const CostPoint& p, const std::vector<CostPoint>& points) {
  for (const CostPoint& o : points) {
    if (!std::isfinite(o.error)) continue;
    const bool no_worse = o.cost <= p.cost && o.error <= p.error;
    const bool better = o.cost < p.cost || o.error < p.error;
    if (no_worse && better) return true;
  }
  return false;
}

std::vector<std::size_t> pareto_front(const std::vector<CostPoint>& points) {
  std::vector<std::size_t> front;
  for (std::size_t k = 0; k < points.size(); ++k)
    if (std::isfinite(points[k].error) && !dominated(points[k], points)) front.push_back(k);
  std::sort(front.begin(), front.end(), [&](std::size_t a, std::size_t b) { return points[a].cost < points[b].cost; });
  return front;
}

}  // namespace lbsolid::accuracy
