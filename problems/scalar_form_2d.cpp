/// Galerkin (or Petrov–Galerkin, or collocation) assembly of −∇·(k ∇u) = f in 2D with u = g
/// on every side of the box, from any method's shape tables (the manufactured scalar problem).
#include <set>
#include <utility>
#include <vector>

#include "problems/problem.hpp"

namespace mfv {

AssembledSystem assemble_scalar_2d(const Discretization& d, double k,
                                   const std::function<double(double, double)>& source,
                                   const std::function<double(double, double)>& dirichlet) {
  const int n = d.particles.size();
  const ShapeTable& tr = d.trial_q;
  const ShapeTable& te = d.test_q;
  const int nq = tr.points();
  // K = Σ_q w_q k ∇N^test_I(x_q)·∇N^trial_J(x_q): per point, every test × trial pair.
  std::vector<Eigen::Triplet<double>> trip;
  Eigen::VectorXd f = Eigen::VectorXd::Zero(n);
  for (int q = 0; q < nq; ++q) {
    const double w = d.quadrature.weights[q];
    const double fx = source(d.quadrature.points(0, q), d.quadrature.points(1, q));
    for (int a = te.offsets[q]; a < te.offsets[q + 1]; ++a) {
      const int I = te.index[a];
      f[I] += w * te.value[a] * fx;
      const double hx = te.grad[2 * a], hy = te.grad[2 * a + 1];
      for (int b = tr.offsets[q]; b < tr.offsets[q + 1]; ++b)
        trip.emplace_back(I, tr.index[b],
                          w * k * (hx * tr.grad[2 * b] + hy * tr.grad[2 * b + 1]));
    }
  }
  AssembledSystem s;
  s.components = 1;
  s.K.resize(n, n);
  s.K.setFromTriplets(trip.begin(), trip.end());
  s.K.makeCompressed();
  s.f = std::move(f);
  // Essential conditions at the particles of each side (a corner once).
  std::vector<double> px, py, val;
  std::set<int> held;
  for (int side = 0; side < 4; ++side) {
    const IntegrationRule b = nodal_boundary_rule(d.domain, d.particles, side);
    for (int q = 0; q < b.size(); ++q) {
      const int I = b.cell[q];
      if (!held.insert(I).second) continue;
      const double x = d.particle_values ? d.particles.x(0, I) : b.points(0, q);
      const double y = d.particle_values ? d.particles.x(1, I) : b.points(1, q);
      px.push_back(x);
      py.push_back(y);
      val.push_back(dirichlet(x, y));
      s.constraint_particles.push_back(I);
    }
  }
  s.constraint_points.resize(2, static_cast<Eigen::Index>(px.size()));
  for (std::size_t i = 0; i < px.size(); ++i) s.constraint_points.col(i) << px[i], py[i];
  s.constraint_values = Eigen::Map<Eigen::VectorXd>(val.data(), static_cast<Eigen::Index>(val.size()));
  return s;
}

}  // namespace mfv
