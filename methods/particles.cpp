#include "methods/particles.hpp"

#include <algorithm>
#include <random>

#include <fmt/format.h>

#include "methods/core/errors.hpp"
#include "methods/core/resources.hpp"

namespace mfv {

Domain Domain::interval(double a, double b) {
  Domain d;
  d.dim = 1;
  d.lower = Eigen::VectorXd::Constant(1, a);
  d.upper = Eigen::VectorXd::Constant(1, b);
  return d;
}

Domain Domain::rectangle(double x0, double y0, double x1, double y1) {
  if (!(x1 > x0) || !(y1 > y0))
    throw InputError(fmt::format("a rectangle needs x1 > x0 and y1 > y0, got [{}, {}] × [{}, {}]",
                                 x0, x1, y0, y1));
  Domain d;
  d.dim = 2;
  d.lower = Eigen::Vector2d(x0, y0);
  d.upper = Eigen::Vector2d(x1, y1);
  return d;
}

double Domain::measure() const { return (upper - lower).prod(); }

Eigen::VectorXd voronoi_volumes_1d(const Eigen::VectorXd& x, double a, double b) {
  const Eigen::Index n = x.size();
  Eigen::VectorXd v(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double left = i == 0 ? a : 0.5 * (x[i - 1] + x[i]);
    const double right = i == n - 1 ? b : 0.5 * (x[i] + x[i + 1]);
    v[i] = right - left;
  }
  return v;
}

ParticleSet uniform_line(const Domain& domain, int n, double perturbation, std::uint64_t seed) {
  if (domain.dim != 1) throw InputError("uniform_line needs a 1D domain");
  if (n < 2)
    throw InputError(fmt::format("--nodes must be at least 2 on a line, got {}", n));
  if (!(perturbation >= 0 && perturbation < 0.5))
    throw InputError(fmt::format(
        "perturbation must be in [0, 0.5) of the spacing so particles keep their order, got {}",
        perturbation));
  check_case_memory(n, 1, fmt::format("a line of {} particles", n));
  const double a = domain.lower[0], b = domain.upper[0];
  const double dx = (b - a) / (n - 1);
  Eigen::VectorXd x(n);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-perturbation, perturbation);
  for (int i = 0; i < n; ++i) {
    x[i] = a + i * dx;
    if (i > 0 && i < n - 1 && perturbation > 0) x[i] += u(rng) * dx;
  }
  ParticleSet p;
  p.dim = 1;
  p.x = x.transpose();
  p.volume = voronoi_volumes_1d(x, a, b);
  p.dilation = Eigen::VectorXd::Constant(n, dx);
  p.spacing = dx;
  p.lattice = Eigen::Vector2i(n, 1);
  p.sides.assign(n, 0u);
  p.sides.front() |= Side::left;
  p.sides.back() |= Side::right;
  return p;
}

}  // namespace mfv
