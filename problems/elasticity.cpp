/// Assembly of 2D linear elasticity from any method's gradient tables (001 Table 1 read as
/// B matrices): K = Σ_q w_q B^test_qᵀ D B^trial_q, tractions on the method's boundary rule.
#include <fmt/format.h>

#include "methods/core/errors.hpp"
#include "problems/problem.hpp"

namespace mfv {

namespace {

using RowSparse = Eigen::SparseMatrix<double, Eigen::RowMajor>;

/// Voigt strain operator of a table: rows 3q..3q+2 are (ε_xx, ε_yy, γ_xy) at point q in terms of
/// the interleaved unknowns (u_x, u_y) of each particle.
RowSparse strain_operator(const ShapeTable& t, int particles) {
  if (t.dim != 2 || t.grad.size() != static_cast<std::size_t>(t.entries()) * 2)
    throw std::logic_error("2D elasticity needs gradient tables of a 2D discretization");
  std::vector<Eigen::Triplet<double>> trip;
  trip.reserve(4 * t.entries());
  for (int q = 0; q < t.points(); ++q)
    for (int k = t.offsets[q]; k < t.offsets[q + 1]; ++k) {
      const int J = t.index[k];
      const double gx = t.grad[2 * k], gy = t.grad[2 * k + 1];
      trip.emplace_back(3 * q, 2 * J, gx);
      trip.emplace_back(3 * q + 1, 2 * J + 1, gy);
      trip.emplace_back(3 * q + 2, 2 * J, gy);
      trip.emplace_back(3 * q + 2, 2 * J + 1, gx);
    }
  RowSparse B(3 * t.points(), 2 * particles);
  B.setFromTriplets(trip.begin(), trip.end());
  return B;
}

}  // namespace

AssembledSystem assemble_elasticity(const Discretization& d, const ElasticityBVP& bvp) {
  const int n = d.particles.size();
  const int nq = d.trial_q.points();
  // W ⊗ D as a block diagonal, then K = B_testᵀ (W⊗D) B_trial: two sparse products instead of
  // a triplet per (point, particle pair).
  const Eigen::Matrix3d D = bvp.material.D();
  std::vector<Eigen::Triplet<double>> trip;
  trip.reserve(9 * static_cast<std::size_t>(nq));
  for (int q = 0; q < nq; ++q)
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b)
        if (D(a, b) != 0) trip.emplace_back(3 * q + a, 3 * q + b, d.quadrature.weights[q] * D(a, b));
  RowSparse WD(3 * nq, 3 * nq);
  WD.setFromTriplets(trip.begin(), trip.end());
  const RowSparse Btrial = strain_operator(d.trial_q, n);
  const RowSparse WDB = WD * Btrial;
  AssembledSystem s;
  s.components = 2;
  if (&d.test_q == &d.trial_q || (d.test_q.offsets == d.trial_q.offsets &&
                                  d.test_q.grad == d.trial_q.grad)) {
    s.K = Eigen::SparseMatrix<double>(Btrial.transpose()) * WDB;
  } else {
    const RowSparse Btest = strain_operator(d.test_q, n);
    s.K = Eigen::SparseMatrix<double>(Btest.transpose()) * WDB;
  }
  s.K.makeCompressed();
  s.f = Eigen::VectorXd::Zero(2 * n);
  for (const auto& [side, traction] : bvp.tractions) {
    const IntegrationRule b = d.boundary_rule(side);
    const ShapeTable t = d.test_on(b);
    const Eigen::MatrixXd tv = traction(b.points);
    for (int q = 0; q < b.size(); ++q)
      for (int k = t.offsets[q]; k < t.offsets[q + 1]; ++k)
        for (int c = 0; c < 2; ++c) s.f[2 * t.index[k] + c] += b.weights[q] * t.value[k] * tv(c, q);
  }
  // Essential conditions at the particles of each clamped side (their projections onto the
  // side): both components.
  std::vector<double> px, py, val;
  for (const auto& [side, disp] : bvp.displacements) {
    const IntegrationRule b = nodal_boundary_rule(d.domain, d.particles, side);
    // Particle-value methods fix the particle itself, at its own position.
    Eigen::MatrixXd at = b.points;
    if (d.particle_values)
      for (int q = 0; q < b.size(); ++q) at.col(q) = d.particles.x.col(b.cell[q]);
    const Eigen::MatrixXd g = disp(at);
    for (int q = 0; q < b.size(); ++q)
      for (int c = 0; c < 2; ++c) {
        // A corner particle on two clamped sides is constrained once (a repeated constraint
        // would make the multiplier system singular).
        bool repeated = false;
        for (std::size_t i = 0; i < val.size() && !repeated; ++i)
          repeated = s.constraint_particles[i] == b.cell[q] && s.constraint_components[i] == c &&
                     px[i] == at(0, q) && py[i] == at(1, q);
        if (repeated) continue;
        px.push_back(at(0, q));
        py.push_back(at(1, q));
        val.push_back(g(c, q));
        s.constraint_components.push_back(c);
        s.constraint_particles.push_back(b.cell[q]);
      }
  }
  s.constraint_points.resize(2, static_cast<Eigen::Index>(px.size()));
  for (std::size_t i = 0; i < px.size(); ++i) s.constraint_points.col(i) << px[i], py[i];
  s.constraint_values = Eigen::Map<Eigen::VectorXd>(val.data(), static_cast<Eigen::Index>(val.size()));
  return s;
}

}  // namespace mfv
